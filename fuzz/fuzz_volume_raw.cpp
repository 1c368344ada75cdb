// Raw volumes with a JSON sidecar: the input is "<sidecar JSON>\n#@raw\n<voxels>", written as
// v.json and v.raw (no separator: a sidecar and an empty v.raw).
#include "fuzz_support.hpp"
#include "sciray/io/volume.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto [sidecar, voxels] = sciray_fuzz::split(sciray_fuzz::text_of(data, size), "\n#@raw\n");
  sciray_fuzz::write_file("v.json", sidecar);
  const auto path = sciray_fuzz::write_file("v.raw", voxels);
  return sciray_fuzz::run([&] { sciray::io::read_volume(path); });
}
