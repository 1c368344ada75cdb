// Point clouds, parsed from memory: the first byte picks the format (.ply, .xyz, .xyzr,
// .f32xyzr), the rest is the file; a cloud that parses is made into spheres as the tool
// does, coloured by x (or by the file's colours when the second byte is odd).
#include "fuzz_support.hpp"
#include "sciray/io/points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  static constexpr sciray::io::PointFormat formats[] = {sciray::io::PointFormat::ply, sciray::io::PointFormat::xyz,
                                                        sciray::io::PointFormat::xyzr,
                                                        sciray::io::PointFormat::f32xyzr};
  sciray::io::PointOptions options;
  options.format = formats[data[0] % 4];
  const bool file_colors = data[1] % 2 == 1;
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data + 2), size - 2);
  return sciray_fuzz::run([&] {
    sciray::io::PointCloud cloud = sciray::io::parse_points(bytes, "fuzz.points", options);
    sciray::io::PointOptions spheres;
    if (file_colors)
      spheres.file_colors = true;
    else
      spheres.color_by = "x";
    sciray::io::to_spheres(std::move(cloud), spheres, [](float v) { return sciray::Vec3f{v, v, v}; });
  });
}
