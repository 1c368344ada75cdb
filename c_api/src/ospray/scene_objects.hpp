#pragma once
// OSPRay's scene objects over sciray types: cameras, geometry (mesh, sphere, curve),
// geometric models, groups, instances, worlds, lights, materials and renderers. Each reads its committed
// parameters in on_commit and names the parameter when one is wrong.
#include <memory>
#include <mutex>

#include "data.hpp"
#include "sciray/geometry/curves.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/render/scivis.hpp"
#include "sciray/shim/engine.hpp"

namespace sciray::ospray {

class CameraObject : public Object {
public:
  explicit CameraObject(std::string type) : Object(OSP_CAMERA, std::move(type)) {}
  const sciray::Camera& camera() const { return camera_; }

protected:
  void on_commit() override;

private:
  sciray::Camera camera_;
};

class Material : public Object {
public:
  explicit Material(std::string type) : Object(OSP_MATERIAL, std::move(type)) {}
  Vec3f kd() const { return kd_; }

protected:
  void on_commit() override;

private:
  Vec3f kd_{0.8f, 0.8f, 0.8f};
};

/// OSPRay's `mesh`, `sphere` and `curve` geometry; exactly one of mesh(), spheres() and
/// curves() is set once committed, according to the subtype.
class Geometry : public Object {
public:
  explicit Geometry(std::string type) : Object(OSP_GEOMETRY, std::move(type)) {}
  /// The mesh data as committed (owned, padded for Embree), or null.
  const std::shared_ptr<const MeshData>& mesh() const { return mesh_; }
  /// The spheres as committed (owned, padded), or null; with their type and intersector.
  const std::shared_ptr<const SphereData>& spheres() const { return spheres_; }
  SphereType sphere_type() const { return sphere_type_; }
  SphereIntersector sphere_intersector() const { return sphere_intersector_; }
  /// The curves as committed (owned, padded), or null.
  const std::shared_ptr<const CurveData>& curves() const { return curves_; }
  /// Faces, spheres or curve segments: what a model's per-primitive `color` indexes.
  std::size_t primitive_count() const { return primitive_count_; }
  Box3f bounds() const { return bounds_; }

protected:
  void on_commit() override;

private:
  void commit_mesh();
  void commit_spheres();
  void commit_curves();

  std::shared_ptr<const MeshData> mesh_;
  std::shared_ptr<const SphereData> spheres_;
  SphereType sphere_type_ = SphereType::sphere;
  SphereIntersector sphere_intersector_ = SphereIntersector::sciray;
  std::shared_ptr<const CurveData> curves_;
  std::size_t primitive_count_ = 0;
  Box3f bounds_;
};

class GeometricModel : public Object {
public:
  GeometricModel() : Object(OSP_GEOMETRIC_MODEL, "") {}
  Geometry* geometry() const { return geometry_.get(); }
  /// The material's `kd`, if the model has a material.
  std::optional<Vec3f> material_color() const;
  /// Per-primitive colours (RGBA), or empty.
  const PaddedVector<float>& face_colors() const { return face_colors_; }
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  Ref<Geometry> geometry_;
  Ref<Material> material_;
  PaddedVector<float> face_colors_;
};

class Group : public Object {
public:
  Group() : Object(OSP_GROUP, "") {}
  const std::vector<Ref<GeometricModel>>& models() const { return models_; }
  Box3f bounds() const;
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  std::vector<Ref<GeometricModel>> models_;
};

/// An affine transform as OSPRay stores it: linear part columns vx, vy, vz, then p.
struct Affine {
  Vec3f vx{1, 0, 0}, vy{0, 1, 0}, vz{0, 0, 1}, p{0, 0, 0};
  bool identity() const {
    return vx == Vec3f{1, 0, 0} && vy == Vec3f{0, 1, 0} && vz == Vec3f{0, 0, 1} && p == Vec3f{0, 0, 0};
  }
  Vec3f point(const Vec3f& x) const { return vx * x.x + vy * x.y + vz * x.z + p; }
  Vec3f vector(const Vec3f& x) const { return vx * x.x + vy * x.y + vz * x.z; }
  /// Transforms normals: the inverse transpose of the linear part (up to scale).
  Vec3f normal(const Vec3f& n) const {
    return cross(vy, vz) * n.x + cross(vz, vx) * n.y + cross(vx, vy) * n.z;
  }
};

class Instance : public Object {
public:
  Instance() : Object(OSP_INSTANCE, "") {}
  Group* group() const { return group_.get(); }
  const Affine& transform() const { return transform_; }
  Box3f bounds() const;
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  Ref<Group> group_;
  Affine transform_;
};

class Light : public Object {
public:
  explicit Light(std::string type) : Object(OSP_LIGHT, std::move(type)) {}
  Vec3f color() const { return color_; }
  float intensity() const { return intensity_; }
  Vec3f direction() const { return direction_; }

protected:
  void on_commit() override;

private:
  Vec3f color_{1.f, 1.f, 1.f};
  float intensity_ = 1.f;
  Vec3f direction_{0.f, 0.f, 1.f};
};

/// The engine's form of a committed world: every (instance, model) pair as one geometry
/// of a flat sciray world, rebuilt when anything the world uses is recommitted or when it
/// is rendered with another ISA's kernels (sciray's own intersectors are per ISA).
struct BuiltWorld {
  std::shared_ptr<accel::Device> device;
  /// Arrays the world's geometries read in place (declared before `world`, which is
  /// destroyed first).
  std::vector<std::shared_ptr<const void>> keep_alive;
  std::unique_ptr<shim::EngineWorld> world;
  /// The kernels the world was committed with; frames and picks trace with them.
  const shim::IsaKernels* kernels = nullptr;
  struct Origin {
    Ref<Instance> instance;
    Ref<GeometricModel> model;
  };
  std::vector<Origin> origins;  ///< by sciray geometry id
  SciVisParams lights;          ///< light part of the scivis parameters
  std::uint64_t version = 0;
};

class World : public Object {
public:
  World() : Object(OSP_WORLD, "") {}
  /// The engine world for the current commits of everything this world uses, committed
  /// through `kernels` (the rendering device's ISA).
  std::shared_ptr<const BuiltWorld> built(const shim::IsaKernels& kernels, std::vector<std::string>& warnings);
  Box3f bounds() const;
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  std::vector<Ref<Instance>> instances_;
  std::vector<Ref<Light>> lights_;
  std::mutex build_mutex_;
  std::shared_ptr<const BuiltWorld> built_;
};

class Renderer : public Object {
public:
  explicit Renderer(std::string type) : Object(OSP_RENDERER, std::move(type)) {}
  std::array<float, 4> background() const { return background_; }

protected:
  void on_commit() override;

private:
  std::array<float, 4> background_{0.f, 0.f, 0.f, 0.f};
};

}  // namespace sciray::ospray
