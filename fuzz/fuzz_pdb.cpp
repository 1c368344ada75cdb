// PDB molecules, parsed from memory, with CONECT and distance bonds (the defaults).
#include "fuzz_support.hpp"
#include "sciray/io/pdb.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return sciray_fuzz::run([&] { sciray::io::parse_pdb(sciray_fuzz::text_of(data, size), "fuzz.pdb"); });
}
