// `import sciray`: the engine over numpy arrays (see python/sciray/__init__.py for the
// Python side and docs/python.md).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "scene.hpp"
#include "sciray/simd/arch.hpp"

namespace sciray_python {
void bind_render(py::module_& m);
void bind_readers(py::module_& m);
}  // namespace sciray_python

PYBIND11_MODULE(_sciray, m) {
  namespace py = pybind11;
  m.doc() = "sciray: CPU ray tracing for scientific visualization";
  // The engine's errors (bad values, unreadable files) are sciray.Error, a ValueError.
  py::register_exception<sciray::Error>(m, "Error", PyExc_ValueError);
  sciray_python::bind_scene(m);
  sciray_python::bind_render(m);
  sciray_python::bind_readers(m);
  m.def("isas", [] {
    std::vector<std::string> names;
    for (auto isa : sciray::simd::all_isas)
      if (sciray::simd::cpu_supports(isa)) names.emplace_back(sciray::simd::isa_name(isa));
    return names;
  }, "The ISAs this CPU runs (a Scene takes one by name, or 'auto': the widest)");
}
