// OSPRay's C++ wrapper must compile as the C++ its users write (OSPRay's is C++11): this
// file is built as C++11, 14, 17 and 20 with warnings as errors and linked against the
// shim, never run. It constructs every wrapper class every way OSPRay's allow, calls every
// member, sets a parameter of every type OSPTypeFor knows and checks each type's size
// against the OSPDataType it is declared as. It uses none of sciray's extensions (see
// docs/c-api.md): it is an OSPRay program.

#include <ospray/ospray_cpp.h>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>
#define OSPRAY_GLM_DEFINITIONS  // this translation unit defines the glm traits' constants
#include <ospray/ospray_cpp/ext/glm.h>

namespace {

// Application types taught to the wrapper with the documented macro.
struct Box3f {
  float lower[3], upper[3];
};
struct Size2 {
  std::uint64_t x, y;
};
struct Size3 {
  std::uint64_t x, y, z;
};

}  // namespace

namespace ospray {
OSPTYPEFOR_SPECIALIZATION(Box3f, OSP_BOX3F)
OSPTYPEFOR_SPECIALIZATION(Size2, OSP_VEC2UL)
OSPTYPEFOR_SPECIALIZATION(Size3, OSP_VEC3UL)
}  // namespace ospray

namespace {

using namespace ospray;

// The bytes an OSPDataType's value takes (0: not a fixed-size value type).
constexpr std::size_t bytesOf(OSPDataType type) {
  return type == OSP_BOOL || type == OSP_CHAR || type == OSP_UCHAR                                 ? 1
         : type == OSP_SHORT || type == OSP_USHORT                                                 ? 2
         : type == OSP_INT || type == OSP_UINT || type == OSP_FLOAT                                ? 4
         : type == OSP_LONG || type == OSP_ULONG || type == OSP_DOUBLE                             ? 8
         : type == OSP_VEC2F || type == OSP_VEC2I || type == OSP_VEC2UI                            ? 8
         : type == OSP_VEC3F || type == OSP_VEC3I || type == OSP_VEC3UI                            ? 12
         : type == OSP_VEC4F || type == OSP_VEC4I || type == OSP_VEC4UI                            ? 16
         : type == OSP_VEC2UL || type == OSP_LINEAR2F                                              ? 16
         : type == OSP_VEC3UL || type == OSP_BOX3F || type == OSP_AFFINE2F                         ? 24
         : type == OSP_LINEAR3F                                                                    ? 36
         : type == OSP_AFFINE3F                                                                    ? 48
         : type == OSP_VOID_PTR || type == OSP_STRING || (type >= OSP_OBJECT && type <= OSP_WORLD) ? sizeof(void*)
                                                                                                   : 0;
}

template <typename T>
constexpr bool declaredWithItsSize() {
  return OSPTypeFor<T>::value != OSP_UNKNOWN && bytesOf(OSPTypeFor<T>::value) == sizeof(T);
}

#define CHECK_TYPE(T, osp_type)                                               \
  static_assert(OSPTypeFor<T>::value == (osp_type), #T " is not " #osp_type); \
  static_assert(declaredWithItsSize<T>(), #T " and " #osp_type " differ in size")

// Every OSPTypeFor OSPRay declares, and glm's.
CHECK_TYPE(void*, OSP_VOID_PTR);
CHECK_TYPE(char*, OSP_STRING);
CHECK_TYPE(const char*, OSP_STRING);
static_assert(OSPTypeFor<const char[]>::value == OSP_STRING, "const char[] is not OSP_STRING");
CHECK_TYPE(bool, OSP_BOOL);
CHECK_TYPE(char, OSP_CHAR);
CHECK_TYPE(unsigned char, OSP_UCHAR);
CHECK_TYPE(short, OSP_SHORT);
CHECK_TYPE(unsigned short, OSP_USHORT);
CHECK_TYPE(int, OSP_INT);
CHECK_TYPE(unsigned int, OSP_UINT);
CHECK_TYPE(long, OSP_LONG);
CHECK_TYPE(unsigned long, OSP_ULONG);
CHECK_TYPE(long long, OSP_LONG);
CHECK_TYPE(unsigned long long, OSP_ULONG);
CHECK_TYPE(float, OSP_FLOAT);
CHECK_TYPE(double, OSP_DOUBLE);
CHECK_TYPE(OSPObject, OSP_OBJECT);
CHECK_TYPE(OSPCamera, OSP_CAMERA);
CHECK_TYPE(OSPData, OSP_DATA);
CHECK_TYPE(OSPFrameBuffer, OSP_FRAMEBUFFER);
CHECK_TYPE(OSPFuture, OSP_FUTURE);
CHECK_TYPE(OSPGeometricModel, OSP_GEOMETRIC_MODEL);
CHECK_TYPE(OSPGeometry, OSP_GEOMETRY);
CHECK_TYPE(OSPGroup, OSP_GROUP);
CHECK_TYPE(OSPImageOperation, OSP_IMAGE_OPERATION);
CHECK_TYPE(OSPInstance, OSP_INSTANCE);
CHECK_TYPE(OSPLight, OSP_LIGHT);
CHECK_TYPE(OSPMaterial, OSP_MATERIAL);
CHECK_TYPE(OSPRenderer, OSP_RENDERER);
CHECK_TYPE(OSPTexture, OSP_TEXTURE);
CHECK_TYPE(OSPTransferFunction, OSP_TRANSFER_FUNCTION);
CHECK_TYPE(OSPVolume, OSP_VOLUME);
CHECK_TYPE(OSPVolumetricModel, OSP_VOLUMETRIC_MODEL);
CHECK_TYPE(OSPWorld, OSP_WORLD);
CHECK_TYPE(cpp::Camera, OSP_CAMERA);
CHECK_TYPE(cpp::CopiedData, OSP_DATA);
CHECK_TYPE(cpp::SharedData, OSP_DATA);
CHECK_TYPE(cpp::MovedData, OSP_DATA);
CHECK_TYPE(cpp::FrameBuffer, OSP_FRAMEBUFFER);
CHECK_TYPE(cpp::Future, OSP_FUTURE);
CHECK_TYPE(cpp::GeometricModel, OSP_GEOMETRIC_MODEL);
CHECK_TYPE(cpp::Geometry, OSP_GEOMETRY);
CHECK_TYPE(cpp::Group, OSP_GROUP);
CHECK_TYPE(cpp::ImageOperation, OSP_IMAGE_OPERATION);
CHECK_TYPE(cpp::Instance, OSP_INSTANCE);
CHECK_TYPE(cpp::Light, OSP_LIGHT);
CHECK_TYPE(cpp::Material, OSP_MATERIAL);
CHECK_TYPE(cpp::Renderer, OSP_RENDERER);
CHECK_TYPE(cpp::Texture, OSP_TEXTURE);
CHECK_TYPE(cpp::TransferFunction, OSP_TRANSFER_FUNCTION);
CHECK_TYPE(cpp::Volume, OSP_VOLUME);
CHECK_TYPE(cpp::VolumetricModel, OSP_VOLUMETRIC_MODEL);
CHECK_TYPE(cpp::World, OSP_WORLD);
static_assert(OSPTypeFor<cpp::Device>::value == OSP_DEVICE, "cpp::Device is not OSP_DEVICE");
CHECK_TYPE(glm::vec2, OSP_VEC2F);
CHECK_TYPE(glm::vec3, OSP_VEC3F);
CHECK_TYPE(glm::vec4, OSP_VEC4F);
CHECK_TYPE(glm::ivec2, OSP_VEC2I);
CHECK_TYPE(glm::ivec3, OSP_VEC3I);
CHECK_TYPE(glm::ivec4, OSP_VEC4I);
CHECK_TYPE(glm::uvec2, OSP_VEC2UI);
CHECK_TYPE(glm::uvec3, OSP_VEC3UI);
CHECK_TYPE(glm::uvec4, OSP_VEC4UI);
CHECK_TYPE(glm::mat2x2, OSP_LINEAR2F);
CHECK_TYPE(glm::mat3x3, OSP_LINEAR3F);
CHECK_TYPE(glm::mat3x2, OSP_AFFINE2F);
CHECK_TYPE(glm::mat4x3, OSP_AFFINE3F);
CHECK_TYPE(Box3f, OSP_BOX3F);
CHECK_TYPE(Size2, OSP_VEC2UL);
CHECK_TYPE(Size3, OSP_VEC3UL);

// Enums are declared as whichever of OSP_UCHAR and OSP_UINT has their size.
#define CHECK_ENUM(E) static_assert(declaredWithItsSize<E>(), #E " is declared with a type of another size")
CHECK_ENUM(OSPLogLevel);
CHECK_ENUM(OSPDeviceProperty);
CHECK_ENUM(OSPDataType);
CHECK_ENUM(OSPTextureFormat);
CHECK_ENUM(OSPTextureFilter);
CHECK_ENUM(OSPTextureWrapMode);
CHECK_ENUM(OSPError);
CHECK_ENUM(OSPFrameBufferFormat);
CHECK_ENUM(OSPFrameBufferChannel);
CHECK_ENUM(OSPSyncEvent);
CHECK_ENUM(OSPUnstructuredCellType);
CHECK_ENUM(OSPStereoMode);
CHECK_ENUM(OSPShutterType);
CHECK_ENUM(OSPCurveType);
CHECK_ENUM(OSPCurveBasis);
CHECK_ENUM(OSPSubdivisionMode);
CHECK_ENUM(OSPAMRMethod);
CHECK_ENUM(OSPVolumeFilter);
CHECK_ENUM(OSPPixelFilterType);
CHECK_ENUM(OSPIntensityQuantity);
CHECK_ENUM(OSPSphereType);

static_assert(std::is_same<OSPVecElementOf<OSP_VEC3F>::type, float>::value, "vec3f is of floats");
static_assert(std::is_same<OSPVecElementOf<OSP_VEC2UL>::type, std::uint64_t>::value, "vec2ul is of uint64");
static_assert(std::is_same<OSPVecElementOf<OSP_BOX3I>::type, std::int32_t>::value, "box3i is of int32");
static_assert(OSPDimensionalityOf<OSP_VEC3UL>::value == 3 && OSPDimensionalityOf<OSP_INT>::value == 1 &&
                  OSPDimensionalityOf<OSP_BOX2F>::value == 2,
              "dimensionalities");
static_assert(cpp::Camera::type == OSP_CAMERA && cpp::ManagedObject<>::type == OSP_OBJECT, "wrapper types");

// The same parameter of every declared type, on any object wrapper (or the device).
template <typename Object>
void setEveryType(const Object& object, const cpp::Geometry& geometry, const cpp::CopiedData& data) {
  object.setParam("p", static_cast<void*>(nullptr));
  char text[] = "text";
  object.setParam("p", static_cast<char*>(text));
  object.setParam("p", static_cast<const char*>(text));
  object.setParam("p", "literal");
  object.setParam("p", std::string("string"));
  object.setParam("p", true);
  object.setParam("p", 'c');
  object.setParam("p", static_cast<unsigned char>(1));
  object.setParam("p", static_cast<short>(1));
  object.setParam("p", static_cast<unsigned short>(1));
  object.setParam("p", 1);
  object.setParam("p", 1u);
  object.setParam("p", 1l);
  object.setParam("p", 1ul);
  object.setParam("p", 1ll);
  object.setParam("p", 1ull);
  object.setParam("p", 1.f);
  object.setParam("p", 1.0);
  object.setParam("p", OSP_FLOAT, &text);
  object.setParam("p", geometry.handle());
  object.setParam("p", static_cast<OSPObject>(geometry.handle()));
  object.setParam("p", geometry);
  object.setParam("p", data);
  object.setParam("p", data.handle());
  object.setParam("p", OSP_LOG_WARNING);
  object.setParam("p", OSP_DEVICE_VERSION);
  object.setParam("p", OSP_VEC3F);
  object.setParam("p", OSP_TEXTURE_RGBA8);
  object.setParam("p", OSP_TEXTURE_FILTER_NEAREST);
  object.setParam("p", OSP_TEXTURE_WRAP_REPEAT);
  object.setParam("p", OSP_NO_ERROR);
  object.setParam("p", OSP_FB_SRGBA);
  object.setParam("p", OSP_FB_COLOR);
  object.setParam("p", OSP_FRAME_FINISHED);
  object.setParam("p", OSP_TETRAHEDRON);
  object.setParam("p", OSP_STEREO_SIDE_BY_SIDE);
  object.setParam("p", OSP_SHUTTER_GLOBAL);
  object.setParam("p", OSP_ROUND);
  object.setParam("p", OSP_BEZIER);
  object.setParam("p", OSP_SUBDIVISION_PIN_CORNERS);
  object.setParam("p", OSP_AMR_FINEST);
  object.setParam("p", OSP_VOLUME_FILTER_CUBIC);
  object.setParam("p", OSP_PIXELFILTER_GAUSS);
  object.setParam("p", OSP_INTENSITY_QUANTITY_POWER);
  object.setParam("p", OSP_DISC);
  object.setParam("p", glm::vec2(1.f));
  object.setParam("p", glm::vec3(1.f));
  object.setParam("p", glm::vec4(1.f));
  object.setParam("p", glm::ivec2(1));
  object.setParam("p", glm::ivec3(1));
  object.setParam("p", glm::ivec4(1));
  object.setParam("p", glm::uvec2(1u));
  object.setParam("p", glm::uvec3(1u));
  object.setParam("p", glm::uvec4(1u));
  object.setParam("p", glm::mat2x2(1.f));
  object.setParam("p", glm::mat3x3(1.f));
  object.setParam("p", glm::mat3x2(1.f));
  object.setParam("p", glm::mat4x3(1.f));
  object.setParam("p", Box3f());
  object.removeParam("p");
  object.commit();
}

// Each class: made by type (or new), adopting a handle, empty; copied, moved, assigned.
template <typename Wrapper, typename... Args>
void lifetime(Args&&... args) {
  Wrapper made(std::forward<Args>(args)...);
  Wrapper adopted(made.handle());
  ospRetain(adopted.handle());  // `adopted` owns a reference of its own
  Wrapper copy(made);
  Wrapper moved(std::move(copy));
  copy = moved;
  moved = std::move(copy);
  const bool valid = made;
  (void)valid;
}

}  // namespace

// Referenced from nowhere: it exists to be compiled, and linked against the shim.
void everyWrapper();
void everyWrapper() {
  cpp::Device device("cpu");
  cpp::Device adopted(ospNewDevice("cpu"));
  cpp::Device copied(device);
  cpp::Device moved(std::move(copied));
  copied = moved;
  moved = std::move(copied);
  device.setErrorCallback([](void*, OSPError, const char*) {});
  device.setStatusCallback([](void*, const char*) {});
  device.commit();
  device.setCurrent();
  cpp::Device current = cpp::Device::current();
  (void)current.handle();

  lifetime<cpp::Camera>("perspective");
  lifetime<cpp::Geometry>("mesh");
  lifetime<cpp::ImageOperation>("tonemapper");
  lifetime<cpp::Light>("ambient");
  lifetime<cpp::Material>("obj");
  lifetime<cpp::Renderer>("scivis");
  lifetime<cpp::Texture>("texture2d");
  lifetime<cpp::TransferFunction>("piecewiseLinear");
  lifetime<cpp::Volume>("structuredRegular");
  lifetime<cpp::Group>();
  lifetime<cpp::World>();
  lifetime<cpp::FrameBuffer>(4, 4);
  lifetime<cpp::FrameBuffer>(4, 4, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_DEPTH | OSP_FB_ACCUM);
  lifetime<cpp::Future>(static_cast<OSPFuture>(nullptr));
  lifetime<cpp::Camera>();
  lifetime<cpp::ManagedObject<>>(static_cast<OSPObject>(nullptr));

  cpp::Geometry geometry("mesh");
  cpp::GeometricModel model(geometry);
  cpp::GeometricModel modelOfHandle(geometry.handle());
  cpp::GeometricModel emptyModel;
  cpp::Volume volume("structuredRegular");
  cpp::VolumetricModel volumetricModel(volume);
  cpp::VolumetricModel volumetricModelOfHandle(volume.handle());
  cpp::VolumetricModel emptyVolumetricModel;
  cpp::Group group;
  cpp::Instance instance(group);
  cpp::Instance instanceOfHandle(group.handle());
  cpp::Instance emptyInstance;
  const Box3f bounds = instance.getBounds<Box3f>();
  (void)bounds;

  // Data: explicit element type; inferred from a pointer; containers; one item; adopted.
  std::vector<glm::vec3> points(8);
  const std::array<float, 4> values = {{1.f, 2.f, 3.f, 4.f}};
  cpp::CopiedData explicitType(points.data(), OSP_VEC3F, 8);
  cpp::SharedData explicitTypeStrided(points.data(), OSP_FLOAT, std::size_t(8), std::size_t(12));
  cpp::SharedData grid2(points.data(), glm::ivec2(4, 2));
  cpp::SharedData grid3(points.data(), glm::ivec3(2, 2, 2), glm::ivec3(0));
  cpp::CopiedData grid2ul(points.data(), Size2{4, 2}, Size2{0, 0});
  cpp::CopiedData grid3ul(points.data(), Size3{2, 2, 2}, Size3{0, 0, 0});
  cpp::CopiedData fromArray(values);
  cpp::SharedData fromVector(points);
  cpp::CopiedData oneModel(model);
  cpp::CopiedData oneHandle(model.handle());
  cpp::CopiedData adoptedData(ospNewData(OSP_FLOAT, 4));
  cpp::CopiedData emptyData;
  std::vector<cpp::GeometricModel> models = {model, modelOfHandle};
  cpp::CopiedData modelArray(models);
  std::vector<glm::vec4> colours(8);
  cpp::MovedData movedIn(colours);

  setEveryType(model, geometry, explicitType);
  setEveryType(device, geometry, explicitType);

  cpp::Camera camera("perspective");
  cpp::Renderer renderer("scivis");
  cpp::World world;
  cpp::FrameBuffer framebuffer(4, 4);
  cpp::FrameBuffer none;
  framebuffer.resetAccumulation();
  framebuffer.clear();
  cpp::Future future = framebuffer.renderFrame(renderer, camera, world);
  const bool ready = future.isReady() && future.isReady(OSP_FRAME_FINISHED);
  (void)ready;
  future.wait();
  future.wait(OSP_WORLD_COMMITTED);
  future.cancel();
  const float progress = future.progress() + future.duration() + framebuffer.variance();
  (void)progress;
  const cpp::PickResult picked = framebuffer.pick(renderer, camera, world, 0.5f, 0.5f);
  const bool hit =
      picked.hasHit && picked.instance && picked.model && picked.primID == 0 && picked.worldPosition[0] == 0.f;
  (void)hit;
  void* pixels = framebuffer.map(OSP_FB_COLOR);
  framebuffer.unmap(pixels);

  // OSPRAY_GLM_DEFINITIONS: the constants can be bound to references before C++17 too.
  const OSPDataType& vec3Type = OSPTypeFor<glm::vec3>::value;
  (void)vec3Type;
}

int main() {}
