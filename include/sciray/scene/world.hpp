#pragma once
// World<Geometries...>: the compile-time set of geometry types a scene uses, their
// instances, and the Embree scene over them. A program that renders only meshes
// instantiates World<TriangleMesh> and compiles no code for other types.
//
// The world holds data and the BVH only; it is not templated on the SIMD architecture
// because Embree's build is ISA-independent. Renderers, which run per ray, take Arch.
#include <array>
#include <concepts>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "sciray/accel/embree.hpp"
#include "sciray/math/box.hpp"

namespace sciray {

/// What the world needs of a geometry type.
template <class G>
concept Geometry = requires(const G& g, const accel::Device& device) {
  { g.validate() } -> std::same_as<void>;
  { g.bounds() } -> std::same_as<Box3f>;
  { g.owned_bytes() } -> std::convertible_to<std::size_t>;
  { g.create_embree_geometry(device) } -> std::same_as<RTCGeometry>;
};

template <Geometry... Geometries>
class World {
public:
  explicit World(const accel::Device& device) : device_(&device), scene_(device) {}

  /// Adds a geometry; returns its id, which hits report as geom_id. Takes effect at commit.
  template <class G>
  std::uint32_t add(G geometry) {
    static_assert((std::is_same_v<G, Geometries> || ...), "World was not composed with this geometry type");
    auto& list = std::get<std::vector<G>>(geometries_);
    refs_.push_back({type_index<G>(), static_cast<std::uint32_t>(list.size())});
    list.push_back(std::move(geometry));
    committed_ = false;
    return static_cast<std::uint32_t>(refs_.size() - 1);
  }

  /// Validates every geometry and builds the BVH.
  void commit() {
    accel::Scene scene(*device_);
    // Embree's default traversal lets rays exactly through a shared edge slip between the
    // two triangles (tests/stability); robust mode closes edges at no measured cost.
    if (robust_) rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_ROBUST);
    bounds_ = {};
    for (std::size_t id = 0; id < refs_.size(); ++id) {
      visit(static_cast<std::uint32_t>(id), [&](const auto& geometry) {
        geometry.validate();
        RTCGeometry g = geometry.create_embree_geometry(*device_);
        rtcAttachGeometryByID(scene.get(), g, static_cast<unsigned>(id));
        rtcReleaseGeometry(g);
        device_->check("rtcAttachGeometryByID");
        bounds_.extend(geometry.bounds());
      });
    }
    scene.commit();
    scene_ = std::move(scene);
    committed_ = true;
  }

  /// Robust traversal (the default) or Embree's faster-in-theory default mode; takes
  /// effect at the next commit.
  void set_robust(bool robust) { robust_ = robust; }

  bool committed() const { return committed_; }
  RTCScene scene() const { return scene_.get(); }
  const accel::Device& device() const { return *device_; }
  Box3f bounds() const { return bounds_; }
  std::size_t geometry_count() const { return refs_.size(); }

  /// Calls f(geometry) with the concrete geometry of id `id`.
  template <class F>
  decltype(auto) visit(std::uint32_t id, F&& f) const {
    const Ref ref = refs_.at(id);
    return visit_type<0>(ref, std::forward<F>(f));
  }

  template <class G>
  const std::vector<G>& all() const {
    return std::get<std::vector<G>>(geometries_);
  }

  /// Bytes of geometry data sciray owns, plus what Embree holds (BVH and buffers).
  std::size_t memory_bytes() const {
    std::size_t bytes = 0;
    std::apply([&](const auto&... lists) { ((bytes += owned_bytes(lists)), ...); }, geometries_);
    return bytes + static_cast<std::size_t>(std::max<std::int64_t>(0, device_->bytes_in_use()));
  }

private:
  struct Ref {
    std::uint8_t type;
    std::uint32_t index;
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
      return f(std::get<std::vector<G>>(geometries_)[ref.index]);
    } else {
      if (ref.type == I) return f(std::get<std::vector<G>>(geometries_)[ref.index]);
      return visit_type<I + 1>(ref, std::forward<F>(f));
    }
  }

  template <class G>
  static std::size_t owned_bytes(const std::vector<G>& list) {
    std::size_t bytes = 0;
    for (const auto& g : list) bytes += g.owned_bytes();
    return bytes;
  }

  const accel::Device* device_;
  accel::Scene scene_;
  std::tuple<std::vector<Geometries>...> geometries_;
  std::vector<Ref> refs_;
  Box3f bounds_;
  bool committed_ = false;
  bool robust_ = true;
};

}  // namespace sciray
