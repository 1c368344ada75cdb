// libFuzzer target: the OSPRay C API, reading its input as a sequence of API calls.
// Object creation (every type, valid and unknown subtypes), parameters of every type under
// the names the shim reads (and wrong types for them), data arrays of random element types,
// sizes and strides (shared or copied, objects included), copies between arrays, commits,
// retains and releases, renders into tiny frame buffers (read back channel by channel,
// sometimes cancelled) and picks. The shim's refusals arrive through the error callback and
// are clean outcomes; a crash, a sanitizer finding, a leak or a hang is a finding.
//
// Encoding (fuzz/make_c_api_seeds.py writes seeds in it): one byte picks an operation, the
// bytes after it its operands, each read in turn; an input that ends early reads zeros.
// Objects go into a table of handles (an operand byte picks one modulo its size); a handle
// stays in the table after its last release, so later calls also pass released handles,
// which the shim must recognize. This target holds references only through `held` and
// gives every one back at the end of the input, with shared arrays' memory freed after that.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <ospray/ospray.h>

namespace {

/// With SCIRAY_FUZZ_VERBOSE set, the target says what each input did.
bool verbose() {
  static const bool on = std::getenv("SCIRAY_FUZZ_VERBOSE") != nullptr;
  return on;
}

/// Reads operands from the input in order; past its end every read is zero.
class Reader {
public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool done() const { return at_ >= size_; }
  std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }
  std::uint16_t u16() { return static_cast<std::uint16_t>(byte() | (byte() << 8)); }

private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

/// A float from one byte: mostly small multiples of 1/4 in [-8, 8] (coordinates, colours
/// and radii that make scenes), sometimes the values that break arithmetic.
float float_of(std::uint8_t b) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  static constexpr std::array<float, 16> specials = {
      std::numeric_limits<float>::quiet_NaN(), inf, -inf, 1e30f, -1e30f, 1e-30f, 1e-45f, 3.4e38f,
      -0.0f, 1e6f, -1e6f, 1e-6f, 0.999999f, 1.000001f, 65504.f, std::numeric_limits<float>::max()};
  if (b < 240) return (static_cast<int>(b % 65) - 32) / 4.0f;
  return specials[b - 240];
}

/// An integer from one byte: small values (indices, counts, enums) and the edges of types.
std::int64_t int_of(std::uint8_t b) {
  static constexpr std::array<std::int64_t, 16> specials = {
      -1, -2, 255, 256, 65535, 65536, 2147483647, -2147483648LL, 4294967295LL, 4294967296LL,
      std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min(), 1 << 20, 1000, 100, 16};
  if (b < 240) return b % 24;
  return specials[b - 240];
}

/// The element types of OSPRay with the kind and count of their components.
struct TypeInfo {
  OSPDataType type;
  char component;  // f float, d double, h half, i/u 32-bit, s/S 16-bit, c/b 8-bit, l/L 64-bit,
                   // B bool, o object handle, z string, p pointer
  int count;
};
constexpr std::array<TypeInfo, 62> types = {{
    {OSP_FLOAT, 'f', 1},         {OSP_VEC2F, 'f', 2},       {OSP_VEC3F, 'f', 3},      {OSP_VEC4F, 'f', 4},
    {OSP_INT, 'i', 1},           {OSP_VEC2I, 'i', 2},       {OSP_VEC3I, 'i', 3},      {OSP_VEC4I, 'i', 4},
    {OSP_UINT, 'u', 1},          {OSP_VEC2UI, 'u', 2},      {OSP_VEC3UI, 'u', 3},     {OSP_VEC4UI, 'u', 4},
    {OSP_UCHAR, 'b', 1},         {OSP_VEC2UC, 'b', 2},      {OSP_VEC3UC, 'b', 3},     {OSP_VEC4UC, 'b', 4},
    {OSP_CHAR, 'c', 1},          {OSP_VEC3C, 'c', 3},       {OSP_SHORT, 's', 1},      {OSP_VEC3S, 's', 3},
    {OSP_USHORT, 'S', 1},        {OSP_VEC2US, 'S', 2},      {OSP_VEC3US, 'S', 3},     {OSP_HALF, 'h', 1},
    {OSP_VEC3H, 'h', 3},         {OSP_LONG, 'l', 1},        {OSP_VEC3L, 'l', 3},      {OSP_ULONG, 'L', 1},
    {OSP_VEC2UL, 'L', 2},        {OSP_DOUBLE, 'd', 1},      {OSP_VEC3D, 'd', 3},      {OSP_BOOL, 'B', 1},
    {OSP_BOX1I, 'i', 2},         {OSP_BOX3I, 'i', 6},       {OSP_BOX1F, 'f', 2},      {OSP_BOX2F, 'f', 4},
    {OSP_BOX3F, 'f', 6},         {OSP_LINEAR2F, 'f', 4},    {OSP_LINEAR3F, 'f', 9},   {OSP_AFFINE2F, 'f', 6},
    {OSP_AFFINE3F, 'f', 12},     {OSP_QUATF, 'f', 4},       {OSP_STRING, 'z', 1},     {OSP_VOID_PTR, 'p', 1},
    {OSP_DATA, 'o', 1},          {OSP_CAMERA, 'o', 1},      {OSP_FRAMEBUFFER, 'o', 1}, {OSP_GEOMETRIC_MODEL, 'o', 1},
    {OSP_GEOMETRY, 'o', 1},      {OSP_GROUP, 'o', 1},       {OSP_IMAGE_OPERATION, 'o', 1}, {OSP_INSTANCE, 'o', 1},
    {OSP_LIGHT, 'o', 1},         {OSP_MATERIAL, 'o', 1},    {OSP_RENDERER, 'o', 1},   {OSP_TEXTURE, 'o', 1},
    {OSP_TRANSFER_FUNCTION, 'o', 1}, {OSP_VOLUME, 'o', 1},  {OSP_VOLUMETRIC_MODEL, 'o', 1}, {OSP_WORLD, 'o', 1},
    {OSP_OBJECT, 'o', 1},        {OSP_UNKNOWN, 'b', 1},
}};

constexpr std::size_t first_object_type = 44, object_type_count = 17;  // OSP_DATA to OSP_OBJECT
static_assert(types[first_object_type].type == OSP_DATA &&
              types[first_object_type + object_type_count - 1].type == OSP_OBJECT);

std::size_t component_size(char component) {
  switch (component) {
    case 'f': case 'i': case 'u': return 4;
    case 'd': case 'l': case 'L': case 'o': case 'p': return 8;
    case 's': case 'S': case 'h': return 2;
    default: return 1;
  }
}

/// Every parameter name the shim reads, and two it never does.
constexpr auto names = std::to_array<const char*>({
    "position", "direction", "up", "fovy", "aspect", "height", "nearClip", "apertureRadius", "focusDistance",
    "imageStart", "imageEnd", "stereoMode", "interpupillaryDistance", "architectural", "transform", "motion.transform",
    "shutter", "backgroundColor", "pixelSamples", "maxPathLength", "minContribution", "aoSamples", "aoDistance",
    "aoIntensity", "shadows", "volumeSamplingRate", "lightSamples", "geometryLights", "roulettePathLength",
    "maxContribution", "map_backplate", "map_maxDepth", "pixelFilter", "varianceThreshold", "visibleLights",
    "vertex.position", "vertex.normal", "vertex.color", "vertex.texcoord", "vertex.tangent", "vertex.position_radius",
    "index", "quadSoup", "sphere.position", "sphere.radius", "sphere.texcoord", "radius", "type", "basis",
    "box", "plane.coefficients", "plane.bounds", "isovalue", "volume", "level", "vertexCrease.index",
    "vertexCrease.weight", "edgeCrease.index", "edgeCrease.weight", "face", "mode", "data", "gridOrigin",
    "gridSpacing", "cellCentered", "filter", "gradientFilter", "vertex.data", "cell.index", "cell.type", "cell.data",
    "hexIterative", "precomputedNormals", "particle.position", "particle.radius", "particle.weight",
    "clampMaxCumulativeValue", "radiusSupportFactor", "estimateValueRanges", "node.level", "node.origin",
    "node.format", "node.data", "block.bounds", "block.level", "block.data", "cellWidth", "method", "background",
    "color", "opacity", "value", "intensity", "intensityQuantity", "visible", "angularDiameter", "openingAngle",
    "penumbraAngle", "edge1", "edge2", "position0", "position1", "map", "turbidity", "horizonExtension",
    "densityScale", "anisotropy", "gradientShadingScale", "geometry", "material", "invertNormals", "id",
    "transferFunction", "texture", "instance", "group", "light", "ambientRadiance", "kd", "ks", "ns", "d",
    "baseColor", "metallic", "roughness", "ior", "eta", "k", "material1", "material2", "format", "wrapMode",
    "exposure", "contrast", "shoulder", "midIn", "midOut", "hdrMax", "acesColor", "", "noSuchParameter"});

/// The object types, each with its subtypes; one past the last subtype asks for an unknown one.
struct Kind {
  const char* name;
  std::vector<const char*> subtypes;
};
const std::array<Kind, 9> kinds = {{
    {"camera", {"perspective", "orthographic", "panoramic"}},
    {"renderer", {"scivis", "ao", "pathtracer"}},
    {"geometry", {"mesh", "sphere", "curve", "box", "plane", "isosurface", "subdivision"}},
    {"volume", {"structuredRegular", "unstructured", "particle", "structuredSpherical", "vdb", "amr"}},
    {"light", {"ambient", "distant", "sphere", "spot", "quad", "cylinder", "hdri", "sunSky"}},
    {"material", {"obj", "principled", "glass", "thinGlass", "metal", "alloy", "luminous", "velvet",
                  "metallicPaint", "carPaint", "plastic", "mix"}},
    {"transferFunction", {"piecewiseLinear"}},
    {"texture", {"volume", "texture2d"}},
    {"imageOperation", {"tonemapper", "debug"}},
}};

OSPObject create(std::size_t kind, const char* subtype) {
  switch (kind) {
    case 0: return ospNewCamera(subtype);
    case 1: return ospNewRenderer(subtype);
    case 2: return ospNewGeometry(subtype);
    case 3: return ospNewVolume(subtype);
    case 4: return ospNewLight(subtype);
    case 5: return ospNewMaterial(subtype);
    case 6: return ospNewTransferFunction(subtype);
    case 7: return ospNewTexture(subtype);
    default: return ospNewImageOperation(subtype);
  }
}

/// The handles of one input and the references this target holds on them.
struct Session {
  std::vector<OSPObject> handles;
  std::vector<int> held;
  std::vector<std::unique_ptr<std::byte[]>> shared_memory;

  void add(OSPObject handle) {
    if (!handle || handles.size() >= 64) {
      if (handle) ospRelease(handle);
      return;
    }
    handles.push_back(handle);
    held.push_back(1);
  }
  /// A handle from the table (possibly released), or null.
  OSPObject pick(std::uint8_t b) const {
    if (handles.empty() || b == 255) return nullptr;
    return handles[b % handles.size()];
  }
  /// The same as a handle of type `Handle`: handles are opaque, the shim checks their type.
  template <class Handle>
  Handle pick_as(std::uint8_t b) const {
    return reinterpret_cast<Handle>(pick(b));
  }
  ~Session() {
    for (std::size_t i = 0; i < handles.size(); ++i)
      for (; held[i] > 0; --held[i]) ospRelease(handles[i]);
  }
};

/// Writes one component of `component` kind read from the input at `out`.
void write_component(Reader& in, const Session& session, char component, std::byte* out) {
  const std::uint8_t b = in.byte();
  auto put = [out](auto value) { std::memcpy(out, &value, sizeof value); };
  switch (component) {
    case 'f': put(float_of(b)); break;
    case 'd': put(static_cast<double>(float_of(b))); break;
    case 'h': put(static_cast<std::uint16_t>(b < 128 ? 0x3c00 + (b << 4) : b * 257)); break;
    case 'i': put(static_cast<std::int32_t>(int_of(b))); break;
    case 'u': put(static_cast<std::uint32_t>(int_of(b))); break;
    case 's': put(static_cast<std::int16_t>(int_of(b))); break;
    case 'S': put(static_cast<std::uint16_t>(int_of(b))); break;
    case 'l': put(int_of(b)); break;
    case 'L': put(static_cast<std::uint64_t>(int_of(b))); break;
    case 'o': put(session.pick(b)); break;
    case 'p': put(static_cast<const void*>(nullptr)); break;
    case 'B': put(static_cast<std::uint8_t>(b & 1)); break;
    default: put(b); break;
  }
}

// Costs a fuzzer could raise without limit are held to what a tiny frame needs: a
// million samples a pixel is the caller's request, not a hang of the shim.
constexpr std::array<const char*, 8> costly = {"pixelSamples", "maxPathLength", "aoSamples", "lightSamples",
                                               "roulettePathLength", "level", "map_maxDepth", "maxIteratorDepth"};

void set_param(Reader& in, Session& session) {
  OSPObject object = session.pick(in.byte());
  const char* name = names[in.byte() % names.size()];
  const TypeInfo& info = types[in.byte() % types.size()];
  if (info.component == 'z') {
    std::string text;
    for (std::uint8_t n = in.byte() % 24; n > 0; --n) text += static_cast<char>(in.byte());
    ospSetParam(object, name, OSP_STRING, text.c_str());
    return;
  }
  alignas(16) std::array<std::byte, 128> value{};
  const std::size_t size = component_size(info.component);
  for (int c = 0; c < info.count; ++c) write_component(in, session, info.component, value.data() + c * size);
  if (std::find_if(costly.begin(), costly.end(), [&](const char* c) { return std::strcmp(c, name) == 0; }) !=
          costly.end() &&
      (info.component == 'i' || info.component == 'u')) {
    std::int32_t v;
    std::memcpy(&v, value.data(), 4);
    v = std::clamp(v, -4, 6);
    std::memcpy(value.data(), &v, 4);
  }
  ospSetParam(object, name, info.type, value.data());
}

/// A data array: element type, up to 3 dimensions (at most 4096 elements), filled from the
/// input; shared from memory laid out with the chosen byte strides (misaligned, padded and
/// reversed included) or created by the shim and filled with ospCopyData.
void new_data(Reader& in, Session& session) {
  const TypeInfo& info = types[in.byte() % types.size()];
  std::array<std::uint64_t, 3> count = {in.byte() % 65u, 1u + in.byte() % 17u, 1u + in.byte() % 5u};
  const std::uint8_t layout = in.byte();
  if (count[0] * count[1] * count[2] > 4096) count[2] = 1;
  if (info.component == 'z') return;  // arrays of strings do not exist
  const std::size_t element = component_size(info.component) * static_cast<std::size_t>(info.count);

  // Byte strides: all 0 (packed, OSPRay's default) or per dimension one of packed,
  // packed + 1 (misaligned), twice the element (gaps) or reversed.
  std::array<std::int64_t, 3> stride = {0, 0, 0}, step = {0, 0, 0};
  std::int64_t packed = static_cast<std::int64_t>(element);
  for (int d = 0; d < 3; ++d) {
    const int choice = (layout & 1) ? (layout >> (1 + 2 * d)) & 3 : 0;
    step[d] = choice == 0 ? packed : choice == 1 ? packed + 1 : choice == 2 ? 2 * packed : -packed;
    if (layout & 1) stride[d] = step[d];
    packed = step[d] < 0 ? -step[d] : step[d];
    packed *= static_cast<std::int64_t>(count[d]);
  }
  // The memory the steps reach, and where element 0 lies in it.
  std::int64_t low = 0, high = 0;
  for (int d = 0; d < 3; ++d) {
    const std::int64_t reach = step[d] * (static_cast<std::int64_t>(std::max<std::uint64_t>(count[d], 1)) - 1);
    (reach < 0 ? low : high) += reach;
  }
  const std::size_t bytes = static_cast<std::size_t>(high - low) + element;
  auto memory = std::make_unique<std::byte[]>(bytes + 16);  // 16: Embree reads vectors past the end
  for (std::size_t at = 0; at + element <= bytes; at += element)
    for (int c = 0; c < info.count; ++c)
      write_component(in, session, info.component, memory.get() + at + c * component_size(info.component));
  const std::byte* first = memory.get() - low;

  if (layout & 128) {  // copied: a shared source into an array of the shim's
    OSPData source = ospNewSharedData(first, info.type, count[0], stride[0], count[1], stride[1], count[2], stride[2]);
    OSPData copy = ospNewData(info.type, count[0], count[1], count[2]);
    if (source && copy) ospCopyData(source, copy, 0, 0, 0);
    if (source) ospRelease(source);
    session.add(copy);
  } else {
    session.add(ospNewSharedData(first, info.type, count[0], stride[0], count[1], stride[1], count[2], stride[2]));
  }
  session.shared_memory.push_back(std::move(memory));
}

/// Renders 1 to 3 frames of up to 8x8 pixels, sometimes cancelling one, and reads every
/// channel back.
void render(Reader& in, Session& session, bool pick) {
  const int width = 1 + in.byte() % 8, height = 1 + in.byte() % 8;
  const auto format = static_cast<OSPFrameBufferFormat>(in.byte() % 6);
  const std::uint32_t channels = in.u16() & 0x1ff;
  auto renderer = session.pick_as<OSPRenderer>(in.byte());
  auto camera = session.pick_as<OSPCamera>(in.byte());
  auto world = session.pick_as<OSPWorld>(in.byte());
  const std::uint8_t frames = 1 + in.byte() % 3, cancel = in.byte();
  OSPFrameBuffer fb = ospNewFrameBuffer(width, height, format, channels);
  if (!fb) return;
  if (in.byte() & 1) {
    OSPImageOperation tonemapper = ospNewImageOperation("tonemapper");
    OSPData operations = ospNewSharedData(&tonemapper, OSP_IMAGE_OPERATION, 1);
    ospCommit(tonemapper);
    ospSetParam(fb, "imageOperation", OSP_DATA, &operations);
    ospCommit(fb);
    ospRelease(operations);
    ospRelease(tonemapper);
  }
  for (std::uint8_t f = 0; f < frames; ++f) {
    OSPFuture future = ospRenderFrame(fb, renderer, camera, world);
    if (!future) break;
    if (cancel & (1 << f)) ospCancel(future);
    ospWait(future, OSP_TASK_FINISHED);
    (void)ospGetProgress(future);
    ospRelease(future);
  }
  volatile float sum = ospGetVariance(fb);
  for (OSPFrameBufferChannel channel : {OSP_FB_COLOR, OSP_FB_DEPTH, OSP_FB_NORMAL, OSP_FB_ALBEDO,
                                        OSP_FB_ID_PRIMITIVE, OSP_FB_ID_OBJECT, OSP_FB_ID_INSTANCE}) {
    const void* mapped = ospMapFrameBuffer(fb, channel);
    if (!mapped) continue;
    // Every byte is read, so that a short buffer is an AddressSanitizer finding.
    const std::size_t bytes =
        static_cast<std::size_t>(width) * height *
        (channel == OSP_FB_COLOR ? (format == OSP_FB_RGBA32F ? 16 : format == OSP_FB_NONE ? 0 : 4)
                                 : channel == OSP_FB_NORMAL || channel == OSP_FB_ALBEDO ? 12 : 4);
    for (std::size_t i = 0; i < bytes; ++i) sum = sum + static_cast<const unsigned char*>(mapped)[i];
    if (channel == OSP_FB_DEPTH && verbose()) {  // to check that the seeds' frames show their scenes
      const auto* depth = static_cast<const float*>(mapped);
      std::fprintf(stderr, "frame: %ld of %d pixels hit\n",
                   std::count_if(depth, depth + width * height, [](float d) { return std::isfinite(d); }),
                   width * height);
    }
    ospUnmapFrameBuffer(mapped, fb);
  }
  if (pick) {
    OSPPickResult result{};
    ospPick(&result, fb, renderer, camera, world, float_of(in.byte()) / 8 + 0.5f, float_of(in.byte()) / 8 + 0.5f);
    // A hit hands back references, as in OSPRay.
    if (result.hasHit) {
      if (result.instance) ospRelease(result.instance);
      if (result.model) ospRelease(result.model);
    }
  }
  ospResetAccumulation(fb);
  ospRelease(fb);
}

void error_callback(void*, OSPError, const char* message) {
  if (verbose()) std::fprintf(stderr, "error: %s\n", message);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (ospInit(nullptr, nullptr) != OSP_NO_ERROR) std::abort();
  OSPDevice device = ospGetCurrentDevice();
  ospDeviceSetErrorCallback(device, error_callback, nullptr);
  ospDeviceRelease(device);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  Session session;
  for (int operations = 0; !in.done() && operations < 256; ++operations) {
    const int operation = in.byte() % 13;
    if (verbose()) std::fprintf(stderr, "operation %d\n", operation);
    switch (operation) {
      case 0: {  // a new object of a type with a subtype
        const Kind& kind = kinds[in.byte() % kinds.size()];
        const std::uint8_t subtype = in.byte() % (kind.subtypes.size() + 1);
        session.add(create(static_cast<std::size_t>(&kind - kinds.data()),
                           subtype < kind.subtypes.size() ? kind.subtypes[subtype] : "noSuchType"));
        break;
      }
      case 1: {  // a new object made from another handle (possibly of the wrong type)
        const std::uint8_t which = in.byte() % 5;
        OSPObject from = session.pick(in.byte());
        session.add(which == 0   ? ospNewGeometricModel(reinterpret_cast<OSPGeometry>(from))
                    : which == 1 ? ospNewVolumetricModel(reinterpret_cast<OSPVolume>(from))
                    : which == 2 ? ospNewInstance(reinterpret_cast<OSPGroup>(from))
                    : which == 3 ? static_cast<OSPObject>(ospNewGroup())
                                 : static_cast<OSPObject>(ospNewWorld()));
        break;
      }
      case 2: set_param(in, session); break;
      case 3: new_data(in, session); break;
      case 4: ospCommit(session.pick(in.byte())); break;
      case 5: {  // a release of a held reference (releasing a dead handle is not the shim's to catch)
        if (session.handles.empty()) break;
        const std::size_t i = in.byte() % session.handles.size();
        if (session.held[i] > 0) {
          ospRelease(session.handles[i]);
          --session.held[i];
        }
        break;
      }
      case 6: {
        if (session.handles.empty()) break;
        const std::size_t i = in.byte() % session.handles.size();
        if (session.held[i] > 0) {
          ospRetain(session.handles[i]);
          ++session.held[i];
        }
        break;
      }
      case 7: ospRemoveParam(session.pick(in.byte()), names[in.byte() % names.size()]); break;
      case 8: render(in, session, false); break;
      case 9: render(in, session, true); break;
      case 10: {  // a copy between arrays at an offset
        auto source = session.pick_as<OSPData>(in.byte()), destination = session.pick_as<OSPData>(in.byte());
        ospCopyData(source, destination, in.byte() % 8, in.byte() % 4, in.byte() % 2);
        break;
      }
      case 11: {
        volatile OSPBounds bounds = ospGetBounds(session.pick(in.byte()));
        (void)bounds;
        break;
      }
      default: {  // an object parameter set to a handle of any type
        OSPObject object = session.pick(in.byte()), value = session.pick(in.byte());
        const TypeInfo& info = types[first_object_type + in.byte() % object_type_count];
        ospSetParam(object, names[in.byte() % names.size()], info.type, &value);
        break;
      }
    }
  }
  return 0;
}
