#pragma once
// The scenes and helpers the C API tests share: the bunny as an OSPRay scene, a scene of
// one geometry, array setters, constructors of spheres and curves, and pick checks.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "sciray/io/ply.hpp"
#include "support/api_fixture.hpp"

namespace sciray_test {



/// The bunny as an OSPRay scene: mesh, model with an obj material, group, instance,
/// world with an ambient and a distant light, a perspective camera, scivis.
struct BunnyScene {
  sciray::MeshData mesh = sciray::io::read_ply(SCIRAY_DATA_DIR "/meshes/bunny.ply");
  OSPGeometry geometry = ospNewGeometry("mesh");
  OSPMaterial material = ospNewMaterial("obj");
  OSPGeometricModel model = ospNewGeometricModel(geometry);
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = ospNewWorld();
  OSPCamera camera = ospNewCamera("perspective");
  OSPRenderer renderer = ospNewRenderer("scivis");
  OSPLight lights[2] = {ospNewLight("ambient"), ospNewLight("distant")};

  BunnyScene() {
    OSPData position = ospNewSharedData1D(mesh.positions.data(), OSP_VEC3F, mesh.vertex_count());
    OSPData index = ospNewSharedData1D(mesh.indices.data(), OSP_VEC3UI, mesh.face_count());
    ospSetObject(geometry, "vertex.position", position);
    ospSetObject(geometry, "index", index);
    ospRelease(position);
    ospRelease(index);
    ospCommit(geometry);
    ospSetVec3f(material, "kd", 0.9f, 0.6f, 0.3f);
    ospCommit(material);
    ospSetObject(model, "material", material);
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospSetFloat(lights[0], "intensity", 0.3f);
    ospSetVec3f(lights[1], "direction", 0.5f, -0.7f, -0.6f);
    for (OSPLight l : lights) ospCommit(l);
    OSPData light_list = ospNewSharedData1D(lights, OSP_LIGHT, 2);
    ospSetObject(world, "light", light_list);
    ospRelease(light_list);
    ospCommit(world);
    const OSPBounds b = ospGetBounds(world);
    const float center[3] = {(b.lower[0] + b.upper[0]) / 2, (b.lower[1] + b.upper[1]) / 2,
                             (b.lower[2] + b.upper[2]) / 2};
    ospSetVec3f(camera, "position", center[0], center[1], center[2] + 0.35f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, -1.f);
    ospSetFloat(camera, "fovy", 40.f);
    ospCommit(camera);
    ospSetVec4f(renderer, "backgroundColor", 0.1f, 0.1f, 0.12f, 1.f);
    ospCommit(renderer);
  }
  ~BunnyScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{geometry, material, model, group, instance, world, camera,
                                                       renderer, lights[0], lights[1]})
      ospRelease(o);
  }
};

inline std::vector<std::uint8_t> render_rgba8(const BunnyScene& s, int w, int h) {
  OSPFrameBuffer fb = ospNewFrameBuffer(w, h, OSP_FB_SRGBA, OSP_FB_COLOR);
  ospRenderFrameBlocking(fb, s.renderer, s.camera, s.world);
  const auto* pixels = static_cast<const std::uint8_t*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  std::vector<std::uint8_t> out(pixels, pixels + 4 * w * h);
  ospUnmapFrameBuffer(pixels, fb);
  ospRelease(fb);
  return out;
}


/// One geometry in a scene lit by a white ambient light of intensity 1 only, so that a
/// pixel's colour is the surface's albedo. The camera looks down +z from z = -5; `ortho`
/// makes it orthographic (height 4). Owns the geometry it is given.
struct GeometryScene {
  OSPGeometry geometry;
  OSPGeometricModel model;
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = ospNewWorld();
  OSPCamera camera;
  OSPRenderer renderer = ospNewRenderer("scivis");
  OSPLight light = ospNewLight("ambient");

  explicit GeometryScene(OSPGeometry g, bool ortho = false)
      : geometry(g), model(ospNewGeometricModel(g)), camera(ospNewCamera(ortho ? "orthographic" : "perspective")) {
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospCommit(light);
    ospSetObjectAsData(world, "light", OSP_LIGHT, light);
    ospCommit(world);
    look_from(0.f, 0.f, -5.f);
    if (ortho) ospSetFloat(camera, "height", 4.f);
    ospCommit(camera);
    ospCommit(renderer);
  }
  GeometryScene(const GeometryScene&) = delete;
  GeometryScene& operator=(const GeometryScene&) = delete;
  ~GeometryScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{geometry, model, group, instance, world, camera, renderer, light})
      ospRelease(o);
  }

  /// Moves the camera to (x, y, z), still looking down +z.
  void look_from(float x, float y, float z) {
    ospSetVec3f(camera, "position", x, y, z);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospCommit(camera);
  }

  /// The pick at screen position (x, y); releases the handles it returns after checking
  /// they are this scene's.
  OSPPickResult pick(float x, float y) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(8, 8);
    OSPPickResult result;
    ospPick(&result, fb, renderer, camera, world, x, y);
    ospRelease(fb);
    if (result.hasHit) {
      CHECK(result.instance == instance);
      CHECK(result.model == model);
      ospRelease(result.instance);
      ospRelease(result.model);
    }
    return result;
  }

  /// An RGBA32F frame, first row at the bottom.
  std::vector<float> render(int w, int h) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(w, h, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* p = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    std::vector<float> out(p, p + 4 * w * h);
    ospUnmapFrameBuffer(p, fb);
    ospRelease(fb);
    return out;
  }
};

/// Sets a 1D array parameter holding a copy of `values` (an object may read its arrays
/// again at any later commit, so the tests do not share their temporaries).
inline void set_array(OSPObject o, const char* id, const void* values, OSPDataType type, std::uint64_t n) {
  OSPData shared = ospNewSharedData1D(values, type, n);
  OSPData owned = ospNewData1D(type, n);
  ospCopyData1D(shared, owned, 0);
  ospSetObject(o, id, owned);
  ospRelease(shared);
  ospRelease(owned);
}

/// A committed mesh: one 20 x 20 quad at y = 0 centred on the origin, its normal up.
inline OSPGeometry new_floor_mesh() {
  OSPGeometry mesh = ospNewGeometry("mesh");
  const float positions[] = {-10, 0, -10, 10, 0, -10, 10, 0, 10, -10, 0, 10};
  const unsigned quads[] = {0, 3, 2, 1};  // the normal points up
  set_array(mesh, "vertex.position", positions, OSP_VEC3F, 4);
  set_array(mesh, "index", quads, OSP_VEC4UI, 1);
  ospCommit(mesh);
  return mesh;
}

/// Points an orthographic camera straight down at the floor's centre from y = 5, its
/// image `height` world units tall (committed only by the caller, which may add more).
inline void look_down_at_floor(OSPCamera camera, float height) {
  ospSetVec3f(camera, "position", 0.f, 5.f, 0.f);
  ospSetVec3f(camera, "direction", 0.f, -1.f, 0.f);
  ospSetVec3f(camera, "up", 0.f, 0.f, 1.f);
  ospSetFloat(camera, "height", height);
}

/// The mean RGB of a frame buffer's `pixels` pixels of RGBA32F colour.
inline std::array<float, 3> mean_rgb(OSPFrameBuffer fb, int pixels) {
  const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  std::array<float, 3> mean{};
  for (int p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) mean[c] += rgba[4 * p + c] / static_cast<float>(pixels);
  ospUnmapFrameBuffer(rgba, fb);
  return mean;
}

/// A committed sphere geometry with the given centres (x,y,z each) and one radius.
inline OSPGeometry new_spheres(const std::vector<float>& centers, float radius) {
  OSPGeometry g = ospNewGeometry("sphere");
  set_array(g, "sphere.position", centers.data(), OSP_VEC3F, centers.size() / 3);
  ospSetFloat(g, "radius", radius);
  ospCommit(g);
  return g;
}

/// A committed curve geometry of x,y,z,r control points and segment indices.
inline OSPGeometry new_curves(const std::vector<float>& position_radius, const std::vector<std::uint32_t>& index,
                       OSPCurveType type, OSPCurveBasis basis) {
  OSPGeometry g = ospNewGeometry("curve");
  set_array(g, "vertex.position_radius", position_radius.data(), OSP_VEC4F, position_radius.size() / 4);
  set_array(g, "index", index.data(), OSP_UINT, index.size());
  ospSetInt(g, "type", type);
  ospSetInt(g, "basis", basis);
  ospCommit(g);
  return g;
}

inline void check_position(const OSPPickResult& hit, float x, float y, float z, float tolerance = 1e-4f) {
  REQUIRE(hit.hasHit == 1);
  CHECK(hit.worldPosition[0] == Approx(x).margin(tolerance));
  CHECK(hit.worldPosition[1] == Approx(y).margin(tolerance));
  CHECK(hit.worldPosition[2] == Approx(z).margin(tolerance));
}

inline float max_abs_difference(const std::vector<float>& a, const std::vector<float>& b) {
  REQUIRE(a.size() == b.size());
  float largest = 0.f;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest;
}

inline const char* const intersectors[] = {"sciray", "embree"};



/// An affine3f as OSPRay stores it: the linear part's columns, then the translation.
inline std::array<float, 12> scale_then_move(float sx, float sy, float sz, float tx, float ty, float tz) {
  return {sx, 0.f, 0.f, 0.f, sy, 0.f, 0.f, 0.f, sz, tx, ty, tz};
}

inline void set_transform(OSPInstance instance, const std::array<float, 12>& m) {
  ospSetParam(instance, "transform", OSP_AFFINE3F, m.data());
}

/// A committed world of `instances` lit by a white ambient light of intensity 1 only.
inline OSPWorld new_world(const std::vector<OSPInstance>& instances) {
  OSPWorld world = ospNewWorld();
  OSPData list = ospNewSharedData1D(instances.data(), OSP_INSTANCE, instances.size());
  ospSetObject(world, "instance", list);
  ospRelease(list);
  OSPLight light = ospNewLight("ambient");
  ospCommit(light);
  ospSetObjectAsData(world, "light", OSP_LIGHT, light);
  ospRelease(light);
  ospCommit(world);
  return world;
}

/// A committed group of `models`.
inline OSPGroup new_group(const std::vector<OSPGeometricModel>& models) {
  OSPGroup group = ospNewGroup();
  if (!models.empty()) {
    OSPData list = ospNewSharedData1D(models.data(), OSP_GEOMETRIC_MODEL, models.size());
    ospSetObject(group, "geometry", list);
    ospRelease(list);
  }
  ospCommit(group);
  return group;
}

/// A committed instance of `group` placed by `m`.
inline OSPInstance new_instance(OSPGroup group, const std::array<float, 12>& m = scale_then_move(1, 1, 1, 0, 0, 0)) {
  OSPInstance instance = ospNewInstance(group);
  set_transform(instance, m);
  ospCommit(instance);
  return instance;
}

/// Picks along single rays: the centre ray of a perspective camera at `from` looking
/// along `dir`.
struct Picker {
  OSPCamera camera = ospNewCamera("perspective");
  OSPRenderer renderer = ospNewRenderer("scivis");
  OSPFrameBuffer fb = ospNewFrameBuffer(8, 8);

  Picker() { ospCommit(renderer); }
  Picker(const Picker&) = delete;
  Picker& operator=(const Picker&) = delete;
  ~Picker() {
    ospRelease(camera);
    ospRelease(renderer);
    ospRelease(fb);
  }

  /// The first hit; the caller releases its instance and model (see release_pick).
  OSPPickResult operator()(OSPWorld world, std::array<float, 3> from, std::array<float, 3> dir = {0.f, 0.f, 1.f}) {
    ospSetVec3f(camera, "position", from[0], from[1], from[2]);
    ospSetVec3f(camera, "direction", dir[0], dir[1], dir[2]);
    ospCommit(camera);
    OSPPickResult result;
    ospPick(&result, fb, renderer, camera, world, 0.5f, 0.5f);
    return result;
  }
};

inline void release_pick(const OSPPickResult& hit) {
  if (!hit.hasHit) return;
  ospRelease(hit.instance);
  ospRelease(hit.model);
}

/// The pick from `from` along `dir` must hit `instance` and `model` at (x, y, z).
inline void check_pick(Picker& pick, OSPWorld world, std::array<float, 3> from, std::array<float, 3> dir,
                OSPInstance instance, OSPGeometricModel model, std::array<float, 3> expected,
                float tolerance = 1e-4f) {
  const OSPPickResult hit = pick(world, from, dir);
  check_position(hit, expected[0], expected[1], expected[2], tolerance);
  CHECK(hit.instance == instance);
  CHECK(hit.model == model);
  release_pick(hit);
}

/// The debug summary of the last world build ("world: built with ...").
inline std::string last_build_summary(const Messages& messages) {
  for (auto it = messages.status.rbegin(); it != messages.status.rend(); ++it)
    if (it->rfind("world: built with", 0) == 0) return *it;
  return {};
}

inline std::uint64_t reported_memory(const std::string& summary) {
  const auto at = summary.find("engine memory ");
  REQUIRE(at != std::string::npos);
  return std::stoull(summary.substr(at + std::strlen("engine memory ")));
}

inline void log_debug(OSPDevice device) {
  ospDeviceSetParam(device, "logLevel", OSP_STRING, "debug");
  ospDeviceCommit(device);
}

inline void check_bounds(const OSPBounds& b, std::array<float, 3> lower, std::array<float, 3> upper) {
  for (int k = 0; k < 3; ++k) {
    INFO("axis " << k);
    CHECK(b.lower[k] == Approx(lower[k]).margin(1e-5));
    CHECK(b.upper[k] == Approx(upper[k]).margin(1e-5));
  }
}



/// A box1f range as OSPRay's `value` takes it.
inline void set_value_range(OSPTransferFunction tf, float lo, float hi) {
  const float range[2] = {lo, hi};
  ospSetParam(tf, "value", OSP_BOX1F, range);
}

/// A committed piecewiseLinear transfer function.
inline OSPTransferFunction new_transfer_function(const std::vector<float>& colors, const std::vector<float>& opacities,
                                          float lo, float hi) {
  OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
  set_array(tf, "color", colors.data(), OSP_VEC3F, colors.size() / 3);
  set_array(tf, "opacity", opacities.data(), OSP_FLOAT, opacities.size());
  set_value_range(tf, lo, hi);
  ospCommit(tf);
  return tf;
}

/// A volume through the C API: a structuredRegular volume, a transfer function, a
/// volumetric model in a group placed by an identity instance, a world; an orthographic
/// camera looking along +z through x, y in [0, 1]; scivis on a black, transparent
/// background. The volume's parameters are the caller's, before `commit`.
/// A shared 3D array of `voxels` (x fastest).
template <class T>
inline OSPData shared_voxels(const std::vector<T>& voxels, OSPDataType type, std::uint64_t nx, std::uint64_t ny,
                      std::uint64_t nz) {
  REQUIRE(voxels.size() == nx * ny * nz);
  return ospNewSharedData3D(voxels.data(), type, nx, ny, nz);
}

struct VolumeScene {
  OSPVolume volume;
  OSPTransferFunction tf = nullptr;
  OSPVolumetricModel model = ospNewVolumetricModel(volume);
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = nullptr;
  OSPCamera camera = ospNewCamera("orthographic");
  OSPRenderer renderer = ospNewRenderer("scivis");
  const std::vector<float> unit_voxels = std::vector<float>(8, 1.f);

  explicit VolumeScene(const char* volume_type = "structuredRegular") : volume(ospNewVolume(volume_type)) {
    ospSetVec3f(camera, "position", 0.5f, 0.5f, -5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospSetFloat(camera, "height", 1.f);
    ospCommit(camera);
    ospCommit(renderer);
  }
  VolumeScene(const VolumeScene&) = delete;
  VolumeScene& operator=(const VolumeScene&) = delete;
  ~VolumeScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{volume, tf, model, group, instance, world, camera, renderer})
      ospRelease(o);
  }

  /// Commits the volume with `data`, and the model with `transfer_function` (taken over).
  void commit(OSPData data, OSPTransferFunction transfer_function, float density_scale = 1.f) {
    ospSetObject(volume, "data", data);
    commit_model(transfer_function, density_scale);
  }
  /// Commits the volume as its parameters stand, and the model with `transfer_function` (taken over).
  void commit_model(OSPTransferFunction transfer_function, float density_scale = 1.f) {
    ospCommit(volume);
    ospRelease(tf);
    tf = transfer_function;
    ospSetObject(model, "transferFunction", tf);
    ospSetFloat(model, "densityScale", density_scale);
    ospCommit(model);
    ospSetObjectAsData(group, "volume", OSP_VOLUMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    if (!world) world = new_world({instance});
  }

  /// Commits the unit cube of constant value 1 (2³ shared voxels) with `transfer_function`.
  void commit_constant(OSPTransferFunction transfer_function, float density_scale = 1.f) {
    OSPData data = shared_voxels(unit_voxels, OSP_FLOAT, 2, 2, 2);
    commit(data, transfer_function, density_scale);
    ospRelease(data);
  }

  /// An RGBA32F frame (premultiplied by the volume's opacity), first row at the bottom.
  std::vector<float> render(int size = 16) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* pixels = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    std::vector<float> out(pixels, pixels + 4 * size * size);
    ospUnmapFrameBuffer(pixels, fb);
    ospRelease(fb);
    return out;
  }
  /// The RGBA of the pixel at the centre of a size x size frame.
  std::array<float, 4> centre(int size = 16) const {
    const auto image = render(size);
    const std::size_t at = 4 * static_cast<std::size_t>(size / 2 * size + size / 2);
    return {image[at], image[at + 1], image[at + 2], image[at + 3]};
  }
  /// centre() with `other` renderer in place of the scene's.
  std::array<float, 4> centre_with(OSPRenderer other) {
    std::swap(other, renderer);
    const auto c = centre();
    std::swap(other, renderer);
    return c;
  }
  /// The path tracer's alpha is OSPRay's: 1 where the camera path collides in the volume,
  /// 0 where it passes through, so over the 12 x 12 inner pixels of 16 x 16 (the volume
  /// fills the view; the pixel filter reaches past its edge) at 128 samples its mean is
  /// the opacity, within 4 standard errors (0.011).
  double path_traced_alpha() {
    OSPRenderer pathtracer = ospNewRenderer("pathtracer");
    ospSetInt(pathtracer, "pixelSamples", 128);
    ospCommit(pathtracer);
    std::swap(pathtracer, renderer);
    const auto image = render(16);
    std::swap(pathtracer, renderer);
    ospRelease(pathtracer);
    double mean_alpha = 0;
    for (int y = 2; y < 14; ++y)
      for (int x = 2; x < 14; ++x) mean_alpha += image[4 * (16 * y + x) + 3] / 144.0;
    return mean_alpha;
  }
  /// With a model of extinction 1 over the unit cube committed: instance transforms place
  /// it, stretched to z in [1, 3] along the view twice as thick (sigma per world unit, as
  /// OSPRay), turned a quarter about y still 1 thick. Leaves it turned.
  void check_placed_by_instance_transforms() {
    set_transform(instance, scale_then_move(1, 1, 2, 0, 0, 1));
    ospCommit(instance);
    CHECK(centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));
    const std::array<float, 12> turned{0.f, 0.f, -1.f, 0.f, 1.f, 0.f, 1.f, 0.f, 0.f, 0.f, 0.f, 1.f};
    set_transform(instance, turned);
    ospCommit(instance);
    CHECK(centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));
  }
};



/// The 8 corners of [lower, upper] (corner k takes upper on axis i where bit i of k is
/// set) and the 12 outward-facing triangles over them.
inline std::vector<float> cube_corners(std::array<float, 3> lower, std::array<float, 3> upper) {
  std::vector<float> corners;
  for (int k = 0; k < 8; ++k)
    for (int i = 0; i < 3; ++i) corners.push_back(k & (1 << i) ? upper[i] : lower[i]);
  return corners;
}
const std::uint32_t cube_triangles[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};

/// A committed mesh geometry: the closed cube [lower, upper] as 12 triangles.
inline OSPGeometry new_cube_mesh(std::array<float, 3> lower, std::array<float, 3> upper) {
  const std::vector<float> corners = cube_corners(lower, upper);
  OSPGeometry g = ospNewGeometry("mesh");
  set_array(g, "vertex.position", corners.data(), OSP_VEC3F, 8);
  set_array(g, "index", cube_triangles, OSP_VEC3UI, 12);
  ospCommit(g);
  return g;
}

/// A committed model of `g`, which it takes over; `invert` sets invertNormals.
inline OSPGeometricModel new_model(OSPGeometry g, bool invert = false) {
  OSPGeometricModel model = ospNewGeometricModel(g);
  ospRelease(g);
  if (invert) ospSetBool(model, "invertNormals", true);
  ospCommit(model);
  return model;
}

/// Sets `group`'s clippingGeometry to `models` (none: removes it) and commits it.
inline void set_clipping(OSPGroup group, const std::vector<OSPGeometricModel>& models) {
  if (models.empty()) {
    ospRemoveParam(group, "clippingGeometry");
  } else {
    OSPData list = ospNewSharedData1D(models.data(), OSP_GEOMETRIC_MODEL, models.size());
    ospSetObject(group, "clippingGeometry", list);
    ospRelease(list);
  }
  ospCommit(group);
}

/// A rotation by `degrees` about the axis `axis` (0, 1, 2 for x, y, z), then a move.
inline std::array<float, 12> rotate_then_move(int axis, float degrees, float tx, float ty, float tz, float scale = 1.f) {
  const float a = degrees * 3.14159265358979f / 180.f, c = std::cos(a) * scale, s = std::sin(a) * scale;
  std::array<float, 12> m{};
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // rotates u towards v
  m[3 * axis + axis] = scale;
  m[3 * u + u] = c, m[3 * u + v] = s;
  m[3 * v + u] = -s, m[3 * v + v] = c;
  m[9] = tx, m[10] = ty, m[11] = tz;
  return m;
}

/// The solid cube [-1, 1]³ as a mesh in one group and instance, and a second group
/// with clipping geometry only (none at first) in its own instance; lit by an ambient
/// light. Picks and orthographic depth images look down +z from z = -5.
struct ClipScene {
  OSPGeometricModel cube = new_model(new_cube_mesh({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
  OSPGroup cube_group = new_group({cube});
  OSPInstance cube_instance = new_instance(cube_group);
  OSPGroup clip_group = new_group({});
  OSPInstance clip_instance = new_instance(clip_group);
  OSPWorld world = new_world({cube_instance, clip_instance});
  Picker pick;

  ClipScene() = default;
  ClipScene(const ClipScene&) = delete;
  ClipScene& operator=(const ClipScene&) = delete;
  ~ClipScene() {
    for (OSPObject o :
         std::initializer_list<OSPObject>{cube, cube_group, cube_instance, clip_group, clip_instance, world})
      ospRelease(o);
  }

  /// Clips with `models` placed by `m` (the models stay the caller's).
  void clip(const std::vector<OSPGeometricModel>& models,
            const std::array<float, 12>& m = scale_then_move(1, 1, 1, 0, 0, 0)) {
    set_clipping(clip_group, models);
    set_transform(clip_instance, m);
    ospCommit(clip_instance);
  }

  /// The pick from (x, y, -5) along +z must land on the cube at (x, y, z).
  void expect_cube(float x, float y, float z) {
    INFO("pick from (" << x << ", " << y << ", -5)");
    check_pick(pick, world, {x, y, -5.f}, {0.f, 0.f, 1.f}, cube_instance, cube, {x, y, z});
  }
  void expect_miss(float x, float y) {
    INFO("pick from (" << x << ", " << y << ", -5)");
    const OSPPickResult hit = pick(world, {x, y, -5.f});
    CHECK(hit.hasHit == 0);
    release_pick(hit);
  }

  /// Depth (distance from the plane z = -5: 4 on the front face, 6 on the back face,
  /// inf where nothing is hit) of an orthographic W x W view of [-2, 2]², with the
  /// screen's x running along -x; calls check(x, y, depth) for each pixel.
  template <class Check>
  void check_depth(int W, Check&& check) {
    OSPCamera camera = ospNewCamera("orthographic");
    ospSetVec3f(camera, "position", 0.f, 0.f, -5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospSetFloat(camera, "height", 4.f);
    ospCommit(camera);
    OSPFrameBuffer fb = ospNewFrameBuffer(W, W, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_DEPTH);
    ospRenderFrameBlocking(fb, pick.renderer, camera, world);
    const auto* depth = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_DEPTH));
    REQUIRE(depth != nullptr);
    for (int py = 0; py < W; ++py)
      for (int px = 0; px < W; ++px)
        check(-((px + 0.5f) / W * 4.f - 2.f), (py + 0.5f) / W * 4.f - 2.f, depth[py * W + px]);
    ospUnmapFrameBuffer(depth, fb);
    ospRelease(fb);
    ospRelease(camera);
  }
};

constexpr float inf = std::numeric_limits<float>::infinity();

/// Counts pixels whose depth is not `expected(x, y)`; NaN means "do not check" (near an
/// edge of the clipped region).
template <class Expected>
inline int wrong_depths(ClipScene& scene, Expected&& expected, int* checked) {
  int wrong = 0;
  *checked = 0;
  scene.check_depth(64, [&](float x, float y, float depth) {
    const float want = expected(x, y);
    if (std::isnan(want)) return;
    ++*checked;
    if (std::isinf(want) ? !std::isinf(depth) : std::abs(depth - want) > 1e-3f) ++wrong;
  });
  return wrong;
}

/// Where the front face is cut by a disc of `radius` about (cx, cy) and the back face is
/// not: `inside` where the front face is clipped, `outside` elsewhere on the cube, inf
/// off it, NaN within `margin` of an edge.
inline float disc_depth(float x, float y, float cx, float cy, float radius, float inside, float outside,
                 float margin = 0.05f) {
  if (std::abs(std::abs(x) - 1.f) < margin || std::abs(std::abs(y) - 1.f) < margin) return NAN;
  if (std::abs(x) > 1.f || std::abs(y) > 1.f) return inf;
  const float r = std::hypot(x - cx, y - cy);
  if (std::abs(r - radius) < margin) return NAN;
  return r < radius ? inside : outside;
}


}  // namespace sciray_test
