#pragma once
// Group<Geometries...> and World<Geometries...>: the compile-time set of geometry types a
// scene uses, and Embree scenes over them. A program that renders only meshes
// instantiates World<TriangleMesh> and compiles no code for other types.
//
// A world holds geometries placed directly, and instances: a shared Group (its own BVH,
// built once) placed by an affine transform through Embree's instancing, so 10,000
// instances of a 1M-triangle group cost one copy of the group plus a small top-level BVH.
// An instance may move: its transform is then keyed over time (math/motion.hpp) and
// Embree places it at each ray's time.
//
// Neither is templated on the SIMD architecture, because Embree's build is
// ISA-independent; `commit<Arch>` only tells geometries with sciray's own intersectors
// which compiled packet code to register. Renderers, which run per ray, take Arch.
#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <tuple>
#include <unordered_set>
#include <vector>

#include "sciray/accel/embree.hpp"
#include "sciray/accel/trace.hpp"
#include "sciray/error.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/motion.hpp"
#include "sciray/render/material.hpp"
#include "sciray/scene/clipping.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

/// What a group needs of a geometry type. `create_embree_geometry<Arch>` may register
/// sciray's own intersectors (compiled for Arch) with Embree, so the geometry's address
/// must not change while the scene exists: groups keep geometries in deques.
template <class G>
concept Geometry = requires(const G& g, const accel::Device& device) {
  { g.validate() } -> std::same_as<void>;
  { g.bounds() } -> std::same_as<Box3f>;
  { g.owned_bytes() } -> std::convertible_to<std::size_t>;
  { g.template create_embree_geometry<simd::scalar>(device) } -> std::same_as<RTCGeometry>;
};

/// How Embree lays out and builds a group's or world's BVH: OSPRay's group and world
/// parameters `compactMode` and `dynamicScene`. The default is the fastest to traverse;
/// docs/performance.md charts what each choice costs and saves.
struct BvhSettings {
  /// RTC_SCENE_FLAG_COMPACT: leaves index the mesh's vertices instead of holding copies of
  /// them (a 5M-triangle mesh: 46 % less peak memory, a 40 % faster build, 22 % slower
  /// primary rays).
  bool compact = false;
  /// RTC_SCENE_FLAG_DYNAMIC and Embree's low build quality, for geometry rebuilt every
  /// frame: quicker builds up to a few million triangles, 60 % more memory.
  bool dynamic = false;
  bool operator==(const BvhSettings&) const = default;
};

template <Geometry... Geometries>
class Group {
public:
  explicit Group(const accel::Device& device) : device_(&device), scene_(device) {}

  /// Adds a geometry shaded with entry `material` of the renderer's material list (or, with
  /// no_material, in its own colours); returns its id, which hits report as geom_id.
  /// Takes effect at commit.
  template <class G>
  std::uint32_t add(G geometry, std::uint32_t material = no_material) {
    return add(std::move(geometry), material, {});
  }
  /// add() with a material per primitive (OSPRay's material lists): primitive p is shaded
  /// with entry primitive_materials[p]; empty for `material` on all.
  template <class G>
  std::uint32_t add(G geometry, std::uint32_t material, std::vector<std::uint32_t> primitive_materials) {
    static_assert((std::is_same_v<G, Geometries> || ...), "the group was not composed with this geometry type");
    auto& list = std::get<std::deque<G>>(geometries_);
    std::shared_ptr<const std::vector<std::uint32_t>> per_primitive;
    if (!primitive_materials.empty())
      per_primitive = std::make_shared<const std::vector<std::uint32_t>>(std::move(primitive_materials));
    const auto id = static_cast<std::uint32_t>(refs_.size());
    refs_.push_back({type_index<G>(), static_cast<std::uint32_t>(list.size()), material, std::move(per_primitive), id});
    list.push_back(std::move(geometry));
    committed_ = false;
    return static_cast<std::uint32_t>(refs_.size() - 1);
  }

  /// Validates every geometry and builds the group's BVH.
  template <class Arch = xsimd::default_arch>
  void commit() {
    accel::Scene scene(*device_);
    configure(scene);
    bounds_ = {};
    attach_geometries<Arch>(scene.get(), 0);
    scene.commit();
    scene_ = std::move(scene);
    committed_ = true;
  }

  /// Robust traversal (the default) or Embree's faster-in-theory default mode; takes
  /// effect at the next commit.
  void set_robust(bool robust) { robust_ = robust; }

  /// The BVH's layout and build (BvhSettings); takes effect at the next commit.
  void set_bvh(const BvhSettings& settings) {
    if (!(settings == bvh_)) bvh_ = settings, committed_ = false;
  }
  const BvhSettings& bvh() const { return bvh_; }

  /// Whether queries may carry a context filter (clipping); a world with clipping sets it
  /// on its groups. Takes effect at the next commit.
  void set_context_filter(bool enabled) {
    if (enabled != context_filter_) context_filter_ = enabled, committed_ = false;
  }
  bool context_filter() const { return context_filter_; }

  bool committed() const { return committed_; }
  RTCScene scene() const { return scene_.get(); }
  const accel::Device& device() const { return *device_; }
  Box3f bounds() const { return bounds_; }
  std::size_t geometry_count() const { return refs_.size(); }

  /// Calls f(geometry) with the concrete geometry of id `id`.
  template <class F>
  decltype(auto) visit(std::uint32_t id, F&& f) const {
    return visit_type<0>(refs_.at(id), std::forward<F>(f));
  }

  /// The material index geometry `id` was added with.
  std::uint32_t material(std::uint32_t id) const { return refs_.at(id).material; }

  /// What the object id channel shows for geometry `id`: `object_id` in place of its id
  /// (OSPRay's geometric model `id`). Takes effect at the world's commit.
  void set_object_id(std::uint32_t id, std::uint32_t object_id) {
    refs_.at(id).object_id = object_id;
    user_object_ids_ = true;
  }
  /// The id channel's object id of geometry `id`: its id unless set_object_id gave another.
  std::uint32_t object_id(std::uint32_t id) const { return refs_.at(id).object_id; }
  /// Whether some geometry's object id differs from its id.
  bool user_object_ids() const { return user_object_ids_; }
  /// Geometry `id`'s material per primitive, or null where it has one for all.
  const std::vector<std::uint32_t>* primitive_materials(std::uint32_t id) const {
    return refs_.at(id).primitive_materials.get();
  }
  /// How many materials the geometries need: one more than the largest index used.
  std::uint32_t materials_needed() const {
    std::uint32_t n = 0;
    const auto use = [&](std::uint32_t m) {
      if (m != no_material) n = std::max(n, m + 1);
    };
    for (const Ref& r : refs_) {
      use(r.material);
      if (r.primitive_materials)
        for (std::uint32_t m : *r.primitive_materials) use(m);
    }
    return n;
  }

  /// Whether any geometry shows colours with alpha below 1, which renderers take as
  /// opacity (so that shadow rays look at what they pass).
  bool translucent_colors() const {
    bool any = false;
    std::apply([&](const auto&... lists) { ((any = any || translucent_colors(lists)), ...); }, geometries_);
    return any;
  }

  template <class G>
  const std::deque<G>& all() const {
    return std::get<std::deque<G>>(geometries_);
  }

  /// Bytes of geometry data sciray owns (Embree's share is counted by the device).
  std::size_t owned_bytes() const {
    std::size_t bytes = 0;
    std::apply([&](const auto&... lists) { ((bytes += owned_bytes(lists)), ...); }, geometries_);
    return bytes;
  }

protected:
  void configure(accel::Scene& scene) const {
    // Embree's default traversal lets rays exactly through a shared edge slip between the
    // two triangles (tests/stability); robust mode closes edges at no measured cost.
    rtcSetSceneFlags(scene.get(), (robust_ ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
                                      (context_filter_ ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_NONE) |
                                      (bvh_.compact ? RTC_SCENE_FLAG_COMPACT : RTC_SCENE_FLAG_NONE) |
                                      (bvh_.dynamic ? RTC_SCENE_FLAG_DYNAMIC : RTC_SCENE_FLAG_NONE));
    rtcSetSceneBuildQuality(scene.get(), bvh_.dynamic ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM);
  }

  /// Attaches every geometry to `scene` with ids first_id, first_id + 1, ...
  template <class Arch>
  void attach_geometries(RTCScene scene, std::uint32_t first_id) {
    for (std::uint32_t id = 0; id < refs_.size(); ++id) {
      visit(id, [&](const auto& geometry) {
        geometry.validate();
        RTCGeometry g = geometry.template create_embree_geometry<Arch>(*device_);
        rtcAttachGeometryByID(scene, g, first_id + id);
        rtcReleaseGeometry(g);
        device_->check("rtcAttachGeometryByID");
        bounds_.extend(geometry.bounds());
      });
    }
  }

  const accel::Device* device_;
  accel::Scene scene_;
  Box3f bounds_;
  bool committed_ = false;
  bool user_object_ids_ = false;
  bool context_filter_ = false;
  BvhSettings bvh_;

private:
  struct Ref {
    std::uint8_t type;
    std::uint32_t index;
    std::uint32_t material;
    std::shared_ptr<const std::vector<std::uint32_t>> primitive_materials;
    std::uint32_t object_id;  ///< what the object id channel shows
  };

  template <class G, std::size_t I = 0>
  static constexpr std::uint8_t type_index() {
    using Tuple = std::tuple<Geometries...>;
    if constexpr (std::is_same_v<G, std::tuple_element_t<I, Tuple>>)
      return I;
    else
      return type_index<G, I + 1>();
  }

  template <std::size_t I, class F>
  decltype(auto) visit_type(const Ref& ref, F&& f) const {
    using G = std::tuple_element_t<I, std::tuple<Geometries...>>;
    if constexpr (I + 1 == sizeof...(Geometries)) {
      return f(std::get<std::deque<G>>(geometries_)[ref.index]);
    } else {
      if (ref.type == I) return f(std::get<std::deque<G>>(geometries_)[ref.index]);
      return visit_type<I + 1>(ref, std::forward<F>(f));
    }
  }

  template <class G>
  static bool translucent_colors(const std::deque<G>& list) {
    if constexpr (requires(const G& g) { g.translucent_colors(); })
      for (const auto& g : list)
        if (g.translucent_colors()) return true;
    return false;
  }

  template <class G>
  static std::size_t owned_bytes(const std::deque<G>& list) {
    std::size_t bytes = 0;
    for (const auto& g : list) bytes += g.owned_bytes();
    return bytes;
  }

  std::tuple<std::deque<Geometries>...> geometries_;
  std::vector<Ref> refs_;
  bool robust_ = true;
};

/// A world: geometries placed directly (ids 0..n-1 in the top-level scene) and instances
/// of groups (ids n.. in the top-level scene; hits report them as inst_id).
template <Geometry... Geometries>
class World : public Group<Geometries...> {
public:
  using GroupType = Group<Geometries...>;
  using GroupType::GroupType;

  /// Places `group` (built at the world's commit if it is not yet) by `transform`;
  /// returns the instance's index. Takes effect at commit.
  std::uint32_t add_instance(std::shared_ptr<GroupType> group, const Affine3f& transform = {}) {
    return add_instance(std::move(group), MotionTransform(transform));
  }

  /// Places `group` by a transform that may move over time: at each ray's time, and
  /// nowhere at times outside a moving transform's range.
  std::uint32_t add_instance(std::shared_ptr<GroupType> group, MotionTransform motion) {
    if (!group) throw Error("world: instance of a null group");
    if (&group->device() != this->device_) throw Error("world: an instance's group must use the world's device");
    for (std::size_t k = 0; k < motion.key_count(); ++k) {
      const float det = motion.key(k).determinant();
      if (det == 0.f || !std::isfinite(det))
        throw Error("world: instance " + std::to_string(instances_.size()) + " has a singular or non-finite transform" +
                    (motion.moving() ? " at key " + std::to_string(k) : std::string()));
    }
    const auto id = static_cast<std::uint32_t>(instances_.size());
    instances_.push_back({std::move(group), std::move(motion), id});
    this->committed_ = false;
    return static_cast<std::uint32_t>(instances_.size() - 1);
  }

  /// Clipping geometry for the whole world (scene/clipping.hpp), or null for none. Takes
  /// effect at commit.
  void set_clipping(std::shared_ptr<Clipping> clipping) {
    clipping_ = std::move(clipping);
    this->committed_ = false;
  }

  /// The clipping in effect, or null.
  const Clipping* clipping() const { return clipping_ && !clipping_->empty() ? clipping_.get() : nullptr; }

  /// What every query of this world passes to Embree: the clipping test, if any.
  accel::HitFilter hit_filter() const {
    if (!clipping_ || clipping_->empty()) return {};
    return {&World::clip_filter, this};
  }

  std::size_t instance_count() const { return instances_.size(); }

  /// What the instance id channel shows for instance `instance`: `id` in place of its
  /// index (OSPRay's instance `id`). Takes effect at commit.
  void set_instance_id(std::uint32_t instance, std::uint32_t id) {
    instances_.at(instance).id = id;
    this->committed_ = false;
  }

  /// Whether an object or instance id differs from its index (as of the last commit):
  /// the id channels then need channel_ids() instead of the hits' own ids.
  bool user_ids() const { return user_ids_; }

  /// The object and instance ids that the id channels show for a hit's geometry: the
  /// Embree ids `inst_id` and `geom_id` (as visit_hit) mapped through the user ids; the
  /// instance id is -1 for a direct geometry.
  std::array<std::int32_t, 2> channel_ids(std::uint32_t inst_id, std::uint32_t geom_id) const {
    if (inst_id == RTC_INVALID_GEOMETRY_ID) return {static_cast<std::int32_t>(this->object_id(geom_id)), -1};
    const Instance& instance = instances_.at(inst_id - this->geometry_count());
    return {static_cast<std::int32_t>(instance.group->object_id(geom_id)), static_cast<std::int32_t>(instance.id)};
  }
  const MotionTransform& instance_motion(std::uint32_t instance) const { return instances_.at(instance).motion; }
  const GroupType& instance_group(std::uint32_t instance) const { return *instances_.at(instance).group; }

  /// Builds the groups not yet built, then the top-level BVH over direct geometries and
  /// instances.
  template <class Arch = xsimd::default_arch>
  void commit() {
    const bool clipped = clipping_ && !clipping_->empty();
    if (clipped) clipping_->commit(*this->device_);
    this->set_context_filter(clipped);
    accel::Scene scene(*this->device_);
    this->configure(scene);
    this->bounds_ = {};
    this->template attach_geometries<Arch>(scene.get(), 0);
    const auto first_instance = static_cast<std::uint32_t>(this->geometry_count());
    user_ids_ = this->user_object_ids();
    for (std::uint32_t i = 0; i < instances_.size(); ++i) {
      const Instance& instance = instances_[i];
      user_ids_ = user_ids_ || instance.id != i || instance.group->user_object_ids();
      instance.group->set_context_filter(clipped);
      if (!instance.group->committed()) instance.group->template commit<Arch>();
      accel::GeometryHandle handle(*this->device_, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(handle.get(), instance.group->scene());
      accel::set_transform(handle.get(), instance.motion);
      RTCGeometry geometry = handle.commit(*this->device_, "world: instance");
      rtcAttachGeometryByID(scene.get(), geometry, first_instance + i);
      rtcReleaseGeometry(geometry);
      this->device_->check("world: instance");
      this->bounds_.extend(instance.motion.transform(instance.group->bounds()));
    }
    scene.commit();
    this->scene_ = std::move(scene);
    this->committed_ = true;
  }

  /// Calls f(geometry, placement) for the geometry a hit reports: `inst_id` as Embree
  /// reports it (RTC_INVALID_GEOMETRY_ID for a direct geometry, whose placement is null);
  /// an instance's placement is its MotionTransform (normals at the hits' ray times).
  template <class F>
  decltype(auto) visit_hit(std::uint32_t inst_id, std::uint32_t geom_id, F&& f) const {
    if (inst_id == RTC_INVALID_GEOMETRY_ID)
      return this->visit(geom_id, [&](const auto& g) { return f(g, static_cast<const MotionTransform*>(nullptr)); });
    const Instance& instance = instances_.at(inst_id - this->geometry_count());
    return instance.group->visit(geom_id, [&](const auto& g) { return f(g, &instance.motion); });
  }

  /// The material index of the geometry a hit reports (inst_id as for visit_hit).
  std::uint32_t material_of(std::uint32_t inst_id, std::uint32_t geom_id) const {
    if (inst_id == RTC_INVALID_GEOMETRY_ID) return this->material(geom_id);
    return instances_[inst_id - this->geometry_count()].group->material(geom_id);
  }
  /// That geometry's material per primitive, or null where it has one for all.
  const std::vector<std::uint32_t>* primitive_materials_of(std::uint32_t inst_id, std::uint32_t geom_id) const {
    if (inst_id == RTC_INVALID_GEOMETRY_ID) return this->primitive_materials(geom_id);
    return instances_[inst_id - this->geometry_count()].group->primitive_materials(geom_id);
  }

  /// How many materials the geometries, direct or instanced, need.
  std::uint32_t materials_needed() const {
    std::uint32_t n = GroupType::materials_needed();
    for (const Instance& instance : instances_) n = std::max(n, instance.group->materials_needed());
    return n;
  }

  /// Whether any geometry, direct or instanced, shows translucent colours.
  bool translucent_colors() const {
    if (GroupType::translucent_colors()) return true;
    for (const Instance& instance : instances_)
      if (instance.group->translucent_colors()) return true;
    return false;
  }

  /// Bytes of geometry data sciray owns (each group once, however often instanced), plus
  /// what Embree holds (BVHs and buffers).
  std::size_t memory_bytes() const {
    std::size_t bytes = this->owned_bytes();
    std::unordered_set<const GroupType*> counted;
    for (const Instance& instance : instances_)
      if (counted.insert(instance.group.get()).second) bytes += instance.group->owned_bytes();
    return bytes + static_cast<std::size_t>(std::max<std::int64_t>(0, this->device_->bytes_in_use()));
  }

private:
  struct Instance {
    std::shared_ptr<GroupType> group;
    MotionTransform motion;
    std::uint32_t id;  ///< what the instance id channel shows
  };
  bool user_ids_ = false;


  /// Embree's context filter: rejects candidate hits inside a clipping volume. Instanced
  /// candidates arrive in their group's space and are moved to the world's first.
  static void clip_filter(const RTCFilterFunctionNArguments* args) {
    const auto& world = *static_cast<const World*>(accel::HitFilter::data_of(args->context));
    for (unsigned i = 0; i < args->N; ++i) {
      if (!args->valid[i]) continue;
      const float t = RTCRayN_tfar(args->ray, args->N, i);
      Vec3f p{RTCRayN_org_x(args->ray, args->N, i) + t * RTCRayN_dir_x(args->ray, args->N, i),
              RTCRayN_org_y(args->ray, args->N, i) + t * RTCRayN_dir_y(args->ray, args->N, i),
              RTCRayN_org_z(args->ray, args->N, i) + t * RTCRayN_dir_z(args->ray, args->N, i)};
      const unsigned instance = RTCHitN_instID(args->hit, args->N, i, 0);
      const float time = RTCRayN_time(args->ray, args->N, i);
      if (instance != RTC_INVALID_GEOMETRY_ID)
        p = world.instances_[instance - world.geometry_count()].motion.at(time).point(p);
      if (world.clipping_->clipped(p, time)) args->valid[i] = 0;
    }
  }

  std::vector<Instance> instances_;
  std::shared_ptr<Clipping> clipping_;
};

}  // namespace sciray
