#include "arrays.hpp"

#include <cmath>
#include <limits>

#include <pybind11/stl.h>

namespace sciray_python {

void type_error(std::string_view argument, const std::string& problem) {
  throw py::type_error(std::string(argument) + ": " + problem);
}

void value_error(std::string_view argument, const std::string& problem) {
  throw py::value_error(std::string(argument) + ": " + problem);
}

namespace {

std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

template <class T>
bool is_dtype(const py::array& a) {
  return py::isinstance<py::array_t<T>>(a);
}

bool aligned(const void* p, std::size_t alignment) { return reinterpret_cast<std::uintptr_t>(p) % alignment == 0; }

/// Rows of `columns` values (1: a 1-D array); `rgb_allowed`: 3 where 4 are read.
py::ssize_t check_shape(const py::array& a, const RowSpec& spec) {
  if (spec.columns == 1) {
    if (a.ndim() != 1) value_error(spec.argument, "expected a 1-D array, got shape " + shape_text(a));
    return 1;
  }
  const bool ok = a.ndim() == 2 && (a.shape(1) == spec.columns || (spec.rgb_allowed && a.shape(1) == 3));
  if (!ok)
    value_error(spec.argument, "expected shape (N, " + std::to_string(spec.columns) + ")" +
                                   (spec.rgb_allowed ? " or (N, 3)" : "") + ", got " + shape_text(a));
  return a.shape(1);
}

/// Whether rows of `a` can be read in place as `columns` adjacent values of `size` bytes.
bool rows_in_place(const py::array& a, const RowSpec& spec, py::ssize_t given, std::size_t size) {
  if (given != spec.columns || a.shape(0) == 0 || !aligned(a.data(), size)) return false;
  if (spec.columns > 1 && a.strides(1) != static_cast<py::ssize_t>(size)) return false;
  const py::ssize_t row = a.strides(0);
  if (row < static_cast<py::ssize_t>(size) * spec.columns || row % static_cast<py::ssize_t>(size) != 0) return false;
  return !spec.needs_slack || readable_after(a, sciray::embree_buffer_padding);
}

}  // namespace

py::array numeric_array(py::handle object, std::string_view argument) {
  if (object.is_none()) type_error(argument, "expected an array, got None");
  py::array a = py::array::ensure(object);
  if (!a)
    type_error(argument, "expected an array of numbers, got " + py::str(py::type::handle_of(object).attr("__name__")).cast<std::string>());
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    type_error(argument, "expected numbers (a float or integer dtype), got dtype " + dtype_text(a));
  return a;
}

bool readable_after(const py::array& a, std::size_t bytes) {
  if (a.size() == 0) return false;
  const char* begin = static_cast<const char*>(a.data());
  py::ssize_t last = 0;
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    if (a.strides(d) < 0) return false;
    last += (a.shape(d) - 1) * a.strides(d);
  }
  const char* end = begin + last + a.itemsize();
  for (py::handle base = a.base(); base && py::isinstance<py::array>(base);) {
    const auto owner = py::reinterpret_borrow<py::array>(base);
    if (owner.owndata()) {
      const char* start = static_cast<const char*>(owner.data());
      const bool contiguous = (owner.flags() & py::array::c_style) != 0;
      return contiguous && begin >= start && end + bytes <= start + owner.nbytes();
    }
    base = owner.base();
  }
  return false;
}

Rows<float> float_rows(py::handle object, const RowSpec& spec) {
  const py::array a = numeric_array(object, spec.argument);
  const py::ssize_t given = check_shape(a, spec);
  const auto n = static_cast<std::size_t>(a.shape(0));
  Rows<float> rows;
  if (is_dtype<float>(a) && rows_in_place(a, spec, given, sizeof(float))) {
    rows.view = {static_cast<const float*>(a.data()), n, static_cast<std::size_t>(a.strides(0))};
    return rows;
  }
  const auto values = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  auto copy = std::make_shared<sciray::PaddedVector<float>>();
  copy->reserve(n * static_cast<std::size_t>(spec.columns));
  const float* v = values.data();
  for (std::size_t i = 0; i < n; ++i) {
    for (py::ssize_t c = 0; c < given; ++c) copy->push_back(v[i * static_cast<std::size_t>(given) + static_cast<std::size_t>(c)]);
    if (given < spec.columns) copy->push_back(1.f);  // the alpha of an RGB colour
  }
  rows.view = {copy->data(), n, static_cast<std::size_t>(spec.columns) * sizeof(float)};
  rows.copy = std::move(copy);
  return rows;
}

Rows<std::uint32_t> index_rows(py::handle object, const RowSpec& spec) {
  const py::array a = numeric_array(object, spec.argument);
  if (a.dtype().kind() == 'f') type_error(spec.argument, "expected integers, got dtype " + dtype_text(a));
  const py::ssize_t given = check_shape(a, spec);
  const auto n = static_cast<std::size_t>(a.shape(0));
  Rows<std::uint32_t> rows;
  const std::size_t stride = static_cast<std::size_t>(spec.columns) * sizeof(std::uint32_t);
  if (is_dtype<std::uint32_t>(a) && rows_in_place(a, spec, given, sizeof(std::uint32_t))) {
    rows.view = {static_cast<const std::uint32_t*>(a.data()), n, static_cast<std::size_t>(a.strides(0))};
    return rows;
  }
  auto copy = std::make_shared<sciray::PaddedVector<std::uint32_t>>();
  copy->reserve(n * static_cast<std::size_t>(spec.columns));
  const auto name = [&](std::size_t k) {
    return std::string(spec.argument) + "[" + std::to_string(k / static_cast<std::size_t>(given)) +
           (spec.columns > 1 ? ", " + std::to_string(k % static_cast<std::size_t>(given)) : std::string()) + "]";
  };
  constexpr auto largest = std::numeric_limits<std::uint32_t>::max();
  if (a.dtype().kind() == 'u') {
    const auto values = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    for (py::ssize_t k = 0; k < values.size(); ++k) {
      if (values.data()[k] > largest)
        throw py::value_error(name(static_cast<std::size_t>(k)) + " = " + std::to_string(values.data()[k]) +
                              " is beyond the largest index, 2^32 - 1");
      copy->push_back(static_cast<std::uint32_t>(values.data()[k]));
    }
  } else {
    const auto values = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    for (py::ssize_t k = 0; k < values.size(); ++k) {
      const std::int64_t v = values.data()[k];
      if (v < 0) throw py::value_error(name(static_cast<std::size_t>(k)) + " = " + std::to_string(v) + " is negative");
      if (v > static_cast<std::int64_t>(largest))
        throw py::value_error(name(static_cast<std::size_t>(k)) + " = " + std::to_string(v) +
                              " is beyond the largest index, 2^32 - 1");
      copy->push_back(static_cast<std::uint32_t>(v));
    }
  }
  rows.view = {copy->data(), n, stride};
  rows.copy = std::move(copy);
  return rows;
}

Voxels voxels_of(py::handle object, std::string_view argument) {
  py::array a = numeric_array(object, argument);
  if (a.ndim() != 3) value_error(argument, "expected a 3-D array, got shape " + shape_text(a));
  const bool voxel_type = is_dtype<std::uint8_t>(a) || is_dtype<std::int16_t>(a) || is_dtype<std::uint16_t>(a) ||
                          is_dtype<float>(a) || is_dtype<double>(a);
  Voxels v;
  if (voxel_type && (a.flags() & py::array::c_style)) {
    v.array = a, v.dims = {a.shape(2), a.shape(1), a.shape(0)}, v.shared = true;
  } else if (voxel_type && (a.flags() & py::array::f_style)) {
    v.array = a, v.dims = {a.shape(0), a.shape(1), a.shape(2)}, v.shared = true;
  } else {
    // Other dtypes (int8, int32, float16, ...) become float32; strided arrays a C-order copy.
    const py::object dtype = voxel_type ? py::object(a.dtype()) : py::object(py::dtype::of<float>());
    v.array = py::module_::import("numpy").attr("ascontiguousarray")(a, dtype);
    v.dims = {a.shape(2), a.shape(1), a.shape(0)};
  }
  return v;
}

sciray::Vec3f vec3_of(py::handle object, std::string_view argument) {
  const py::array a = numeric_array(object, argument);
  if (a.size() != 3) value_error(argument, "expected 3 numbers, got shape " + shape_text(a));
  const auto values = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  const sciray::Vec3f v{values.data()[0], values.data()[1], values.data()[2]};
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) value_error(argument, "is not finite");
  return v;
}

py::array padded_array(py::dtype dtype, std::vector<py::ssize_t> shape, std::size_t bytes_after) {
  py::ssize_t count = 1;
  for (py::ssize_t extent : shape) count *= extent;
  const py::ssize_t bytes = count * dtype.itemsize();
  py::array_t<std::uint8_t> buffer(bytes + static_cast<py::ssize_t>(bytes_after));
  return buffer[py::slice(0, bytes, 1)].attr("view")(dtype).attr("reshape")(py::tuple(py::cast(shape)));
}

}  // namespace sciray_python
