#pragma once
// The sciray tool's volumes: a raw or NRRD file becomes a StructuredRegular of its voxel
// type in the layout asked for, rendered through a transfer function from a JSON file (or
// a default one spread over the data's value range), as isosurfaces, or as slices; a VTK
// unstructured grid (.vtu) becomes an Unstructured volume of the array `--field` names.
#include <array>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sciray/io/volume.hpp"
#include "sciray/io/vtk.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "json_float.hpp"

namespace sciray_tool {

struct VolumeOptions {
  std::string tf;                 ///< transfer function JSON, or empty for the default
  std::string layout = "linear";  ///< or "bricked"
  float density = 0.f;            ///< densityScale; 0: a default from the volume's size
  float anisotropy = 0.f;         ///< the path tracer's Henyey–Greenstein g
  float gradient_shading_scale = 0.f;  ///< scivis: how much the gradient-lit colour replaces the sample's
  std::vector<float> isovalues;   ///< isosurfaces instead of volume rendering
  bool exact = false;             ///< integrate a mesh of tetrahedra exactly (VolumeIntegration::exact)
  std::vector<std::array<float, 4>> slices;  ///< planes a,b,c,d coloured by the volume, instead
  std::string field;  ///< .vtu: the point or cell array to render (empty: its Scalars, else the first)
};

/// {"colors": [[r, g, b], ...], "opacities": [a, ...], "range": [lo, hi]}; "range" may be
/// left out to use the data's.
inline sciray::TransferFunction read_transfer_function(const std::string& file, std::array<float, 2> data_range) {
  std::ifstream in(file);
  if (!in) throw sciray::Error(file + ": cannot open transfer function file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for a number beyond double
    throw sciray::Error(file + ": invalid JSON: " + e.what());
  }
  const auto numbers = [&](const nlohmann::json& v, const std::string& what) {
    if (!v.is_array()) throw sciray::Error(file + ": " + what + " must be an array of numbers");
    std::vector<float> out;
    for (const auto& x : v) {
      if (!x.is_number()) throw sciray::Error(file + ": " + what + " must be an array of numbers");
      out.push_back(json_float(x, file + ": " + what));
    }
    return out;
  };
  if (!j.is_object() || !j.contains("colors") || !j.contains("opacities"))
    throw sciray::Error(file + ": expected an object with \"colors\" and \"opacities\"");
  std::vector<sciray::Vec3f> colors;
  for (const auto& c : j["colors"]) {
    const auto rgb = numbers(c, "each of \"colors\"");
    if (rgb.size() != 3) throw sciray::Error(file + ": each of \"colors\" must be [r, g, b]");
    colors.push_back({rgb[0], rgb[1], rgb[2]});
  }
  std::array<float, 2> range = data_range;
  if (j.contains("range")) {
    const auto r = numbers(j["range"], "\"range\"");
    if (r.size() != 2) throw sciray::Error(file + ": \"range\" must be [lo, hi]");
    range = {r[0], r[1]};
  }
  std::vector<float> opacities = numbers(j["opacities"], "\"opacities\"");
  try {
    return {std::move(colors), std::move(opacities), range};
  } catch (const sciray::Error& e) {  // the table's own checks (finite, not negative, lo < hi) name no file
    throw sciray::Error(file + ": " + e.what());
  }
}

/// The colour map of the test scenes with opacity rising linearly over the value range.
inline sciray::TransferFunction default_transfer_function(std::array<float, 2> range) {
  std::vector<sciray::Vec3f> colors;
  for (int i = 0; i < 8; ++i) colors.push_back(sciray::testing::colormap(static_cast<float>(i) / 7.f));
  if (!(range[0] < range[1])) range[1] = range[0] + 1.f;
  return {std::move(colors), {0.f, 1.f}, range};
}

struct VolumeInfo {
  sciray::VolumeDims dims;  ///< a grid's voxels; an unstructured volume's cells, 1, 1
  std::string type;
};

/// The default density: the densest value absorbs 1 − e⁻⁴ over the volume's diagonal.
template <class Volume>
float default_density(const Volume& volume) {
  return 4.f / length(volume.bounds().size());
}

/// A volumetric model of `volume` through the transfer function asked for, at the default
/// density unless one is.
template <class Volume>
sciray::VolumetricModel<Volume> volumetric_model(std::shared_ptr<const Volume> volume, std::array<float, 2> range,
                                                 const VolumeOptions& opt) {
  sciray::TransferFunction tf = opt.tf.empty() ? default_transfer_function(range) : read_transfer_function(opt.tf, range);
  const float density = opt.density > 0.f ? opt.density : default_density(*volume);
  sciray::VolumetricModel<Volume> model(volume, std::move(tf), density, opt.anisotropy);
  model.set_gradient_shading_scale(opt.gradient_shading_scale);
  return model;
}

/// Adds the unstructured grid `grid` (of the file `path`) to `world`, its array
/// `opt.field` volume-rendered, or its isosurfaces (a cell array averaged to the vertices
/// first).
inline VolumeInfo add_unstructured(sciray::shim::EngineWorld& world, const sciray::io::UnstructuredGridFile& grid,
                                   const std::string& path, const VolumeOptions& opt) {
  using namespace sciray;
  if (!opt.slices.empty()) throw Error("--slice: slices of unstructured volumes are not supported yet");
  if (opt.layout != "linear") throw Error("--layout: applies to structured volumes only");
  UnstructuredData data = io::unstructured_volume(grid, opt.field, path);
  const bool averaged = !opt.isovalues.empty() && !data.cell_values.empty();
  if (averaged) average_cell_values_to_vertices(data);
  auto volume = std::make_shared<const Unstructured>(std::move(data));
  if (opt.exact && !volume->tetrahedral())
    throw Error("--exact: integrates meshes of tetrahedra, and " + path + " has other cells too");
  if (!opt.isovalues.empty())
    world.add(Isosurface(volume, opt.isovalues));
  else
    world.add_volume(volumetric_model(volume, volume->value_range(), opt));
  return {{static_cast<std::int64_t>(volume->cell_count()), 1, 1},
          "unstructured (" + std::to_string(volume->folded_cells()) + " folded cells" +
              (averaged ? "; cell values averaged to the vertices for --iso" : "") + ")"};
}

/// Adds a loaded (or generated) volume to `world`: its isosurfaces if isovalues are given,
/// its slices if planes are, else the volume rendered through its transfer function.
inline VolumeInfo add_volume(sciray::shim::EngineWorld& world, const sciray::io::VolumeFile& file,
                             const VolumeOptions& opt) {
  using namespace sciray;
  if (opt.layout != "linear" && opt.layout != "bricked")
    throw Error("--layout: expected linear or bricked, got '" + opt.layout + "'");
  if (opt.exact) throw Error("--exact: integrates meshes of tetrahedra (.vtu files), not grids");
  const auto add = [&](auto voxel_tag) {
    using Voxel = decltype(voxel_tag);
    const auto* voxels = reinterpret_cast<const Voxel*>(file.voxels->data());
    const auto add_model = [&](auto volume) {
      if (!opt.isovalues.empty()) {
        world.add(Isosurface(volume, opt.isovalues));
        return;
      }
      const std::array<float, 2> range = file.range ? *file.range : volume->value_range();
      if (!opt.slices.empty()) {
        TransferFunction tf = opt.tf.empty() ? default_transfer_function(range) : read_transfer_function(opt.tf, range);
        // Each slice is cut to the volume's box.
        std::vector<Planes::Plane> planes;
        for (const auto& c : opt.slices) planes.push_back({c[0], c[1], c[2], c[3]});
        std::vector<Box3f> bounds(planes.size(), volume->bounds());
        world.add(VolumeSlice(std::move(planes), std::move(bounds), volume, std::move(tf)));
        return;
      }
      world.add_volume(volumetric_model(volume, range, opt));
    };
    if (opt.layout == "bricked")
      add_model(std::make_shared<const StructuredRegular<Voxel, BrickedLayout>>(
          BrickedLayout<Voxel>(voxels, file.dims), file.grid));
    else
      add_model(std::make_shared<const StructuredRegular<Voxel>>(LinearLayout<Voxel>(voxels, file.dims, file.voxels),
                                                                 file.grid));
  };
  switch (file.kind) {
    case io::VoxelKind::uint8: add(std::uint8_t{}); break;
    case io::VoxelKind::int16: add(std::int16_t{}); break;
    case io::VoxelKind::uint16: add(std::uint16_t{}); break;
    case io::VoxelKind::float32: add(float{}); break;
    case io::VoxelKind::float64: add(double{}); break;
  }
  return {file.dims, std::string(io::voxel_kind_name(file.kind))};
}

}  // namespace sciray_tool
