// The OSPRay 3 C API over sciray. Each function translates handles and parameters into
// the object model (object.hpp and friends) and turns every sciray::Error into a call of
// the device's error callback: bad input is reported by name and never crashes.
#include <charconv>
#include <cstring>
#include <memory>
#include <limits>
#include <string>

#include "device.hpp"
#include "frame_objects.hpp"
#include "scene_objects.hpp"

using namespace sciray::ospray;
using sciray::Box3f;
using sciray::Error;
using sciray::FrameControl;
using sciray::Ray;
using sciray::SciVisParams;
using sciray::Vec3f;
namespace shim = sciray::shim;

namespace {

Device* current_device = nullptr;

Device& device() {
  if (!current_device) current_device = new Device();  // OSPRay programs may skip ospInit
  return *current_device;
}

/// Runs `body`, reporting any exception through the current device; returns `fallback`
/// after an error.
template <class F, class R = std::invoke_result_t<F>>
R guarded(const char* function, F&& body, R fallback = R()) {
  try {
    return body();
  } catch (const sciray::Error& e) {
    device().error(OSP_INVALID_ARGUMENT, std::string(function) + ": " + e.what());
  } catch (const std::bad_alloc&) {
    device().error(OSP_OUT_OF_MEMORY, std::string(function) + ": out of memory");
  } catch (const std::exception& e) {
    device().error(OSP_UNKNOWN_ERROR, std::string(function) + ": " + e.what());
  }
  return fallback;
}
template <class F>
void guarded_void(const char* function, F&& body) {
  guarded(function, [&] {
    body();
    return 0;
  });
}

/// The live object behind a handle, or an error naming the function's argument.
Object& live(const void* handle, const char* what) {
  if (!handle) throw Error(std::string(what) + " is NULL");
  if (!Registry::instance().alive(handle)) throw Error(std::string(what) + " is not a live object (released or invalid)");
  return *static_cast<Object*>(const_cast<void*>(handle));
}
template <class T>
T& live_as(const void* handle, OSPDataType kind, const char* what) {
  Object& o = live(handle, what);
  if (o.kind() != kind)
    throw Error(std::string(what) + " must be " + type_name(kind) + " but is " + type_name(o.kind()));
  return static_cast<T&>(o);
}

template <class Handle>
Handle handle_of(Object* o) {
  return reinterpret_cast<Handle>(o);
}

std::string type_string(const char* type) {
  if (!type) throw Error("the type name is NULL");
  return type;
}

[[noreturn]] void unknown_type(const char* family, const std::string& type, const char* known) {
  throw Error(std::string("unknown ") + family + " type '" + type + "' (sciray supports: " + known + ")");
}

/// The point of the group's space that `m` places at world point `x`: the inverse of
/// the linear part is its adjugate over its determinant.
Vec3f to_group_space(const sciray::Affine3f& m, const Vec3f& x) {
  const Vec3f w = x - m.p;
  const float det = m.determinant();
  return Vec3f{dot(cross(m.vy, m.vz), w), dot(cross(m.vz, m.vx), w), dot(cross(m.vx, m.vy), w)} * (1.f / det);
}

void report_unused(Object& o, const std::vector<std::string>& unused) {
  for (const auto& id : unused) device().warn(o.name() + ": parameter '" + id + "' is not used (unknown or not supported)");
  for (const auto& message : o.debug_messages()) device().status(OSP_LOG_DEBUG, o.name() + ": " + message);
}

}  // namespace

extern "C" {

// ---- devices -----------------------------------------------------------------------

OSPError ospInit(int* argc, const char** argv) {
  return guarded("ospInit", [&] {
    auto d = std::make_unique<Device>();
    const bool have_args = argc && argv && *argc > 0;
    int kept = 1;  // argv[0], the program
    for (int i = 1; have_args && i < *argc; ++i) {
      const std::string arg = argv[i] ? argv[i] : "";
      if (arg.rfind("--osp:", 0) != 0) {
        argv[kept++] = argv[i];
        continue;
      }
      const std::string option = arg.substr(6);
      const auto eq = option.find('=');
      const std::string key = option.substr(0, eq), value = eq == std::string::npos ? "" : option.substr(eq + 1);
      if (key == "num-threads") {
        int n = 0;
        if (std::from_chars(value.data(), value.data() + value.size(), n).ec != std::errc{} || n < 0)
          throw Error("--osp:num-threads expects a count, got '" + value + "'");
        d->set_param("numThreads", OSP_INT, &n);
      } else if (key == "log-level") {
        d->set_param("logLevel", OSP_STRING, value.c_str());
      } else if (key == "warn-as-error") {
        const int on = 1;
        d->set_param("warnAsError", OSP_INT, &on);
      } else if (key == "debug") {
        const int on = 1;
        d->set_param("debug", OSP_INT, &on);
      } else if (key == "isa") {
        d->set_param("isa", OSP_STRING, value.c_str());
      } else if (key == "device" || key == "load-modules") {
        if (key == "device" && value != "cpu" && value != "default")
          throw Error("--osp:device=" + value + ": sciray provides the 'cpu' device only");
      } else {
        throw Error("unknown option " + arg);
      }
    }
    // Only argv[0 .. *argc-1] belongs to ospInit (OSPRay's contract): the application's
    // argv may be longer, or hold no NULL after the arguments, so nothing past them is written.
    if (have_args) *argc = kept;
    d->commit();
    if (current_device && current_device->release()) delete current_device;
    current_device = d.release();
    return OSP_NO_ERROR;
  }, OSP_INVALID_ARGUMENT);
}

void ospShutdown() {
  if (current_device && current_device->release()) delete current_device;
  current_device = nullptr;
}

OSPDevice ospNewDevice(const char* type) {
  return guarded("ospNewDevice", [&] {
    const std::string t = type ? type : "cpu";
    if (t != "cpu" && t != "default") unknown_type("device", t, "cpu");
    return reinterpret_cast<OSPDevice>(new Device());
  }, OSPDevice{});
}

void ospSetCurrentDevice(OSPDevice d) {
  guarded_void("ospSetCurrentDevice", [&] {
    if (!d) throw Error("device is NULL");
    auto* dev = reinterpret_cast<Device*>(d);
    if (dev == current_device) return;
    dev->retain();
    if (current_device && current_device->release()) delete current_device;
    current_device = dev;
  });
}

OSPDevice ospGetCurrentDevice() {
  Device& d = device();
  d.retain();  // OSPRay returns a new reference
  return reinterpret_cast<OSPDevice>(&d);
}

int64_t ospDeviceGetProperty(OSPDevice, OSPDeviceProperty property) {
  switch (property) {
    case OSP_DEVICE_VERSION: return OSPRAY_VERSION_MAJOR * 10000 + OSPRAY_VERSION_MINOR * 100 + OSPRAY_VERSION_PATCH;
    case OSP_DEVICE_VERSION_MAJOR: return OSPRAY_VERSION_MAJOR;
    case OSP_DEVICE_VERSION_MINOR: return OSPRAY_VERSION_MINOR;
    case OSP_DEVICE_VERSION_PATCH: return OSPRAY_VERSION_PATCH;
    case OSP_DEVICE_SO_VERSION: return OSPRAY_VERSION_MAJOR;
  }
  device().error(OSP_INVALID_ARGUMENT, "ospDeviceGetProperty: unknown property");
  return 0;
}

void ospDeviceSetParam(OSPDevice d, const char* id, OSPDataType type, const void* mem) {
  guarded_void("ospDeviceSetParam", [&] {
    if (!d) throw Error("device is NULL");
    if (!id) throw Error("parameter name is NULL");
    reinterpret_cast<Device*>(d)->set_param(id, type, mem);
  });
}

void ospDeviceRemoveParam(OSPDevice d, const char* id) {
  guarded_void("ospDeviceRemoveParam", [&] {
    if (!d || !id) throw Error("device or parameter name is NULL");
    reinterpret_cast<Device*>(d)->remove_param(id);
  });
}

void ospDeviceSetStatusCallback(OSPDevice d, OSPStatusCallback cb, void* user) {
  if (d) reinterpret_cast<Device*>(d)->set_status_callback(cb, user);
}

void ospDeviceSetErrorCallback(OSPDevice d, OSPErrorCallback cb, void* user) {
  if (d) reinterpret_cast<Device*>(d)->set_error_callback(cb, user);
}

OSPError ospDeviceGetLastErrorCode(OSPDevice d) {
  return d ? reinterpret_cast<Device*>(d)->last_error_code() : OSP_INVALID_ARGUMENT;
}

const char* ospDeviceGetLastErrorMsg(OSPDevice d) {
  return d ? reinterpret_cast<Device*>(d)->last_error_message() : "device is NULL";
}

void ospDeviceCommit(OSPDevice d) {
  guarded_void("ospDeviceCommit", [&] {
    if (!d) throw Error("device is NULL");
    reinterpret_cast<Device*>(d)->commit();
  });
}

void ospDeviceRelease(OSPDevice d) {
  if (!d) return;
  auto* dev = reinterpret_cast<Device*>(d);
  if (dev->release()) {
    if (dev == current_device) current_device = nullptr;
    delete dev;
  }
}

void ospDeviceRetain(OSPDevice d) {
  if (d) reinterpret_cast<Device*>(d)->retain();
}

OSPError ospLoadModule(const char* name) {
  return guarded("ospLoadModule", [&] {
    const std::string module = name ? name : "";
    if (module != "cpu") throw Error("module '" + module + "' does not exist: sciray's types are built in ('cpu')");
    return OSP_NO_ERROR;
  }, OSP_INVALID_ARGUMENT);
}

// ---- data ----------------------------------------------------------------------------

OSPData ospNewSharedData(const void* shared, OSPDataType type, uint64_t n1, int64_t s1, uint64_t n2, int64_t s2,
                         uint64_t n3, int64_t s3, OSPDeleterCallback deleter, const void* user) {
  return guarded("ospNewSharedData", [&] {
    return handle_of<OSPData>(new Data(shared, type, {n1, n2, n3}, {s1, s2, s3}, deleter, user));
  }, OSPData{});
}

OSPData ospNewData(OSPDataType type, uint64_t n1, uint64_t n2, uint64_t n3) {
  return guarded("ospNewData", [&] { return handle_of<OSPData>(new Data(type, {n1, n2, n3})); }, OSPData{});
}

void ospCopyData(const OSPData source, OSPData destination, uint64_t i1, uint64_t i2, uint64_t i3) {
  guarded_void("ospCopyData", [&] {
    auto& from = live_as<Data>(source, OSP_DATA, "source");
    auto& to = live_as<Data>(destination, OSP_DATA, "destination");
    to.copy_from(from, {i1, i2, i3});
  });
}

// ---- object factories ------------------------------------------------------------------

OSPLight ospNewLight(const char* type) {
  return guarded("ospNewLight", [&] {
    const std::string t = type_string(type);
    if (t != "ambient" && t != "distant" && t != "sphere" && t != "spot" && t != "quad" && t != "cylinder" &&
        t != "hdri" && t != "sunSky")
      unknown_type("light", t, "ambient, distant, sphere, spot, quad, cylinder, hdri, sunSky");
    return handle_of<OSPLight>(new Light(t));
  }, OSPLight{});
}

OSPCamera ospNewCamera(const char* type) {
  return guarded("ospNewCamera", [&] {
    const std::string t = type_string(type);
    if (t != "perspective" && t != "orthographic" && t != "panoramic")
      unknown_type("camera", t, "perspective, orthographic, panoramic");
    return handle_of<OSPCamera>(new CameraObject(t));
  }, OSPCamera{});
}

OSPGeometry ospNewGeometry(const char* type) {
  return guarded("ospNewGeometry", [&] {
    const std::string t = type_string(type);
    if (t != "mesh" && t != "sphere" && t != "curve" && t != "box" && t != "plane" && t != "isosurface" &&
        t != "subdivision")
      unknown_type("geometry", t, "mesh, sphere, curve, box, plane, isosurface, subdivision");
    return handle_of<OSPGeometry>(new Geometry(t));
  }, OSPGeometry{});
}

OSPVolume ospNewVolume(const char* type) {
  return guarded("ospNewVolume", [&] {
    const std::string t = type_string(type);
    if (t != "structuredRegular") unknown_type("volume", t, "structuredRegular");
    return handle_of<OSPVolume>(new VolumeObject(t));
  }, OSPVolume{});
}

OSPGeometricModel ospNewGeometricModel(OSPGeometry geometry) {
  return guarded("ospNewGeometricModel", [&] {
    if (geometry) live_as<Geometry>(geometry, OSP_GEOMETRY, "geometry");
    auto* model = new GeometricModel();
    if (geometry) model->set_param("geometry", OSP_GEOMETRY, &geometry);
    return handle_of<OSPGeometricModel>(model);
  }, OSPGeometricModel{});
}

OSPVolumetricModel ospNewVolumetricModel(OSPVolume volume) {
  return guarded("ospNewVolumetricModel", [&] {
    if (volume) live_as<VolumeObject>(volume, OSP_VOLUME, "volume");
    auto* model = new VolumetricModelObject();
    if (volume) model->set_param("volume", OSP_VOLUME, &volume);
    return handle_of<OSPVolumetricModel>(model);
  }, OSPVolumetricModel{});
}

OSPMaterial ospNewMaterial(const char* type) {
  return guarded("ospNewMaterial", [&] {
    const std::string t = type_string(type);
    if (!sciray::material_of_type(t)) unknown_type("material", t, sciray::material_type_list().c_str());
    return handle_of<OSPMaterial>(new Material(t));
  }, OSPMaterial{});
}

OSPTransferFunction ospNewTransferFunction(const char* type) {
  return guarded("ospNewTransferFunction", [&] {
    const std::string t = type_string(type);
    if (t != "piecewiseLinear") unknown_type("transfer function", t, "piecewiseLinear");
    return handle_of<OSPTransferFunction>(new TransferFunctionObject(t));
  }, OSPTransferFunction{});
}

OSPTexture ospNewTexture(const char* type) {
  return guarded("ospNewTexture", [&] {
    const std::string t = type_string(type);
    if (t != "volume" && t != "texture2d") unknown_type("texture", t, "volume, texture2d");
    return handle_of<OSPTexture>(new TextureObject(t));
  }, OSPTexture{});
}

OSPGroup ospNewGroup() {
  return guarded("ospNewGroup", [] { return handle_of<OSPGroup>(new Group()); }, OSPGroup{});
}

OSPInstance ospNewInstance(OSPGroup group) {
  return guarded("ospNewInstance", [&] {
    if (group) live_as<Group>(group, OSP_GROUP, "group");
    auto* instance = new Instance();
    if (group) instance->set_param("group", OSP_GROUP, &group);
    return handle_of<OSPInstance>(instance);
  }, OSPInstance{});
}

OSPWorld ospNewWorld() {
  return guarded("ospNewWorld", [] { return handle_of<OSPWorld>(new World()); }, OSPWorld{});
}

OSPBounds ospGetBounds(OSPObject object) {
  OSPBounds empty{{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                   std::numeric_limits<float>::infinity()},
                  {-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity()}};
  return guarded("ospGetBounds", [&] {
    Object& o = live(object, "object");
    if (!o.committed()) throw Error(o.name() + " has not been committed");
    Box3f box;
    switch (o.kind()) {
      case OSP_WORLD: box = static_cast<World&>(o).bounds(); break;
      case OSP_INSTANCE: box = static_cast<Instance&>(o).bounds(); break;
      case OSP_GROUP: box = static_cast<Group&>(o).bounds(); break;
      case OSP_GEOMETRIC_MODEL: box = static_cast<GeometricModel&>(o).geometry()->bounds(); break;
      case OSP_GEOMETRY: box = static_cast<Geometry&>(o).bounds(); break;
      case OSP_VOLUMETRIC_MODEL: box = static_cast<VolumetricModelObject&>(o).bounds(); break;
      case OSP_VOLUME: box = static_cast<VolumeObject&>(o).bounds(); break;
      default: throw Error(o.name() + " has no bounds");
    }
    return OSPBounds{{box.lower.x, box.lower.y, box.lower.z}, {box.upper.x, box.upper.y, box.upper.z}};
  }, empty);
}

// ---- parameters and lifetime ----------------------------------------------------------

void ospSetParam(OSPObject object, const char* id, OSPDataType type, const void* mem) {
  guarded_void("ospSetParam", [&] {
    Object& o = live(object, "object");
    if (!id) throw Error(o.name() + ": parameter name is NULL");
    o.set_param(id, type, mem);
  });
}

void ospRemoveParam(OSPObject object, const char* id) {
  guarded_void("ospRemoveParam", [&] {
    Object& o = live(object, "object");
    if (!id) throw Error(o.name() + ": parameter name is NULL");
    o.remove_param(id);
  });
}

void ospCommit(OSPObject object) {
  guarded_void("ospCommit", [&] {
    Object& o = live(object, "object");
    report_unused(o, o.commit());
  });
}

void ospRelease(OSPObject object) {
  if (!object) return;
  guarded_void("ospRelease", [&] { live(object, "object").release(); });
}

void ospRetain(OSPObject object) {
  guarded_void("ospRetain", [&] { live(object, "object").retain(); });
}

// ---- frame buffers ---------------------------------------------------------------------

OSPFrameBuffer ospNewFrameBuffer(int width, int height, OSPFrameBufferFormat format, uint32_t channels) {
  return guarded("ospNewFrameBuffer", [&] {
    constexpr uint32_t known = OSP_FB_COLOR | OSP_FB_DEPTH | OSP_FB_ACCUM | OSP_FB_VARIANCE | OSP_FB_NORMAL |
                               OSP_FB_ALBEDO | OSP_FB_ID_PRIMITIVE | OSP_FB_ID_OBJECT | OSP_FB_ID_INSTANCE;
    if (channels & ~known)
      device().warn("frame buffer: channel bits " + std::to_string(channels & ~known) +
                    " are not OSPFrameBufferChannel values and are ignored");
    if ((channels & OSP_FB_VARIANCE) && !(channels & OSP_FB_ACCUM))
      device().warn("frame buffer: OSP_FB_VARIANCE needs OSP_FB_ACCUM; no variance will be estimated");
    return handle_of<OSPFrameBuffer>(new FrameBufferObject(width, height, format, channels));
  }, OSPFrameBuffer{});
}

OSPImageOperation ospNewImageOperation(const char* type) {
  return guarded("ospNewImageOperation", [&] {
    const std::string t = type_string(type);
    if (t != "tonemapper" && t != "debug") unknown_type("image operation", t, "tonemapper, debug");
    return handle_of<OSPImageOperation>(new ImageOperationObject(t));
  }, OSPImageOperation{});
}

const void* ospMapFrameBuffer(OSPFrameBuffer fb, OSPFrameBufferChannel channel) {
  return guarded("ospMapFrameBuffer", [&] {
    return live_as<FrameBufferObject>(fb, OSP_FRAMEBUFFER, "frame buffer").map(channel);
  }, static_cast<const void*>(nullptr));
}

void ospUnmapFrameBuffer(const void* mapped, OSPFrameBuffer fb) {
  guarded_void("ospUnmapFrameBuffer", [&] {
    live_as<FrameBufferObject>(fb, OSP_FRAMEBUFFER, "frame buffer").unmap(mapped);
  });
}

float ospGetVariance(OSPFrameBuffer fb) {
  return guarded("ospGetVariance", [&] {
    auto& frame = live_as<FrameBufferObject>(fb, OSP_FRAMEBUFFER, "frame buffer");
    std::lock_guard lock(frame.mutex());
    return frame.frame().variance();  // OSPRay's measure (ErrorEstimate::ospray)
  }, std::numeric_limits<float>::infinity());
}

void ospResetAccumulation(OSPFrameBuffer fb) {
  guarded_void("ospResetAccumulation", [&] {
    auto& frame = live_as<FrameBufferObject>(fb, OSP_FRAMEBUFFER, "frame buffer");
    std::lock_guard lock(frame.mutex());
    frame.frame().reset_accumulation();
  });
}

// ---- rendering ---------------------------------------------------------------------------

OSPRenderer ospNewRenderer(const char* type) {
  return guarded("ospNewRenderer", [&] {
    const std::string t = type_string(type);
    if (t != "scivis" && t != "ao" && t != "pathtracer") unknown_type("renderer", t, "scivis, ao, pathtracer");
    return handle_of<OSPRenderer>(new Renderer(t));
  }, OSPRenderer{});
}

namespace {
struct FrameInputs {
  Ref<FrameBufferObject> fb;
  Ref<Renderer> renderer;
  Ref<CameraObject> camera;
  std::shared_ptr<const BuiltWorld> world;
};

FrameInputs frame_inputs(OSPFrameBuffer fb, OSPRenderer renderer, OSPCamera camera, OSPWorld world) {
  FrameInputs in;
  in.fb = &live_as<FrameBufferObject>(fb, OSP_FRAMEBUFFER, "frame buffer");
  in.renderer = &live_as<Renderer>(renderer, OSP_RENDERER, "renderer");
  in.camera = &live_as<CameraObject>(camera, OSP_CAMERA, "camera");
  auto& w = live_as<World>(world, OSP_WORLD, "world");
  if (!in.renderer->committed()) throw Error(in.renderer->name() + " has not been committed");
  if (!in.camera->committed()) throw Error(in.camera->name() + " has not been committed");
  if (!w.committed()) throw Error("world has not been committed");
  Device& dev = device();
  BuildLog log;
  log.want_memory = dev.logs(OSP_LOG_DEBUG);  // memory_bytes walks every instance
  in.world = w.built(dev.kernels(), log);
  for (const auto& message : log.warnings) dev.warn(message);
  for (const auto& message : log.debug) dev.status(OSP_LOG_DEBUG, message);
  return in;
}
}  // namespace

OSPFuture ospRenderFrame(OSPFrameBuffer fb, OSPRenderer renderer, OSPCamera camera, OSPWorld world) {
  return guarded("ospRenderFrame", [&] {
    FrameInputs in = frame_inputs(fb, renderer, camera, world);
    Device& dev = device();
    dev.retain();  // the frame may outlive ospShutdown
    auto task = [in, &dev](FrameControl& control) {
      const shim::RendererConfig config = in.renderer->config(*in.world);
      std::lock_guard lock(in.fb->mutex());
      try {
        dev.arena().execute([&] {
          // The kernels the world was committed with (the device's when the frame started).
          in.world->kernels->render(*in.world->world, config, in.camera->camera(), in.fb->frame(), &control,
                                    in.renderer->frame_settings());
        });
      } catch (const std::exception& e) {
        dev.error(OSP_UNKNOWN_ERROR, std::string("ospRenderFrame: ") + e.what());
      }
      if (dev.release()) delete &dev;
    };
    return handle_of<OSPFuture>(new Future(std::move(task)));
  }, OSPFuture{});
}

int ospIsReady(OSPFuture future, OSPSyncEvent) {
  return guarded("ospIsReady", [&] { return live_as<Future>(future, OSP_FUTURE, "future").ready() ? 1 : 0; }, 1);
}

void ospWait(OSPFuture future, OSPSyncEvent) {
  guarded_void("ospWait", [&] { live_as<Future>(future, OSP_FUTURE, "future").wait(); });
}

void ospCancel(OSPFuture future) {
  guarded_void("ospCancel", [&] {
    auto& f = live_as<Future>(future, OSP_FUTURE, "future");
    f.cancel();
    f.wait();  // OSPRay: "may block the calling thread"
  });
}

float ospGetProgress(OSPFuture future) {
  return guarded("ospGetProgress", [&] { return live_as<Future>(future, OSP_FUTURE, "future").progress(); }, 0.f);
}

float ospGetTaskDuration(OSPFuture future) {
  return guarded("ospGetTaskDuration",
                 [&] { return live_as<Future>(future, OSP_FUTURE, "future").duration_seconds(); }, 0.f);
}

void ospPick(OSPPickResult* result, OSPFrameBuffer fb, OSPRenderer renderer, OSPCamera camera, OSPWorld world,
             float x, float y) {
  guarded_void("ospPick", [&] {
    if (!result) throw Error("result is NULL");
    *result = {};
    FrameInputs in = frame_inputs(fb, renderer, camera, world);
    // Through the lens centre: a pick asks what is at a screen point, not what one lens sample sees.
    const Ray<float> ray = std::visit([&](const auto& c) { return sciray::prepare(c).generate(x, y, 0.5f, 0.5f); },
                                      in.camera->camera());
    shim::TraceResult hit;
    in.world->kernels->trace(*in.world->world, std::span(&ray, 1), std::span(&hit, 1));
    if (hit.geom_id < 0) return;
    const BuiltWorld::Origin origin = in.world->origin(hit.inst_id, hit.geom_id);
    // Embree transforms the ray into the instance without renormalizing it, so t is the
    // world ray's parameter too.
    const Vec3f p = ray.org + ray.dir * hit.t;
    // An isosurface's primitives are its isovalues (the engine's are macrocells): the
    // one the volume's value at the hit, in the group's space, is nearest.
    std::uint32_t prim = static_cast<uint32_t>(hit.prim_id);
    if (sciray::ospray::Geometry* g = origin.model->geometry(); g->isosurface_volume())
      prim = g->isovalue_index(to_group_space(origin.instance->placement().at(ray.time), p));
    result->hasHit = 1;
    result->worldPosition[0] = p.x, result->worldPosition[1] = p.y, result->worldPosition[2] = p.z;
    origin.instance->retain();
    origin.model->retain();
    result->instance = handle_of<OSPInstance>(origin.instance);
    result->model = handle_of<OSPGeometricModel>(origin.model);
    result->primID = prim;
  });
}

}  // extern "C"
