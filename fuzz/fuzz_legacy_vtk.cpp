// Legacy VTK files (.vtk), ascii and binary.
#include "fuzz_support.hpp"
#include "sciray/io/vtk_legacy.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = sciray_fuzz::write_file("f.vtk", sciray_fuzz::text_of(data, size));
  return sciray_fuzz::run([&] { sciray::io::read_legacy_vtk(path.string()); });
}
