// NRRD volumes: the input is "<v.nrrd>\n#@data\n<d.raw>", the second part a detached data
// file the header may name ("data file: d.raw"); without the separator, just v.nrrd.
#include "fuzz_support.hpp"
#include "sciray/io/volume.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto [nrrd, detached] = sciray_fuzz::split(sciray_fuzz::text_of(data, size), "\n#@data\n");
  const auto path = sciray_fuzz::write_file("v.nrrd", nrrd);
  if (detached.empty())
    sciray_fuzz::remove_file("d.raw");
  else
    sciray_fuzz::write_file("d.raw", detached);
  return sciray_fuzz::run([&] { sciray::io::read_volume(path); });
}
