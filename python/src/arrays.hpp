#pragma once
// numpy arrays as the engine reads them: shared without a copy where the dtype and layout
// are the engine's, converted into sciray's own storage otherwise, and refused with a
// Python exception naming the argument where the shape or dtype cannot mean what it must.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "sciray/geometry/data.hpp"
#include "sciray/volume/structured_regular.hpp"

namespace sciray_python {

namespace py = pybind11;

[[noreturn]] void type_error(std::string_view argument, const std::string& problem);
[[noreturn]] void value_error(std::string_view argument, const std::string& problem);

/// `object` as an ndarray of numbers (lists and anything with `__array__` are converted).
py::array numeric_array(py::handle object, std::string_view argument);

/// Rows of T as the engine reads them: a view into the caller's array (`copy` null), or
/// into a converted copy.
template <class T>
struct Rows {
  sciray::StridedView<T> view;
  std::shared_ptr<const sciray::PaddedVector<T>> copy;
  bool shared() const { return !copy; }
};

/// How an array argument may be read.
struct RowSpec {
  std::string_view argument;
  int columns = 3;  ///< values per row the engine reads; 1: a 1-D array
  /// A row of 3 colours may be given where 4 are read (alpha 1 is added).
  bool rgb_allowed = false;
  /// Embree reads up to 16 bytes past the last row (vertex and index buffers): shared
  /// only when the array is a view into a larger numpy buffer that has them.
  bool needs_slack = false;
};

/// A float32 view (shared when the array is float32 with rows of adjacent floats) or a
/// copy; non-finite values are left to the geometry's own checks, which name them.
Rows<float> float_rows(py::handle object, const RowSpec& spec);

/// Vertex indices: uint32 shared, other integer dtypes copied after checking each value
/// fits (negative or too large values are named).
Rows<std::uint32_t> index_rows(py::handle object, const RowSpec& spec);

/// Whether the memory after `a`'s last element is readable for `bytes` bytes: `a` is a
/// view into a larger numpy array that owns it.
bool readable_after(const py::array& a, std::size_t bytes);

/// A 3-D array of voxels, x fastest in memory: C order with shape (z, y, x) or Fortran
/// order with shape (x, y, z) (pyvista and VTK) are shared; others are copied in C order.
struct Voxels {
  py::array array;  ///< what the engine reads (the caller's, or a contiguous copy)
  sciray::VolumeDims dims{};
  bool shared = false;
};
Voxels voxels_of(py::handle object, std::string_view argument);

/// Three floats from a sequence (a position, a direction, a colour).
sciray::Vec3f vec3_of(py::handle object, std::string_view argument);

/// A new numpy array of `shape` with `bytes_after` readable bytes after its last element,
/// so that arrays made by sciray (the readers') share with Embree without a copy.
py::array padded_array(py::dtype dtype, std::vector<py::ssize_t> shape, std::size_t bytes_after = 16);

/// `values` (a flat vector) as a padded array of `shape`.
template <class T, class Vector>
py::array array_of(const Vector& values, std::vector<py::ssize_t> shape) {
  py::array a = padded_array(py::dtype::of<T>(), std::move(shape));
  std::copy(values.begin(), values.end(), static_cast<T*>(a.mutable_data()));
  return a;
}

}  // namespace sciray_python
