// PLY meshes, parsed from memory: as they are, then (when that succeeds) with texture
// coordinates made from the x property, which takes the PlyOptions::texcoord_from path.
#include "fuzz_support.hpp"
#include "sciray/io/ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  return sciray_fuzz::run([&] {
    sciray::io::parse_ply(bytes, "fuzz.ply");
    sciray::io::parse_ply(bytes, "fuzz.ply", {.texcoord_from = "x"});
  });
}
