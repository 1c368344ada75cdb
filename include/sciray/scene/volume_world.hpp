#pragma once
// VolumeWorld<WorldT, Volumes...>: a world of surfaces plus volumetric models of the
// volume types listed, composed at compile time like the geometry types:
//   VolumeWorld<World<TriangleMesh>, StructuredRegular<float>>
// compiles the ray marcher for float volumes only. A model is placed directly in the
// world or by a transform, static or moving (volume/volume_placement.hpp), once or many
// times: placements share the model (its macrocells) as instances share a group.
// Renderers integrate the placed volumes along each ray up to the nearest surface.
#include <array>
#include <cstdint>
#include <deque>
#include <tuple>
#include <unordered_set>
#include <vector>

#include "sciray/volume/volume_placement.hpp"
#include "sciray/volume/volumetric_model.hpp"

namespace sciray {

template <class WorldT, class... Volumes>
class VolumeWorld : public WorldT {
public:
  using WorldT::WorldT;

  /// Adds a volumetric model placed directly in the world; returns its placement's index
  /// among this world's volumes.
  template <class V>
  std::size_t add_volume(VolumetricModel<V> model) {
    return add_volume(std::move(model), VolumePlacement());
  }
  /// Adds a volumetric model placed by `motion` (a transform, or keys over time).
  template <class V>
  std::size_t add_volume(VolumetricModel<V> model, const MotionTransform& motion) {
    return add_volume(std::move(model), VolumePlacement(motion, "volume " + std::to_string(placements_.size())));
  }
  /// Places the model of placement `volume` once more, by `motion`, sharing the model.
  std::size_t place_volume(std::size_t volume, const MotionTransform& motion) {
    Placement copy = placements_.at(volume);
    copy.where = VolumePlacement(motion, "volume " + std::to_string(placements_.size()));
    copy.ids = {static_cast<std::int32_t>(placements_.size()), -1};
    visit_model(copy, [&](const auto& model) {
      copy.bounds = copy.where.world_bounds(model.bounds());
      copy.step = model.step(1.f) * copy.where.smallest_scale();
    });
    placements_.push_back(std::move(copy));
    return placements_.size() - 1;
  }

  /// What the id channels show where placed volume `volume` is seen: primitive 0,
  /// `object` and `instance` (OSPRay: the volumetric model's index in its group or its
  /// `id`, and its instance's index or `id`). By default the placement's index and -1.
  void set_volume_ids(std::size_t volume, std::int32_t object, std::int32_t instance) {
    placements_.at(volume).ids = {object, instance};
  }
  /// The object and instance ids of placed volume `volume` (see set_volume_ids).
  std::array<std::int32_t, 2> volume_ids(std::size_t volume) const { return placements_[volume].ids; }

  /// How many placed volumes the world has.
  std::size_t volume_count() const { return placements_.size(); }

  /// A placed volume that some lanes of a packet of world rays pass: where each lane
  /// enters and leaves its world box (enter > leave for lanes that miss it).
  template <class Arch>
  struct Along {
    std::uint32_t volume;
    simd::Float<Arch> enter, leave;
    float step;  ///< about one cell in world units (the sampling step at rate 1)
  };

  /// The placed volumes that some active lane of the world rays `ray` passes within
  /// [tnear, min(tfar, t_end)], in the order they were added.
  template <class Arch>
  std::vector<Along<Arch>> volumes_along(const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                                         const simd::Float<Arch>& t_end) const {
    using Fl = simd::Float<Arch>;
    std::vector<Along<Arch>> out;
    for_each_passed<Arch>(ray, active, t_end, [&](std::uint32_t i, const simd::Mask<Arch>& passing, const Fl& enter,
                                                  const Fl& leave) {
      out.push_back({i, simd::select(passing, enter, Fl(INFINITY)), simd::select(passing, leave, Fl(-INFINITY)),
                     placements_[i].step});
    });
    return out;
  }

  /// Calls f(model, object_ray) for placed volume `volume` if some of the `active` lanes
  /// of `ray` see it at their time: `object_ray` holds them in the volume's object space.
  template <class Arch, class F>
  void with_volume(std::size_t volume, const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                   F&& f) const {
    const Placement& p = placements_[volume];
    const VolumeRay<Arch> object_ray = p.where.template object_ray<Arch>(ray, active);
    if (simd::any(object_ray.active)) visit_model(p, [&](const auto& model) { f(model, object_ray); });
  }

  /// with_volume() for every placed volume that the active lanes pass before t_end.
  template <class Arch, class F>
  void for_each_volume_along(const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                             const simd::Float<Arch>& t_end, F&& f) const {
    using Fl = simd::Float<Arch>;
    for_each_passed<Arch>(ray, active, t_end,
                          [&](std::uint32_t i, const simd::Mask<Arch>& passing, const Fl&, const Fl&) {
                            with_volume<Arch>(i, ray, passing, f);
                          });
  }

  /// Surfaces' and placed volumes' bounds.
  Box3f bounds() const {
    Box3f box = WorldT::bounds();
    for (const Placement& p : placements_) box.extend(p.bounds);
    return box;
  }

  /// The surfaces' memory plus each model's macrocells and each volume's own copy
  /// (bricked voxels), once however often placed.
  std::size_t memory_bytes() const {
    std::size_t bytes = WorldT::memory_bytes();
    std::unordered_set<const void*> models, volumes;
    for (const Placement& p : placements_)
      visit_model(p, [&](const auto& model) {
        if (!models.insert(&model).second) return;
        bytes += model.owned_bytes();
        if (volumes.insert(&model.volume()).second) bytes += model.volume().owned_bytes();
      });
    return bytes;
  }

private:
  /// Calls f(index, passing, enter, leave) for every placed volume whose world box some
  /// active lane passes within [tnear, min(tfar, t_end)]: empty-space skipping's first
  /// step, where volumes no ray passes cost one box test.
  template <class Arch, class F>
  void for_each_passed(const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                       const simd::Float<Arch>& t_end, F&& f) const {
    using Fl = simd::Float<Arch>;
    const Vec3<Fl> inv{Fl(1.f) / ray.dir.x, Fl(1.f) / ray.dir.y, Fl(1.f) / ray.dir.z};
    const Fl reach = simd::min(ray.tfar, t_end);
    for (std::uint32_t i = 0; i < placements_.size(); ++i) {
      const Box3f& b = placements_[i].bounds;
      const Vec3<Fl> t0 = (Vec3<Fl>(b.lower) - ray.org) * inv, t1 = (Vec3<Fl>(b.upper) - ray.org) * inv;
      const Vec3<Fl> near = min(t0, t1), far = max(t0, t1);
      const Fl enter = simd::max(simd::max(simd::max(near.x, near.y), near.z), ray.tnear);
      const Fl leave = simd::min(simd::min(simd::min(far.x, far.y), far.z), reach);
      const auto passing = active & (enter <= leave);
      if (simd::any(passing)) f(i, passing, enter, leave);
    }
  }

  struct Placement {
    std::uint8_t type;
    std::uint32_t index;  ///< in its type's list of models
    VolumePlacement where;
    Box3f bounds;  ///< in world space, over the motion
    float step;    ///< about one cell in world units
    std::array<std::int32_t, 2> ids;  ///< object and instance ids for the id channels
  };

  template <class V>
  std::size_t add_volume(VolumetricModel<V> model, VolumePlacement where) {
    static_assert((std::is_same_v<V, Volumes> || ...), "the world was not composed with this volume type");
    auto& list = std::get<std::deque<VolumetricModel<V>>>(models_);
    const Box3f bounds = where.world_bounds(model.bounds());
    const float step = model.step(1.f) * where.smallest_scale();
    list.push_back(std::move(model));
    const auto placed = static_cast<std::int32_t>(placements_.size());
    placements_.push_back(
        {type_index<V>(), static_cast<std::uint32_t>(list.size() - 1), std::move(where), bounds, step, {placed, -1}});
    return placements_.size() - 1;
  }

  template <class V, std::size_t I = 0>
  static constexpr std::uint8_t type_index() {
    if constexpr (std::is_same_v<V, std::tuple_element_t<I, std::tuple<Volumes...>>>)
      return I;
    else
      return type_index<V, I + 1>();
  }

  template <std::size_t I = 0, class F>
  void visit_model(const Placement& p, F&& f) const {
    using V = std::tuple_element_t<I, std::tuple<Volumes...>>;
    if constexpr (I + 1 == sizeof...(Volumes)) {
      f(std::get<std::deque<VolumetricModel<V>>>(models_)[p.index]);
    } else {
      if (p.type == I) return f(std::get<std::deque<VolumetricModel<V>>>(models_)[p.index]);
      visit_model<I + 1>(p, std::forward<F>(f));
    }
  }

  std::tuple<std::deque<VolumetricModel<Volumes>>...> models_;
  std::vector<Placement> placements_;
};

}  // namespace sciray
