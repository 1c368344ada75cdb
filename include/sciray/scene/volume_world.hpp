#pragma once
// VolumeWorld<WorldT, Volumes...>: a world of surfaces plus volumetric models of the
// volume types listed, composed at compile time like the geometry types:
//   VolumeWorld<World<TriangleMesh>, StructuredRegular<float>>
// compiles the ray marcher for float volumes only. Volumes are placed directly in the
// world (not yet in instanced groups); renderers integrate them along each ray up to the
// nearest surface.
#include <deque>
#include <tuple>
#include <unordered_set>

#include "sciray/volume/volumetric_model.hpp"

namespace sciray {

template <class WorldT, class... Volumes>
class VolumeWorld : public WorldT {
public:
  using WorldT::WorldT;

  /// Adds a volumetric model; returns its index among this world's volumes.
  template <class V>
  std::size_t add_volume(VolumetricModel<V> model) {
    static_assert((std::is_same_v<V, Volumes> || ...), "the world was not composed with this volume type");
    std::get<std::deque<VolumetricModel<V>>>(volumes_).push_back(std::move(model));
    return volume_count_++;
  }

  std::size_t volume_count() const { return volume_count_; }

  /// Calls f(model) for every volumetric model.
  template <class F>
  void for_each_volume(F&& f) const {
    std::apply([&](const auto&... lists) { (for_each(lists, f), ...); }, volumes_);
  }
  template <class F>
  void for_each_volume(F&& f) {
    std::apply([&](auto&... lists) { (for_each(lists, f), ...); }, volumes_);
  }

  /// Surfaces' and volumes' bounds.
  Box3f bounds() const {
    Box3f box = WorldT::bounds();
    for_each_volume([&](const auto& model) { box.extend(model.bounds()); });
    return box;
  }

  /// The surfaces' memory plus each volume's own copy (bricked voxels) and macrocells.
  std::size_t memory_bytes() const {
    std::size_t bytes = WorldT::memory_bytes();
    std::unordered_set<const void*> volumes;
    for_each_volume([&](const auto& model) {
      bytes += model.owned_bytes();
      if (volumes.insert(&model.volume()).second) bytes += model.volume().owned_bytes();
    });
    return bytes;
  }

private:
  template <class List, class F>
  static void for_each(List& list, F& f) {
    for (auto& model : list) f(model);
  }

  std::tuple<std::deque<VolumetricModel<Volumes>>...> volumes_;
  std::size_t volume_count_ = 0;
};

}  // namespace sciray
