// VTK XML poly data (.vtp).
#include "fuzz_support.hpp"
#include "sciray/io/vtk_polydata.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = sciray_fuzz::write_file("f.vtp", sciray_fuzz::text_of(data, size));
  return sciray_fuzz::run([&] { sciray::io::read_vtp(path.string()); });
}
