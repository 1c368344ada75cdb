// Wavefront .obj with its .mtl and a texture: the input is "<obj>\n#@mtl\n<mtl>\n#@pfm\n<pfm>",
// written as f.obj, f.mtl and t.pfm in a scratch folder (a part left out is no file), so
// the .obj reaches the library with "mtllib f.mtl" and the library the texture with "map_Kd t.pfm".
#include "fuzz_support.hpp"
#include "sciray/io/obj.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto [obj, rest] = sciray_fuzz::split(sciray_fuzz::text_of(data, size), "\n#@mtl\n");
  const auto [mtl, pfm] = sciray_fuzz::split(rest, "\n#@pfm\n");
  const auto path = sciray_fuzz::write_file("f.obj", obj);
  if (mtl.empty())
    sciray_fuzz::remove_file("f.mtl");
  else
    sciray_fuzz::write_file("f.mtl", mtl);
  if (pfm.empty())
    sciray_fuzz::remove_file("t.pfm");
  else
    sciray_fuzz::write_file("t.pfm", pfm);
  return sciray_fuzz::run([&] { sciray::io::read_obj(path); });
}
