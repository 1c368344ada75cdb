#pragma once
// OSPRay's scene objects over sciray types: cameras, geometry (mesh, sphere, curve, box,
// plane, isosurface), geometric models, volumes (structuredRegular), transfer functions
// (piecewiseLinear), volumetric models, textures (volume), groups, instances, worlds,
// lights, materials and renderers. Each reads its committed parameters in on_commit and names the parameter
// when one is wrong.
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <variant>
#include <vector>

#include "data.hpp"
#include "sciray/geometry/boxes.hpp"
#include "sciray/geometry/curves.hpp"
#include "sciray/geometry/isosurface.hpp"
#include "sciray/geometry/slice.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/render/scivis.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/volume/structured_regular.hpp"
#include "sciray/volume/transfer_function.hpp"
#include "sciray/volume/volumetric_model.hpp"

namespace sciray::ospray {

namespace detail {
template <class W>
struct VolumeTypesOf;
/// The engine volume types the shim's world is composed with, as variants.
template <class WorldT, class... Volumes>
struct VolumeTypesOf<VolumeWorld<WorldT, Volumes...>> {
  using Volume = std::variant<std::monostate, std::shared_ptr<const Volumes>...>;
  using Model = std::variant<std::monostate, VolumetricModel<Volumes>...>;
};
}  // namespace detail

/// A committed volume: one of the engine's volume types (every voxel type, linear or
/// bricked), shared by the volumetric models that use it.
using EngineVolume = detail::VolumeTypesOf<shim::EngineWorld>::Volume;
/// A volumetric model of one of the engine's volume types.
using EngineVolumetricModel = detail::VolumeTypesOf<shim::EngineWorld>::Model;

/// OSPRay's `perspective` (with depth of field and stereo), `orthographic` and
/// `panoramic` (with stereo) cameras.
class CameraObject : public Object {
public:
  explicit CameraObject(std::string type) : Object(OSP_CAMERA, std::move(type)) {}
  const sciray::Camera& camera() const { return camera_; }

protected:
  void on_commit() override;

private:
  sciray::Camera camera_;
};

/// OSPRay's `structuredRegular` volume: a regular grid of uchar, short, ushort, float or
/// double voxels, read in place from its `data` array where the array is compact (and
/// `layout` is "linear"), otherwise copied.
class VolumeObject : public Object {
public:
  explicit VolumeObject(std::string type) : Object(OSP_VOLUME, std::move(type)) {}
  /// The engine volume as committed (monostate before the first commit).
  const EngineVolume& volume() const { return volume_; }
  /// Whether the last commit reads the application's array in place (no copy).
  bool zero_copy() const { return zero_copy_; }
  Box3f bounds() const { return bounds_; }

protected:
  void on_commit() override;

private:
  const Data& required_data(const char* id, std::initializer_list<OSPDataType> types, const char* what) const;
  /// An OSP_VOLUME_FILTER_* parameter.
  VolumeFilter filter_param(const char* id, VolumeFilter fallback) const;
  EngineVolume commit_structured_regular(bool& zero_copy);
  EngineVolume commit_unstructured();
  EngineVolume commit_particle();
  EngineVolume commit_structured_spherical();
  EngineVolume commit_vdb();
  EngineVolume commit_amr();

  EngineVolume volume_;
  bool zero_copy_ = false;
  Box3f bounds_;
};

/// OSPRay's `piecewiseLinear` transfer function: `color`, `opacity` and `value`.
class TransferFunctionObject : public Object {
public:
  explicit TransferFunctionObject(std::string type) : Object(OSP_TRANSFER_FUNCTION, std::move(type)) {}
  /// As committed, or null before the first commit.
  const std::shared_ptr<const TransferFunction>& transfer_function() const { return tf_; }

protected:
  void on_commit() override;

private:
  std::shared_ptr<const TransferFunction> tf_;
};

/// What a world build did with its volumetric models (for the debug summary).
struct VolumeBuildStats {
  std::size_t volumes = 0;               ///< models placed (each once, however many instances place it)
  std::size_t macrocells_built = 0;      ///< models rebuilt for a recommitted volume
  std::size_t transfer_functions = 0;    ///< models given a recommitted transfer function
};

/// OSPRay's volumetric model: `volume`, `transferFunction`, `densityScale`, `anisotropy`
/// (the path tracer's Henyey–Greenstein g). Its engine
/// model (with the volume's macrocell value ranges) is built at commit and kept: a
/// recommitted transfer function only re-derives the macrocells' opacities.
class VolumetricModelObject : public Object {
public:
  VolumetricModelObject() : Object(OSP_VOLUMETRIC_MODEL, "") {}
  VolumeObject* volume() const { return volume_.get(); }
  TransferFunctionObject* transfer_function() const { return transfer_function_.get(); }
  float density_scale() const { return density_scale_; }
  /// `id`: what the object id channel shows in place of the model's index in its group.
  std::optional<std::uint32_t> user_id() const { return user_id_; }
  Box3f bounds() const { return volume_ ? volume_->bounds() : Box3f{}; }
  std::uint64_t version() const override;
  /// The engine model for the current commits of the volume and the transfer function:
  /// rebuilt when the volume was recommitted, given the new transfer function (keeping
  /// the macrocell ranges) when only that was. A copy, so frames in flight keep theirs.
  EngineVolumetricModel engine_model(VolumeBuildStats& stats);

protected:
  void on_commit() override;

private:
  Ref<VolumeObject> volume_;
  Ref<TransferFunctionObject> transfer_function_;
  float density_scale_ = 1.f;
  float anisotropy_ = 0.f;
  float gradient_shading_scale_ = 0.f;
  std::optional<std::uint32_t> user_id_;
  std::mutex mutex_;  ///< guards the engine model, which world builds refresh
  EngineVolumetricModel model_;
  std::uint64_t model_volume_version_ = 0;  ///< the volume commit the model was built from
  std::uint64_t model_tf_version_ = 0;      ///< the transfer function commit it shows
};

/// An image derived from a texture's data at its first use after a commit (a normal
/// map's raw texels, the alpha channel), so that textures that never need it keep no second
/// copy of their texels. Safe to use from concurrent commits.
class DerivedImage {
public:
  void reset(std::function<std::shared_ptr<const Texture2D>()> source) {
    const std::lock_guard lock(mutex_);
    source_ = std::move(source);
    image_.reset();
  }
  /// Null where the texture has no such image.
  std::shared_ptr<const Texture2D> get() const {
    const std::lock_guard lock(mutex_);
    if (!image_ && source_) image_ = source_();
    return image_;
  }

private:
  std::function<std::shared_ptr<const Texture2D>()> source_;
  mutable std::mutex mutex_;
  mutable std::shared_ptr<const Texture2D> image_;
};

/// OSPRay's `volume` texture: a transfer function colours the points of a surface by a
/// volume's value there. OSPRay 3 gives `volume` (an OSPVolume) and `transferFunction`;
/// OSPRay 2 gave `volume` as a volumetric model, whose transfer function it took. As a
/// material's `map_kd` it turns plane geometry into slices (the engine's VolumeSlice).
/// And OSPRay's `texture2d`: an image (`data`, a 2D array in `format`), used by lights
/// (`hdri` map), renderers (`map_backplate`, `map_maxDepth`) and materials' maps.
class TextureObject : public Object {
public:
  explicit TextureObject(std::string type) : Object(OSP_TEXTURE, std::move(type)) {}
  bool is_volume_texture() const { return model_ || volume_; }
  /// A volume texture's volume and transfer function as currently committed (through its
  /// volumetric model in OSPRay 2's form); null for a texture2d.
  VolumeObject* sampled_volume() const { return model_ ? model_->volume() : volume_.get(); }
  TransferFunctionObject* transfer_function() const {
    return model_ ? model_->transfer_function() : transfer_function_.get();
  }
  /// The image of a texture2d (null for a volume texture).
  const std::shared_ptr<const Texture2D>& image() const { return image_; }
  /// The image as a normal map's texels (normal_map_texel) from the raw channels; null for
  /// formats of one or two channels, which OSPRay's normal maps ignore.
  std::shared_ptr<const Texture2D> normal_image() const { return normal_image_.get(); }
  /// A texture2d's alpha channel as grey texels; null for formats without alpha.
  std::shared_ptr<const Texture2D> alpha_image() const { return alpha_image_.get(); }
  /// Also counts the commits of a volume texture's volume and transfer function (or model).
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  void commit_texture2d();

  Ref<VolumetricModelObject> model_;  ///< OSPRay 2's form
  Ref<VolumeObject> volume_;          ///< OSPRay 3's form, with transfer_function_
  Ref<TransferFunctionObject> transfer_function_;
  std::shared_ptr<const Texture2D> image_;
  DerivedImage normal_image_, alpha_image_;
};

/// The `kd` an obj material has where none is given (OSPRay's default), which is also
/// what the renderer shows on surfaces without colours.
inline constexpr float default_kd = 0.8f;

class Material : public Object {
public:
  explicit Material(std::string type) : Object(OSP_MATERIAL, std::move(type)) {}
  /// The engine material for the committed parameters, its maps showing their textures'
  /// current images.
  sciray::Material material() const;
  /// The colour geometries bake into their own colours (obj `kd`, principled `baseColor`),
  /// none for materials whose colour is not a plain diffuse tint.
  std::optional<Vec3f> base_color() const;
  /// material() with another base colour: white for geometries that baked it in, or the
  /// base colour tinted by a model's colour.
  sciray::Material with_base_color(const Vec3f& color) const;
  /// `map_kd` where it is a volume texture (whose colour multiplies kd), or null.
  TextureObject* volume_map_kd() const { return volume_map_kd_.get(); }
  /// Where the volume texture samples a point of the surface (its affine3f `map_kd.transform`).
  const Affine3f& volume_map_transform() const { return volume_map_transform_; }
  /// Also counts the textures' commits, and a mix's parts'.
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  /// A mix's `material1` and `material2`, checked: committed (a mix containing itself is a
  /// cycle of references, which set_param refuses).
  Ref<Material> mix_part(const std::string& id) const;

  /// A texture2d map: the material's map `name` shows `texture` through `transform`.
  struct ImageMap {
    std::string name;
    Ref<TextureObject> texture;
    TexCoordTransform transform;
  };
  TexCoordTransform map_transform(const std::string& map) const;
  Affine3f volume_transform(const std::string& map) const;

  sciray::Material material_;  ///< the parameters; maps are filled in by material()
  Ref<TextureObject> volume_map_kd_;
  Affine3f volume_map_transform_;
  std::vector<ImageMap> image_maps_;
  Ref<Material> material1_, material2_;  ///< a mix's parts, whose current material() material() mixes
};

/// The primitives of OSPRay's `box` geometry, as committed.
struct BoxData {
  std::vector<Box3f> boxes;
};

/// The primitives of OSPRay's `plane` geometry, as committed: coefficients, and one
/// bounding box per plane or none.
struct PlaneData {
  std::vector<Planes::Plane> planes;
  std::vector<Box3f> bounds;
};

/// OSPRay's `mesh`, `sphere`, `curve`, `box`, `plane`, `isosurface` and `subdivision`
/// geometry; exactly one of mesh(), spheres(), curves(), boxes(), planes(),
/// isosurface_volume() and subdivision() is set once committed, according to the subtype.
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
  /// The boxes as committed, or null.
  const std::shared_ptr<const BoxData>& boxes() const { return boxes_; }
  /// The planes as committed, or null.
  const std::shared_ptr<const PlaneData>& planes() const { return planes_; }
  /// The subdivision surface as committed, or null.
  const std::shared_ptr<const SubdivisionData>& subdivision() const { return subdivision_; }
  /// An isosurface's volume (as the geometry's `volume`), or null for other geometry.
  VolumeObject* isosurface_volume() const { return iso_volume_.get(); }
  /// The isosurface over the volume's current commit (rebuilt when the volume was
  /// recommitted since), or null for other geometry.
  std::shared_ptr<const Isosurface> isosurface();
  /// The index of the isovalue nearest the volume's value at `p` (in the geometry's
  /// space): which of an isosurface's surfaces a hit at p lies on, OSPRay's primID.
  std::uint32_t isovalue_index(const Vec3f& p) const;
  /// Faces, spheres, curve segments, boxes, planes or isovalues: what a model's
  /// per-primitive `color` indexes.
  std::size_t primitive_count() const { return primitive_count_; }
  /// An isosurface's are its volume's current bounds.
  Box3f bounds() const;
  /// An isosurface's also counts its volume's commits.
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  void commit_mesh();
  void commit_spheres();
  void commit_curves();
  void commit_boxes();
  void commit_planes();
  void commit_isosurface();
  void commit_subdivision();

  std::shared_ptr<const MeshData> mesh_;
  std::shared_ptr<const SphereData> spheres_;
  SphereType sphere_type_ = SphereType::sphere;
  SphereIntersector sphere_intersector_ = SphereIntersector::sciray;
  std::shared_ptr<const CurveData> curves_;
  std::shared_ptr<const BoxData> boxes_;
  std::shared_ptr<const PlaneData> planes_;
  std::shared_ptr<const SubdivisionData> subdivision_;
  Ref<VolumeObject> iso_volume_;
  std::vector<float> isovalues_;
  std::mutex iso_mutex_;  ///< guards the isosurface, which world builds refresh
  std::shared_ptr<const Isosurface> isosurface_;
  std::uint64_t isosurface_volume_version_ = 0;  ///< the volume commit it was built from
  std::size_t primitive_count_ = 0;
  Box3f bounds_;
};

class GeometricModel : public Object {
public:
  GeometricModel() : Object(OSP_GEOMETRIC_MODEL, "") {}
  Geometry* geometry() const { return geometry_.get(); }
  /// The material of every primitive, where `material` is one OSPMaterial (else null).
  Material* material() const { return material_.get(); }
  /// Where `material` names the renderer's materials (`uint` indices into its `material`
  /// list) or gives one per primitive: each primitive's choice (one element for all).
  struct MaterialChoice {
    Ref<Material> object;          ///< the material, or null for a renderer index
    std::uint32_t renderer_index;  ///< index into the renderer's list where object is null
  };
  const std::vector<MaterialChoice>& material_choices() const { return material_choices_; }
  /// The material's `kd`, if the model has a material.
  std::optional<Vec3f> material_color() const;
  /// The colour the model gives all of its primitives (one `color`), overriding the
  /// geometry's own colours, times the material's `kd`; none without one `color`.
  std::optional<Vec3f> uniform_color() const;
  /// The alpha of the one `color` (1 without one).
  float uniform_alpha() const { return uniform_color_ ? (*uniform_color_)[3] : 1.f; }
  /// material_color(), or uniform_color() where the model has one `color`: what
  /// multiplies (or, with no colours of their own, is) the primitives' colours.
  std::optional<Vec3f> tint() const { return uniform_color_ ? uniform_color() : material_color(); }
  /// The material's `map_kd` when it is a volume texture, or null.
  TextureObject* volume_texture() const;
  /// Per-primitive colours (RGBA), or empty (also where one `color` is for all).
  const PaddedVector<float>& face_colors() const { return face_colors_; }
  /// `invertNormals`: as clipping geometry, the model clips its outside instead of its
  /// inside (shading is two-sided, so it changes nothing else).
  bool invert_normals() const { return invert_normals_; }
  /// `id`: what the object id channel shows in place of the model's index in its group.
  std::optional<std::uint32_t> user_id() const { return user_id_; }
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  Ref<Geometry> geometry_;
  Ref<Material> material_;
  std::vector<MaterialChoice> material_choices_;
  PaddedVector<float> face_colors_;
  /// One `color` (RGBA) for all primitives; its alpha is below 1 only on curves.
  std::optional<std::array<float, 4>> uniform_color_;
  bool invert_normals_ = false;
  std::optional<std::uint32_t> user_id_;
};

class Light : public Object {
public:
  explicit Light(std::string type) : Object(OSP_LIGHT, std::move(type)) {}
  /// The engine lights for the committed parameters: one, or for `sunSky` the sky and
  /// the sun.
  const std::vector<sciray::Light>& lights() const { return lights_; }

protected:
  void on_commit() override;

private:
  /// The photometric table `intensityDistribution` (a 1D or 2D float array), if set.
  IntensityDistribution read_distribution() const;
  /// The engine sky and sun of a `sunSky` light.
  std::vector<sciray::Light> sun_sky() const;

  std::vector<sciray::Light> lights_;
};

class Group : public Object {
public:
  Group() : Object(OSP_GROUP, "") {}
  /// `geometry`: the models the group renders.
  const std::vector<Ref<GeometricModel>>& models() const { return models_; }
  /// `volume`: the volumetric models the group renders (placed directly in the engine
  /// world, so only by instances with the identity transform).
  const std::vector<Ref<VolumetricModelObject>>& volumes() const { return volumes_; }
  /// `clippingGeometry`: models whose geometry, placed by each instance of the group,
  /// clips the whole world; they are not rendered (unless also in `geometry`).
  const std::vector<Ref<GeometricModel>>& clipping_models() const { return clipping_models_; }
  /// `light`: lights placed by every instance of the group (transformed by it).
  const std::vector<Ref<Light>>& lights() const { return lights_; }
  /// The bounds of the rendered models and volumes (clipping geometry adds nothing).
  Box3f bounds() const;
  /// Also counts the clipping models and the volumes: a world rebuilds when one is
  /// recommitted.
  std::uint64_t version() const override;
  /// What the group's engine form (its BVH) depends on: the group and its rendered
  /// models, not its clipping models.
  std::uint64_t geometry_version() const;
  /// `compactMode`, `dynamicScene`: how its BVH is laid out and built.
  const BvhSettings& bvh() const { return bvh_; }

protected:
  void on_commit() override;

private:
  std::vector<Ref<GeometricModel>> models_;
  std::vector<Ref<GeometricModel>> clipping_models_;
  std::vector<Ref<VolumetricModelObject>> volumes_;
  std::vector<Ref<Light>> lights_;
  BvhSettings bvh_;
};

class Instance : public Object {
public:
  Instance() : Object(OSP_INSTANCE, "") {}
  Group* group() const { return group_.get(); }
  /// `transform`, or the keys of `motion.*` over `time`.
  const MotionTransform& placement() const { return placement_; }
  /// Around the group wherever its placement puts it.
  Box3f bounds() const;
  /// `id`: what the instance id channel shows in place of the instance's index.
  std::optional<std::uint32_t> user_id() const { return user_id_; }
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  Ref<Group> group_;
  MotionTransform placement_;
  std::optional<std::uint32_t> user_id_;
};


/// The engine's form of one OSPRay group: one engine group holding a geometry per model
/// (geometry id = index of the model in the group), built once and shared by every
/// instance of the group. A world keeps it across rebuilds while the group's version and
/// the kernels are unchanged.
struct BuiltGroup {
  /// The Embree device the group was built on (outlives everything below).
  std::shared_ptr<accel::Device> device;
  /// Arrays the group's geometries read in place (destroyed after `group`).
  std::vector<std::shared_ptr<const void>> keep_alive;
  /// Null when the group has no geometry: its instances contribute nothing.
  std::shared_ptr<shim::EngineWorld::GroupType> group;
  std::vector<Ref<GeometricModel>> models;  ///< by engine geometry id
  Ref<Group> source;
  std::uint64_t version = 0;
  /// The kernels the group was committed with (sciray's intersectors are per ISA).
  const shim::IsaKernels* kernels = nullptr;
};

/// The engine's form of a committed world: an engine world with one Embree instance per
/// OSPRay instance of a group with geometry, over the groups' shared BVHs, clipped by
/// the clipping geometry of every instance's group (placed by the instance), plus a copy
/// of the engine model of every volume of every instance's group (placed directly).
/// Rebuilt (the top level only, and the groups that changed) when anything the world
/// uses is recommitted, or when it is rendered with another ISA's kernels.
struct BuiltWorld {
  std::shared_ptr<accel::Device> device;
  /// The groups the world's instances place (declared before `world`, which is
  /// destroyed first).
  std::vector<std::shared_ptr<const BuiltGroup>> groups;
  std::unique_ptr<shim::EngineWorld> world;
  /// The kernels the world was committed with; frames and picks trace with them.
  const shim::IsaKernels* kernels = nullptr;
  struct PlacedInstance {
    Ref<Instance> instance;
    std::size_t group;  ///< index into `groups`
  };
  std::vector<PlacedInstance> instances;  ///< by engine instance index
  std::vector<sciray::Light> lights;
  std::vector<sciray::MovingLight> moving_lights;  ///< of groups in moving instances
  std::vector<sciray::Material> materials;  ///< what the geometries' material indices name
  /// Entries of `materials` that are the renderer's: its `material` list's element
  /// `index`, tinted by a model's colour (isosurfaces) where given.
  struct RendererMaterial {
    std::size_t entry;
    std::uint32_t index;
    std::optional<Vec3f> tint;
  };
  std::vector<RendererMaterial> renderer_materials;
  std::uint64_t version = 0;

  struct Origin {
    Instance* instance;
    GeometricModel* model;
  };
  /// The OSPRay instance and model of a hit (its top-level inst_id and geom_id).
  Origin origin(std::int32_t inst_id, std::int32_t geom_id) const;
};

/// What a world build reports: warnings for the application, and a summary at debug
/// level (instances, groups built and reused, and the engine's memory when asked for).
struct BuildLog {
  bool want_memory = false;
  std::vector<std::string> warnings;
  std::vector<std::string> debug;
};

class World : public Object {
public:
  World() : Object(OSP_WORLD, "") {}
  /// The engine world for the current commits of everything this world uses, committed
  /// through `kernels` (the rendering device's ISA).
  std::shared_ptr<const BuiltWorld> built(const shim::IsaKernels& kernels, BuildLog& log);
  Box3f bounds() const;
  /// `region`: the boxes of the world this rank owns (mpiDistributed); empty if not set.
  const std::vector<Box3f>& regions() const { return regions_; }
  std::uint64_t version() const override;

protected:
  void on_commit() override;

private:
  std::shared_ptr<const BuiltGroup> build_group(Group& group, const shim::IsaKernels& kernels);
  /// The engine material index of `material` (no_material for none), as baked (base colour
  /// in the geometry's colours) or not. Indices stay valid across builds, so that cached
  /// groups keep theirs.
  std::uint32_t material_index(Material* material, bool baked, const std::optional<Vec3f>& tint = std::nullopt,
                               std::optional<std::uint32_t> renderer_index = std::nullopt);
  /// The clipping geometry of every instance's group, placed by the instance, in world
  /// space; null when there is none.
  std::shared_ptr<Clipping> build_clipping() const;

  std::vector<Ref<Instance>> instances_;
  std::vector<Ref<Light>> lights_;
  std::vector<Box3f> regions_;
  BvhSettings bvh_;  ///< `compactMode`, `dynamicScene` of the top-level BVH
  struct MaterialEntry {
    Ref<Material> material;
    bool baked;
    std::optional<Vec3f> tint;  ///< multiplies the base colour (a model's one `color`)
    std::optional<std::uint32_t> renderer_index;  ///< the renderer's material of this index, where material is null
  };
  std::vector<MaterialEntry> materials_;
  std::mutex build_mutex_;
  /// One Embree device for all of this world's builds, so that unchanged groups carry over.
  std::shared_ptr<accel::Device> device_;
  /// The groups of the last successful build, by OSPRay group.
  std::map<const Group*, std::shared_ptr<const BuiltGroup>> group_cache_;
  std::shared_ptr<const BuiltWorld> built_;
};

/// OSPRay's renderers `scivis`, `ao` and `pathtracer` with their parameters; the world
/// supplies lights and materials at each frame.
class Renderer : public Object {
public:
  explicit Renderer(std::string type) : Object(OSP_RENDERER, std::move(type)) {}
  /// The engine renderer for `world`'s lights and materials.
  shim::RendererConfig config(const BuiltWorld& world) const;
  const FrameSettings& frame_settings() const { return settings_; }

protected:
  void on_commit() override;

private:
  shim::RendererConfig config_;
  FrameSettings settings_;
  std::vector<Ref<Material>> materials_;  ///< `material`: what models' material indices name
};

}  // namespace sciray::ospray
