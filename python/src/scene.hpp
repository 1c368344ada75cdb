#pragma once
// A Python scene: the arrays it was given and how each becomes engine geometry or a
// volume, and the engine world built from them. commit() reads every array again, so
// changes made in place to shared (or copied) arrays show after it.
#include <functional>
#include <memory>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>

#include "sciray/render/light.hpp"
#include "sciray/render/material.hpp"
#include "sciray/shim/engine.hpp"

namespace sciray_python {

namespace py = pybind11;
using sciray::shim::EngineWorld;

/// An OSPRay material (type and parameters by OSPRay's names), as the tool's JSON reads it.
struct Material {
  std::string type;
  sciray::Material material;
  nlohmann::json json;  ///< its parameters (a mix material's parts refer to them)
};

/// An OSPRay light.
struct Light {
  std::string type;
  sciray::Light light;
  nlohmann::json json;
};

/// Colours and opacities spread evenly over a value range (the data's when not given).
struct TransferFunction {
  std::vector<sciray::Vec3f> colors;
  std::vector<float> opacities;
  std::optional<std::array<float, 2>> value_range;
  sciray::TransferFunction over(std::array<float, 2> data_range) const;
};

/// Puts one entry's engine objects into a world (with its material's index).
using Adder = std::function<void(EngineWorld&, std::uint32_t material)>;

struct Built {
  Adder add;
  bool shared = false;  ///< every array the engine reads is the caller's own (no copy)
};

struct SceneEntry {
  std::string kind;  ///< "mesh", "spheres", "curves", "isosurface", "volume", "unstructured"
  bool geometry = true;  ///< a surface (pickable, takes a material) rather than a volume
  /// Reads the entry's arrays into engine objects; holds the arrays (called with the GIL).
  std::function<Built()> build;
  Built built;  ///< the engine objects of the last build
  std::optional<sciray::Material> material;
  int index = 0;  ///< among the scene's geometries (or volumes)
};

class Scene {
public:
  explicit Scene(const std::string& isa);
  ~Scene();

  /// Builds the entry now (so bad arrays are named at the call) and returns its index
  /// among the scene's geometries (or volumes).
  int add(SceneEntry entry);
  void add_light(const Light& light) { lights_.push_back(light.light), dirty_ = true; }
  const std::vector<sciray::Light>& lights() const { return lights_; }

  /// Reads every array again and builds a new world and BVH (the GIL released meanwhile);
  /// frames in progress keep the old world, and the new one replaces it between frames.
  void commit();
  /// Commits if something was added since the last commit.
  void commit_if_changed();

  const sciray::shim::IsaKernels& kernels() const { return *kernels_; }
  /// Runs `use(world, materials)` with the GIL released and no commit in progress: frames
  /// (several at once), picks and bounds read the committed world through it. `materials`:
  /// those of the geometries that have one, in the order commit gave them indices.
  template <class Use>
  auto with_world(Use&& use) {
    py::gil_scoped_release release;
    std::shared_lock lock(frames_lock_);
    return use(static_cast<const EngineWorld&>(*world_), static_cast<const std::vector<sciray::Material>&>(materials_));
  }
  sciray::Box3f bounds();
  const std::vector<SceneEntry>& entries() const { return entries_; }
  int geometry_count() const { return geometries_; }
  int volume_count() const { return volumes_; }

private:
  /// Builds a world of `builts` (the entries', in order) and puts both in place.
  void install(std::vector<Built> builts);

  const sciray::shim::IsaKernels* kernels_;
  std::unique_ptr<sciray::accel::Device> device_;
  std::unique_ptr<EngineWorld> world_;
  std::vector<SceneEntry> entries_;
  std::vector<sciray::Light> lights_;
  std::vector<sciray::Material> materials_;
  int geometries_ = 0, volumes_ = 0;
  bool dirty_ = true;
  std::shared_mutex frames_lock_;
};

/// sciray::Error from `call` as a ValueError prefixed by `what`, the engine's parameter
/// names replaced by the Python arguments (`renames`: {engine name, argument}).
template <class F>
auto naming_arguments(const std::string& what, std::initializer_list<std::pair<const char*, const char*>> renames, F&& call) {
  try {
    return call();
  } catch (const sciray::Error& e) {
    std::string message = e.what();
    for (const auto& [engine, argument] : renames)
      for (std::size_t at = message.find(engine); at != std::string::npos; at = message.find(engine, at))
        message.replace(at, std::string_view(engine).size(), argument), at += std::string_view(argument).size();
    throw py::value_error(what + ": " + message);
  }
}

void bind_scene(py::module_& m);

}  // namespace sciray_python
