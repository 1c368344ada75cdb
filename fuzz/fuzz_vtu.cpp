// VTK XML unstructured grids (.vtu), then the volume the tool makes of the default array.
#include "fuzz_support.hpp"
#include "sciray/io/vtk.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = sciray_fuzz::write_file("f.vtu", sciray_fuzz::text_of(data, size));
  return sciray_fuzz::run([&] {
    const sciray::io::UnstructuredGridFile grid = sciray::io::read_vtu(path.string());
    sciray::io::unstructured_volume(grid, "", path.string());
  });
}
