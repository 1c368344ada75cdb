// OSPRay's structuredRegular and unstructured volumes (the other types: volume_types.cpp),
// piecewiseLinear transfer function and volumetric model.
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

namespace sciray::ospray {

// ---- volumes ------------------------------------------------------------------------------

namespace {

std::string format_counts(const std::array<std::uint64_t, 3>& n) {
  return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
}

/// The engine volume over `data` (voxels of type Voxel): read in place where the array
/// is compact and aligned and the layout is linear (the volume then holds a reference to
/// the array, and with it the application's memory), otherwise copied. Float voxels must
/// be finite.
template <class Voxel>
EngineVolume make_structured_regular(const Object& owner, const Data& data, const VolumeGrid& grid,
                                     VolumeFilter filter, bool bricked, bool& zero_copy) {
  const auto& n = data.counts();
  const VolumeDims dims{static_cast<std::int64_t>(n[0]), static_cast<std::int64_t>(n[1]),
                        static_cast<std::int64_t>(n[2])};
  const std::byte* base = data.element(0);
  const bool in_place = data.compact() && reinterpret_cast<std::uintptr_t>(base) % alignof(Voxel) == 0;
  std::shared_ptr<std::vector<Voxel>> copy;
  const Voxel* voxels = reinterpret_cast<const Voxel*>(base);
  if (!in_place) {
    copy = std::make_shared<std::vector<Voxel>>(static_cast<std::size_t>(data.size()));
    Voxel* to = copy->data();
    for (std::uint64_t k = 0; k < n[2]; ++k)
      for (std::uint64_t j = 0; j < n[1]; ++j)
        for (std::uint64_t i = 0; i < n[0]; ++i) std::memcpy(to++, data.element(i, j, k), sizeof(Voxel));
    voxels = copy->data();
  }
  if constexpr (std::is_floating_point_v<Voxel>) {
    const std::uint64_t count = data.size();
    for (std::uint64_t i = 0; i < count; ++i)
      if (!std::isfinite(voxels[i]))
        throw Error(owner.name() + ": parameter 'data': voxel (" + std::to_string(i % n[0]) + ", " +
                    std::to_string(i / n[0] % n[1]) + ", " + std::to_string(i / n[0] / n[1]) + ") is not finite");
  }
  if (bricked) {
    zero_copy = false;
    return std::make_shared<const StructuredRegular<Voxel, BrickedLayout>>(BrickedLayout<Voxel>(voxels, dims), grid,
                                                                           filter);
  }
  zero_copy = in_place;
  // The application's array stays alive (and its deleter uncalled) while any engine
  // volume, also one a frame in flight holds, reads it.
  std::shared_ptr<const void> keep =
      copy ? std::shared_ptr<const void>(copy)
           : std::shared_ptr<const void>(base, [hold = Ref<Data>(const_cast<Data*>(&data))](const void*) {});
  return std::make_shared<const StructuredRegular<Voxel>>(LinearLayout<Voxel>(voxels, dims, std::move(keep)), grid,
                                                          filter);
}

/// The engine model of `volume` with `tf`, `density_scale`, `anisotropy` and
/// `gradient_shading_scale` (builds its macrocells).
EngineVolumetricModel make_volumetric_model(const EngineVolume& volume, const TransferFunction& tf,
                                            float density_scale, float anisotropy = 0.f,
                                            float gradient_shading_scale = 0.f) {
  return std::visit(
      [&](const auto& v) -> EngineVolumetricModel {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          throw Error("volumetric model: its volume has not been committed");
        } else {
          VolumetricModel<std::remove_const_t<typename T::element_type>> model(v, tf, density_scale, anisotropy);
          model.set_gradient_shading_scale(gradient_shading_scale);
          return model;
        }
      },
      volume);
}

/// Which engine volume `model` is built over (to tell a recommitted volume's new engine
/// volume from the one the model has).
const void* volume_of(const EngineVolumetricModel& model) {
  return std::visit(
      [](const auto& m) -> const void* {
        if constexpr (std::is_same_v<std::decay_t<decltype(m)>, std::monostate>)
          return nullptr;
        else
          return &m.volume();
      },
      model);
}
const void* volume_of(const EngineVolume& volume) {
  return std::visit(
      [](const auto& v) -> const void* {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return nullptr;
        else
          return v.get();
      },
      volume);
}

}  // namespace

std::size_t add_volume(shim::EngineWorld& world, const EngineVolumetricModel& model, const MotionTransform& placement) {
  return std::visit(
      [&](const auto& m) -> std::size_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(m)>, std::monostate>)
          throw Error("volumetric model: it has no volume");  // committed models always have one
        else
          return world.add_volume(m, placement);
      },
      model);
}

/// OSPRay's `unstructured`: vertex.position, vertex.data or cell.data, index, cell.index,
/// cell.type, background. (hexIterative and precomputedNormals are accepted: hexahedra
/// are always inverted iteratively, which is exact for faces that are not planar too.)
EngineVolume VolumeObject::commit_unstructured() {
  UnstructuredData u;
  const Data& positions = required_data("vertex.position", {OSP_VEC3F}, "array of vec3f");
  u.positions.resize(static_cast<std::size_t>(positions.size()));
  for (std::size_t i = 0; i < u.positions.size(); ++i) {
    const std::byte* e = positions.element(i);
    u.positions[i] = {read_float(e), read_float(e + 4), read_float(e + 8)};
  }
  const Data* vertex_data = get_data(*this, find("vertex.data"), "vertex.data", {OSP_FLOAT});
  const Data* cell_data = get_data(*this, find("cell.data"), "cell.data", {OSP_FLOAT});
  if (!vertex_data && !cell_data)
    throw Error(name() + ": required parameter 'vertex.data' or 'cell.data' (array of float) is missing");
  // OSPRay takes the cells' values where both are given.
  if (cell_data)
    u.cell_values = read_floats(*cell_data);
  else
    u.vertex_values = read_floats(*vertex_data);
  u.index = read_indices(required_data("index", {OSP_UINT, OSP_ULONG}, "array of uint32 or uint64"));
  u.cell_index = read_indices(required_data("cell.index", {OSP_UINT, OSP_ULONG}, "array of uint32 or uint64"));
  const Data& types = required_data("cell.type", {OSP_UCHAR}, "array of uchar");
  u.cell_type.resize(static_cast<std::size_t>(types.size()));
  for (std::size_t i = 0; i < u.cell_type.size(); ++i) u.cell_type[i] = static_cast<std::uint8_t>(*types.element(i));
  u.background = get_float("background", u.background);
  get_bool("hexIterative", false);
  get_bool("precomputedNormals", false);
  return std::make_shared<const Unstructured>(std::move(u));  // its errors name it "unstructured volume"
}

void VolumeObject::on_commit() {
  // Read into locals: a commit that fails leaves the volume as it was.
  bool zero_copy = false;
  EngineVolume volume = subtype() == "unstructured"          ? commit_unstructured()
                        : subtype() == "particle"            ? commit_particle()
                        : subtype() == "structuredSpherical" ? commit_structured_spherical()
                        : subtype() == "vdb"                 ? commit_vdb()
                        : subtype() == "amr"                 ? commit_amr()
                                                             : commit_structured_regular(zero_copy);
  bounds_ = std::visit(
      [](const auto& v) -> Box3f {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return {};
        else
          return v->bounds();
      },
      volume);
  volume_ = std::move(volume);
  zero_copy_ = zero_copy;
}

/// OSPRay's `structuredRegular` (the factory creates no other types than those above);
/// `zero_copy` tells whether the engine volume reads the application's array in place.
EngineVolume VolumeObject::commit_structured_regular(bool& zero_copy) {
  const std::string voxel_types = "uchar, short, ushort, float or double";
  const Param* p = find("data");
  if (!p || (!p->object && is_object_type(p->type)))  // absent, or set to NULL
    throw Error(name() + ": required parameter 'data' (3D array of " + voxel_types + ") is missing");
  if (!p->object || p->object->kind() != OSP_DATA)
    throw Error(name() + ": parameter 'data' must be an OSPData array, got " +
                type_name(p->object ? p->object->kind() : p->type));
  const auto& data = static_cast<const Data&>(*p->object);
  const OSPDataType type = data.element_type();
  if (type != OSP_UCHAR && type != OSP_SHORT && type != OSP_USHORT && type != OSP_FLOAT && type != OSP_DOUBLE)
    throw Error(name() + ": parameter 'data' must be an array of " + voxel_types + ", got an array of " +
                type_name(type) + (type == OSP_HALF ? " (half voxels are not supported yet)" : ""));
  const auto& n = data.counts();
  if (n[0] < 2 || n[1] < 2 || n[2] < 2) {
    const std::string got = n[1] == 1 && n[2] == 1 ? "a 1D array of " + std::to_string(n[0])
                            : n[2] == 1           ? "a 2D array of " + std::to_string(n[0]) + "x" + std::to_string(n[1])
                                                  : "a 3D array of " + format_counts(n);
    throw Error(name() + ": parameter 'data' must be a 3D array with at least 2 voxels in every direction (its "
                         "dimensions are the grid's), got " + got);
  }

  VolumeGrid grid;
  grid.origin = get_vec3f("gridOrigin", {0.f, 0.f, 0.f});
  grid.spacing = get_vec3f("gridSpacing", {1.f, 1.f, 1.f});
  if (!(grid.spacing.x > 0.f && grid.spacing.y > 0.f && grid.spacing.z > 0.f))
    throw Error(name() + ": parameter 'gridSpacing' must be positive on every axis, got " + format_vec(grid.spacing));
  grid.cell_centered = get_bool("cellCentered", false);

  const VolumeFilter filter = filter_param("filter", VolumeFilter::linear);

  bool bricked = false;
  if (const Param* layout = find("layout")) {
    if (layout->type != OSP_STRING)
      throw Error(name() + ": parameter 'layout' must be a string, got " + type_name(layout->type));
    if (layout->string == "bricked")
      bricked = true;
    else if (layout->string != "linear")
      throw Error(name() + ": parameter 'layout' has unknown value '" + layout->string + "' (linear, bricked)");
  }

  EngineVolume volume;
  switch (type) {
    case OSP_UCHAR: volume = make_structured_regular<std::uint8_t>(*this, data, grid, filter, bricked, zero_copy); break;
    case OSP_SHORT: volume = make_structured_regular<std::int16_t>(*this, data, grid, filter, bricked, zero_copy); break;
    case OSP_USHORT:
      volume = make_structured_regular<std::uint16_t>(*this, data, grid, filter, bricked, zero_copy);
      break;
    case OSP_FLOAT: volume = make_structured_regular<float>(*this, data, grid, filter, bricked, zero_copy); break;
    default: volume = make_structured_regular<double>(*this, data, grid, filter, bricked, zero_copy); break;
  }
  return volume;
}

void TransferFunctionObject::on_commit() {
  // The factory creates no other types.
  const Data* color = get_data(*this, find("color"), "color", {OSP_VEC3F});
  if (!color) throw Error(name() + ": required parameter 'color' (array of vec3f) is missing");
  const Data* opacity = get_data(*this, find("opacity"), "opacity", {OSP_FLOAT});
  if (!opacity) throw Error(name() + ": required parameter 'opacity' (array of float) is missing");
  std::array<float, 2> range{0.f, 1.f};  // OSPRay's default
  if (const Param* p = find("value")) {
    if (p->type != OSP_BOX1F && p->type != OSP_VEC2F)
      throw Error(name() + ": parameter 'value' must be a box1f (or vec2f) range, got " + type_name(p->type));
    std::memcpy(range.data(), p->bytes.data(), sizeof range);
  }
  // Validates: "transferFunction: 'value' must be a finite range with lo < hi, got [1, 1]"
  tf_ = std::make_shared<const TransferFunction>(
      color->to_vector<Vec3f>([](const std::byte* e) { return Vec3f{read_float(e), read_float(e + 4), read_float(e + 8)}; }),
      opacity->to_vector<float>(read_float), range);
}

void VolumetricModelObject::on_commit() {
  // Read into locals: a commit that fails leaves the model as it was.
  Ref<VolumeObject> volume = get_object<VolumeObject>("volume", OSP_VOLUME, true);
  if (!volume->committed()) throw Error(name() + ": its volume has not been committed");
  Ref<TransferFunctionObject> tf =
      get_object<TransferFunctionObject>("transferFunction", OSP_TRANSFER_FUNCTION, true);
  if (!tf->committed()) throw Error(name() + ": its transfer function has not been committed");
  const float density_scale = get_float("densityScale", 1.f);
  if (!(density_scale >= 0.f) || !std::isfinite(density_scale))
    throw Error(name() + ": parameter 'densityScale' must be finite and not negative, got " +
                std::to_string(density_scale));
  const float anisotropy = get_float("anisotropy", 0.f);
  if (!(anisotropy >= -1.f && anisotropy <= 1.f))
    throw Error(name() + ": parameter 'anisotropy' must be in [-1, 1], got " + std::to_string(anisotropy));
  const float gradient_shading_scale = get_float("gradientShadingScale", 0.f);
  if (!(gradient_shading_scale >= 0.f && gradient_shading_scale <= 1.f))
    throw Error(name() + ": parameter 'gradientShadingScale' must be in [0, 1], got " +
                std::to_string(gradient_shading_scale));
  const std::optional<std::uint32_t> user_id = get_user_id();

  std::lock_guard lock(mutex_);
  EngineVolumetricModel model;
  if (volume_of(model_) == volume_of(volume->volume()) && density_scale == density_scale_) {
    // The same engine volume: keep its macrocell ranges.
    model = model_;
    if (model_tf_version_ != tf->version() || transfer_function_.get() != tf.get())
      std::visit(
          [&](auto& m) {
            if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, std::monostate>)
              m.set_transfer_function(*tf->transfer_function());
          },
          model);
  } else {
    model = make_volumetric_model(volume->volume(), *tf->transfer_function(), density_scale);
  }
  std::visit(
      [&](auto& m) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, std::monostate>) {
          m.set_anisotropy(anisotropy);
          m.set_gradient_shading_scale(gradient_shading_scale);
        }
      },
      model);
  model_ = std::move(model);
  model_volume_version_ = volume->version();
  model_tf_version_ = tf->version();
  volume_ = std::move(volume);
  transfer_function_ = std::move(tf);
  density_scale_ = density_scale;
  anisotropy_ = anisotropy;
  gradient_shading_scale_ = gradient_shading_scale;
  user_id_ = user_id;
}

std::uint64_t VolumetricModelObject::version() const {
  std::uint64_t v = version_;
  if (volume_) v = std::max(v, volume_->version());
  if (transfer_function_) v = std::max(v, transfer_function_->version());
  return v;
}

EngineVolumetricModel VolumetricModelObject::engine_model(VolumeBuildStats& stats) {
  std::lock_guard lock(mutex_);
  ++stats.volumes;
  if (model_volume_version_ != volume_->version()) {
    model_ = make_volumetric_model(volume_->volume(), *transfer_function_->transfer_function(), density_scale_,
                                   anisotropy_, gradient_shading_scale_);
    model_volume_version_ = volume_->version();
    model_tf_version_ = transfer_function_->version();
    ++stats.macrocells_built;
  } else if (model_tf_version_ != transfer_function_->version()) {
    std::visit(
        [&](auto& m) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, std::monostate>)
            m.set_transfer_function(*transfer_function_->transfer_function());
        },
        model_);
    model_tf_version_ = transfer_function_->version();
    ++stats.transfer_functions;
  }
  return model_;
}

}  // namespace sciray::ospray
