// The OSPRay 3 C API over sciray. Each function translates handles and parameters into
// the object model (object.hpp and friends) and turns every sciray::Error into a call of
// the device's error callback: bad input is reported by name and never crashes.
#include <charconv>
#include <cstring>
#include <memory>
#include <limits>
#include <mutex>
#include <optional>
#include <string>

#include "device.hpp"
#include "frame_objects.hpp"
#include "mpi/distributed.hpp"
#include "mpi/offload.hpp"
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

/// Serializes what changes objects (parameters, commits, array copies) with what reads
/// them for a frame (the world's build and the frame's snapshot in ospRenderFrame and
/// ospPick, bounds): any application thread may call the API, and a frame renders the
/// state committed before its ospRenderFrame, never a mix (docs/c-api.md, "Threads").
/// Recursive: an error callback may call the API.
std::unique_lock<std::recursive_mutex> lock_object_state() {
  static std::recursive_mutex mutex;
  return std::unique_lock(mutex);
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

/// Where the current device forwards the calls that change state (an mpiOffload device
/// on the application's rank), or null. Calls are recorded after they succeeded here.
offload::CommandLog* forwarding() {
  offload::Session* session = device().offload();
  return session ? &session->log() : nullptr;
}

/// A new object of `kind` (and `type`), recorded for the workers of an offloading device.
template <class Handle>
Handle created(Object* o, const std::string& type = {}) {
  if (offload::CommandLog* log = forwarding()) log->new_object(o->kind(), type, o);
  return handle_of<Handle>(o);
}

/// Makes `d` the current device (the one API calls without a device argument use).
void make_current(Device* d) {
  if (d == current_device) return;
  d->retain();
  if (current_device && current_device->release()) delete current_device;
  current_device = d;
}

const char* const device_types = "cpu, mpiOffload, mpiDistributed";

/// Modules are built in; loading one that exists does nothing.
void check_module(const std::string& module) {
  if (module != "cpu" && module != "mpi" && module != "mpi_offload" && module != "mpi_distributed_cpu")
    throw Error("module '" + module + "' does not exist: sciray's types are built in (modules cpu, mpi_offload, "
                "mpi_distributed_cpu)");
}

DeviceType device_type_of(const std::string& name) {
  if (name == "cpu" || name == "default") return DeviceType::cpu;
  if (name == "mpiOffload" || name == "mpi_offload" || name == "mpi") return DeviceType::mpi_offload;
  if (name == "mpiDistributed" || name == "mpi_distributed") return DeviceType::mpi_distributed;
  throw Error("unknown device type '" + name + "' (sciray provides: " + device_types + ")");
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

struct FrameInputs {
  Ref<FrameBufferObject> fb;
  Ref<Renderer> renderer;
  Ref<CameraObject> camera;
  Ref<World> world_object;
  std::shared_ptr<const BuiltWorld> world;
};

/// The frame's objects, checked; the world built for rendering here unless `build` is
/// false (an offloading device's workers build it).
FrameInputs frame_inputs(OSPFrameBuffer fb, OSPRenderer renderer, OSPCamera camera, OSPWorld world, bool build = true) {
  FrameInputs in;
  in.fb = &live_as<FrameBufferObject>(fb, OSP_FRAMEBUFFER, "frame buffer");
  in.renderer = &live_as<Renderer>(renderer, OSP_RENDERER, "renderer");
  in.camera = &live_as<CameraObject>(camera, OSP_CAMERA, "camera");
  auto& w = live_as<World>(world, OSP_WORLD, "world");
  if (!in.renderer->committed()) throw Error(in.renderer->name() + " has not been committed");
  if (!in.camera->committed()) throw Error(in.camera->name() + " has not been committed");
  if (!w.committed()) throw Error("world has not been committed");
  in.world_object = &w;
  if (!build) return in;
  Device& dev = device();
  BuildLog log;
  log.want_memory = dev.logs(OSP_LOG_DEBUG);  // memory_bytes walks every instance
  in.world = w.built(dev.kernels(), log);
  for (const auto& message : log.warnings) dev.warn(message);
  for (const auto& message : log.debug) dev.status(OSP_LOG_DEBUG, message);
  return in;
}
}  // namespace

extern "C" {

// ---- devices -----------------------------------------------------------------------

OSPError ospInit(int* argc, const char** argv) {
  return guarded("ospInit", [&] {
    DeviceType type = DeviceType::cpu;
    for (int i = 1; argc && argv && i < *argc; ++i)
      if (argv[i] && std::strncmp(argv[i], "--osp:device=", 13) == 0) type = device_type_of(argv[i] + 13);
    auto d = std::make_unique<Device>(type);
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
      } else if (key == "load-modules") {
        for (std::size_t at = 0; at <= value.size();) {
          const std::size_t comma = std::min(value.find(',', at), value.size());
          if (comma > at) check_module(value.substr(at, comma - at));
          at = comma + 1;
        }
      } else if (key == "device") {
        // chosen above
      } else {
        throw Error("unknown option " + arg);
      }
    }
    // Only argv[0 .. *argc-1] belongs to ospInit (OSPRay's contract): the application's
    // argv may be longer, or hold no NULL after the arguments, so nothing past them is written.
    if (have_args) *argc = kept;
    d->commit();
    Device* dev = d.release();
    make_current(dev);
    dev->release();  // current_device holds the reference
    dev->start_mpi([dev] { make_current(dev); });
    return OSP_NO_ERROR;
  }, OSP_INVALID_ARGUMENT);
}

void ospShutdown() {
  if (current_device && current_device->release()) delete current_device;
  current_device = nullptr;
}

OSPDevice ospNewDevice(const char* type) {
  return guarded("ospNewDevice", [&] {
    return reinterpret_cast<OSPDevice>(new Device(device_type_of(type ? type : "cpu")));
  }, OSPDevice{});
}

void ospSetCurrentDevice(OSPDevice d) {
  guarded_void("ospSetCurrentDevice", [&] {
    if (!d) throw Error("device is NULL");
    make_current(reinterpret_cast<Device*>(d));
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
  if (!d) return guarded_void("ospDeviceCommit", [] { throw Error("device is NULL"); });
  auto* dev = reinterpret_cast<Device*>(d);
  try {  // reported by the device committed, which need not be current yet
    dev->commit();
    dev->start_mpi([dev] { make_current(dev); });
  } catch (const sciray::Error& e) {
    dev->error(OSP_INVALID_ARGUMENT, std::string("ospDeviceCommit: ") + e.what());
  } catch (const std::exception& e) {
    dev->error(OSP_UNKNOWN_ERROR, std::string("ospDeviceCommit: ") + e.what());
  }
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
    check_module(name ? name : "");
    return OSP_NO_ERROR;
  }, OSP_INVALID_ARGUMENT);
}

// ---- data ----------------------------------------------------------------------------

OSPData ospNewSharedData(const void* shared, OSPDataType type, uint64_t n1, int64_t s1, uint64_t n2, int64_t s2,
                         uint64_t n3, int64_t s3, OSPDeleterCallback deleter, const void* user) {
  return guarded("ospNewSharedData", [&] {
    auto* data = new Data(shared, type, {n1, n2, n3}, {s1, s2, s3}, deleter, user);
    if (offload::CommandLog* log = forwarding()) log->new_data(data, *data);
    return handle_of<OSPData>(data);
  }, OSPData{});
}

OSPData ospNewData(OSPDataType type, uint64_t n1, uint64_t n2, uint64_t n3) {
  return guarded("ospNewData", [&] {
    auto* data = new Data(type, {n1, n2, n3});
    if (offload::CommandLog* log = forwarding()) log->new_data(data, *data);
    return handle_of<OSPData>(data);
  }, OSPData{});
}

void ospCopyData(const OSPData source, OSPData destination, uint64_t i1, uint64_t i2, uint64_t i3) {
  guarded_void("ospCopyData", [&] {
    const auto state = lock_object_state();
    auto& from = live_as<Data>(source, OSP_DATA, "source");
    auto& to = live_as<Data>(destination, OSP_DATA, "destination");
    to.copy_from(from, {i1, i2, i3});
    if (offload::CommandLog* log = forwarding()) log->copy_data(source, destination, i1, i2, i3);
  });
}

// ---- object factories ------------------------------------------------------------------

OSPLight ospNewLight(const char* type) {
  return guarded("ospNewLight", [&] {
    const std::string t = type_string(type);
    if (t != "ambient" && t != "distant" && t != "sphere" && t != "spot" && t != "quad" && t != "cylinder" &&
        t != "hdri" && t != "sunSky")
      unknown_type("light", t, "ambient, distant, sphere, spot, quad, cylinder, hdri, sunSky");
    return created<OSPLight>(new Light(t), t);
  }, OSPLight{});
}

OSPCamera ospNewCamera(const char* type) {
  return guarded("ospNewCamera", [&] {
    const std::string t = type_string(type);
    if (t != "perspective" && t != "orthographic" && t != "panoramic")
      unknown_type("camera", t, "perspective, orthographic, panoramic");
    return created<OSPCamera>(new CameraObject(t), t);
  }, OSPCamera{});
}

OSPGeometry ospNewGeometry(const char* type) {
  return guarded("ospNewGeometry", [&] {
    const std::string t = type_string(type);
    if (t != "mesh" && t != "sphere" && t != "curve" && t != "box" && t != "plane" && t != "isosurface" &&
        t != "subdivision")
      unknown_type("geometry", t, "mesh, sphere, curve, box, plane, isosurface, subdivision");
    return created<OSPGeometry>(new Geometry(t), t);
  }, OSPGeometry{});
}

OSPVolume ospNewVolume(const char* type) {
  return guarded("ospNewVolume", [&] {
    const std::string t = type_string(type);
    if (t != "structuredRegular" && t != "unstructured" && t != "particle" && t != "structuredSpherical" && t != "vdb" &&
        t != "amr")
      unknown_type("volume", t, "structuredRegular, unstructured, particle, structuredSpherical, vdb, amr");
    return created<OSPVolume>(new VolumeObject(t), t);
  }, OSPVolume{});
}

OSPGeometricModel ospNewGeometricModel(OSPGeometry geometry) {
  return guarded("ospNewGeometricModel", [&] {
    if (geometry) live_as<Geometry>(geometry, OSP_GEOMETRY, "geometry");
    auto* model = new GeometricModel();
    if (geometry) model->set_param("geometry", OSP_GEOMETRY, &geometry);
    if (offload::CommandLog* log = forwarding()) log->new_holder(OSP_GEOMETRIC_MODEL, model, geometry);
    return handle_of<OSPGeometricModel>(model);
  }, OSPGeometricModel{});
}

OSPVolumetricModel ospNewVolumetricModel(OSPVolume volume) {
  return guarded("ospNewVolumetricModel", [&] {
    if (volume) live_as<VolumeObject>(volume, OSP_VOLUME, "volume");
    auto* model = new VolumetricModelObject();
    if (volume) model->set_param("volume", OSP_VOLUME, &volume);
    if (offload::CommandLog* log = forwarding()) log->new_holder(OSP_VOLUMETRIC_MODEL, model, volume);
    return handle_of<OSPVolumetricModel>(model);
  }, OSPVolumetricModel{});
}

OSPMaterial ospNewMaterial(const char* type) {
  return guarded("ospNewMaterial", [&] {
    const std::string t = type_string(type);
    if (!sciray::material_of_type(t)) unknown_type("material", t, sciray::material_type_list().c_str());
    return created<OSPMaterial>(new Material(t), t);
  }, OSPMaterial{});
}

OSPTransferFunction ospNewTransferFunction(const char* type) {
  return guarded("ospNewTransferFunction", [&] {
    const std::string t = type_string(type);
    if (t != "piecewiseLinear") unknown_type("transfer function", t, "piecewiseLinear");
    return created<OSPTransferFunction>(new TransferFunctionObject(t), t);
  }, OSPTransferFunction{});
}

OSPTexture ospNewTexture(const char* type) {
  return guarded("ospNewTexture", [&] {
    const std::string t = type_string(type);
    if (t != "volume" && t != "texture2d") unknown_type("texture", t, "volume, texture2d");
    return created<OSPTexture>(new TextureObject(t), t);
  }, OSPTexture{});
}

OSPGroup ospNewGroup() {
  return guarded("ospNewGroup", [] { return created<OSPGroup>(new Group()); }, OSPGroup{});
}

OSPInstance ospNewInstance(OSPGroup group) {
  return guarded("ospNewInstance", [&] {
    if (group) live_as<Group>(group, OSP_GROUP, "group");
    auto* instance = new Instance();
    if (group) instance->set_param("group", OSP_GROUP, &group);
    if (offload::CommandLog* log = forwarding()) log->new_holder(OSP_INSTANCE, instance, group);
    return handle_of<OSPInstance>(instance);
  }, OSPInstance{});
}

OSPWorld ospNewWorld() {
  return guarded("ospNewWorld", [] { return created<OSPWorld>(new World()); }, OSPWorld{});
}

OSPBounds ospGetBounds(OSPObject object) {
  OSPBounds empty{{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                   std::numeric_limits<float>::infinity()},
                  {-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity()}};
  return guarded("ospGetBounds", [&] {
    const auto state = lock_object_state();
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
    const auto state = lock_object_state();
    Object& o = live(object, "object");
    if (!id) throw Error(o.name() + ": parameter name is NULL");
    o.set_param(id, type, mem);
    if (offload::CommandLog* log = forwarding()) log->set_param(object, id, type, mem);
  });
}

void ospRemoveParam(OSPObject object, const char* id) {
  guarded_void("ospRemoveParam", [&] {
    const auto state = lock_object_state();
    Object& o = live(object, "object");
    if (!id) throw Error(o.name() + ": parameter name is NULL");
    o.remove_param(id);
    if (offload::CommandLog* log = forwarding()) log->remove_param(object, id);
  });
}

void ospCommit(OSPObject object) {
  guarded_void("ospCommit", [&] {
    const auto state = lock_object_state();
    Object& o = live(object, "object");
    report_unused(o, o.commit());
    if (offload::CommandLog* log = forwarding()) {
      // Committing an array that shares the application's memory says the memory changed.
      if (o.kind() == OSP_DATA && static_cast<Data&>(o).shares_memory())
        log->update_data(object, static_cast<Data&>(o));
      log->commit(object);
    }
  });
}

void ospRelease(OSPObject object) {
  if (!object) return;
  guarded_void("ospRelease", [&] {
    Object& o = live(object, "object");
    const bool forwarded = o.kind() != OSP_FUTURE;  // futures live on the application's rank only
    o.release();
    if (offload::CommandLog* log = forwarding(); log && forwarded) log->release(object);
  });
}

void ospRetain(OSPObject object) {
  guarded_void("ospRetain", [&] {
    Object& o = live(object, "object");
    o.retain();
    if (offload::CommandLog* log = forwarding(); log && o.kind() != OSP_FUTURE) log->retain(object);
  });
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
    auto* frame = new FrameBufferObject(width, height, format, channels);
    if (offload::CommandLog* log = forwarding()) log->new_frame_buffer(frame, width, height, format, channels);
    return handle_of<OSPFrameBuffer>(frame);
  }, OSPFrameBuffer{});
}

OSPImageOperation ospNewImageOperation(const char* type) {
  return guarded("ospNewImageOperation", [&] {
    const std::string t = type_string(type);
    if (t != "tonemapper" && t != "debug") unknown_type("image operation", t, "tonemapper, debug");
    return created<OSPImageOperation>(new ImageOperationObject(t), t);
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
    if (t != "scivis" && t != "ao" && t != "pathtracer" && t != "mpiRaycast")
      unknown_type("renderer", t, "scivis, ao, pathtracer, mpiRaycast");
    return created<OSPRenderer>(new Renderer(t), t);
  }, OSPRenderer{});
}

OSPFuture ospRenderFrame(OSPFrameBuffer fb, OSPRenderer renderer, OSPCamera camera, OSPWorld world) {
  return guarded("ospRenderFrame", [&] {
    Device& dev = device();
    auto state = lock_object_state();
    if (offload::Session* session = dev.offload()) {
      FrameInputs in = frame_inputs(fb, renderer, camera, world, false);
      state.unlock();
      auto serve = session->render_frame(in.fb, in.renderer, in.camera, in.world_object, dev.kernels());
      dev.retain();  // the frame may outlive ospShutdown
      auto* future = new Future([serve = std::move(serve), &dev](FrameControl& control) {
        try {
          serve(control);
        } catch (const std::exception& e) {
          dev.error(OSP_UNKNOWN_ERROR, std::string("ospRenderFrame: ") + e.what());
        }
        if (dev.release()) delete &dev;
      });
      // Without MPI_THREAD_MULTIPLE the application may call MPI as soon as this returns.
      if (!session->frames_run_asynchronously()) future->wait();
      return handle_of<OSPFuture>(future);
    }
    FrameInputs in = frame_inputs(fb, renderer, camera, world);
    if (distributed::Session* session = dev.distributed()) {
      state.unlock();
      // A collective call: every rank renders and composites before it returns.
      std::lock_guard lock(in.fb->mutex());
      session->render_frame(*in.fb, *in.renderer, *in.camera, *in.world_object, *in.world, dev);
      return handle_of<OSPFuture>(new Future([](FrameControl&) {}));
    }
    // The frame's state, copied now: commits from here on show in the next frame only.
    std::optional<shim::RendererConfig> config;
    std::string config_error;  // reported by the frame, as the frame's other errors
    try {
      config = in.renderer->config(*in.world);
    } catch (const std::exception& e) {
      config_error = e.what();
    }
    const sciray::Camera view = in.camera->camera();
    const sciray::FrameSettings settings = in.renderer->frame_settings();
    state.unlock();
    dev.retain();  // the frame may outlive ospShutdown
    auto task = [in, config = std::move(config), config_error, view, settings, &dev](FrameControl& control) {
      std::lock_guard lock(in.fb->mutex());
      try {
        if (!config) throw Error(config_error);
        dev.arena().execute([&] {
          // The kernels the world was committed with (the device's when the frame started).
          in.world->kernels->render(*in.world->world, *config, view, in.fb->frame(), &control, settings);
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
    auto state = lock_object_state();
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
    if (offload::CommandLog* log = forwarding()) log->retain(origin.instance), log->retain(origin.model);
    result->instance = handle_of<OSPInstance>(origin.instance);
    result->model = handle_of<OSPGeometricModel>(origin.model);
    result->primID = prim;
  });
}

}  // extern "C"
