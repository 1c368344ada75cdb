// The `sciray` command-line tool end to end: real data in, image and JSON report out,
// and clear errors (non-zero exit, message naming the problem) for bad input.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include <nlohmann/json.hpp>

#include "sciray/io/image.hpp"

namespace {

struct Run {
  int exit_code;
  std::string output;  // stdout and stderr
};

/// Runs a shell command line, collecting what it prints; exit_code -1 when a signal ended it.
Run run_shell(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe);
  std::string output;
  std::array<char, 4096> buffer;
  while (const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

Run run_tool(const std::string& arguments) { return run_shell(std::string(SCIRAY_TOOL) + " " + arguments + " 2>&1"); }

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "sciray_tool_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

/// How many pixels of the image `png` differ from its corner pixel (the background) in
/// green by more than 0.01: how much of the picture the scene covers.
int covered_pixels(const std::filesystem::path& png) {
  const sciray::io::Image image = sciray::io::read_image(png.string());
  int n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += std::abs(image.at(x, y, 1) - image.at(0, 0, 1)) > 0.01f;
  return n;
}

}  // namespace

TEST_CASE("sciray render: a real mesh to PNG with a JSON report", "[tool]") {
  const auto out = scratch("bunny.png");
  const Run run = run_tool("render " SCIRAY_DATA_DIR "/meshes/bunny.ply --size 160x120 --frames 3 --threads 2 "
                           "--isa sse4.2 --json -o " + out.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto report = nlohmann::json::parse(run.output);
  CHECK(report["triangles"] == 69451);
  CHECK(report["vertices"] == 35947);
  CHECK(report["isa"] == "sse4.2");
  CHECK(report["simd_width"] == 4);
  CHECK(report["threads"] == 2);
  CHECK(report["frame_ms"].size() == 3);
  CHECK(report["load_ms"].get<double>() > 0);
  CHECK(report["bvh_build_ms"].get<double>() > 0);
  // Vertices and indices alone are 35947*12 + 69451*12 bytes; the BVH is extra.
  CHECK(report["memory_bytes"]["geometry"].get<double>() >= 35947 * 12 + 69451 * 12);
  CHECK(report["memory_bytes"]["bvh"].get<double>() > 0);

  const auto image = sciray::io::read_png(out);
  CHECK(image.width == 160);
  CHECK(image.height == 120);
  // The framed bunny covers the centre and leaves the corners to the background.
  CHECK(image.at(80, 60, 0) != image.at(0, 0, 0));
}

TEST_CASE("sciray render: the built-in scene, a camera file and float output", "[tool]") {
  const auto camera = scratch("cam.json");
  std::ofstream(camera) << R"({"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fovy": 50})";
  const auto out = scratch("torus.pfm"), depth = scratch("torus_depth.pfm");
  const Run run = run_tool("render --camera " + camera.string() + " --size 64x64 -o " + out.string() + " --depth " +
                           depth.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto color = sciray::io::read_pfm(out), distance = sciray::io::read_pfm(depth);
  CHECK(color.width == 64);
  // Looking straight down on the torus (ring radius 1, tube radius 0.35, waves of at most
  // 0.09): its hole at the centre shows the background (infinite depth); row 6 from the
  // top looks at the top of the tube, 3 - 0.35 below the camera along the view axis.
  CHECK(std::isinf(distance.at(32, 32, 0)));
  const double slope = (2.0 * (63 - 6 + 0.5) / 64 - 1) * std::tan(25.0 * M_PI / 180);
  CHECK(distance.at(32, 6, 0) == Approx(2.65 * std::sqrt(1 + slope * slope)).margin(0.1));
}

TEST_CASE("sciray render: standard scenes by name", "[tool]") {
  const auto out = scratch("cornell.pfm");
  const Run run = run_tool("render builtin:cornell_box --size 64x64 -o " + out.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto image = sciray::io::read_pfm(out);
  // The published camera looks down +z with +y up, so +x (the red wall) is on the left
  // and the green wall on the right; both span the middle row's outer pixels.
  const float left_r = image.at(2, 32, 0), left_g = image.at(2, 32, 1);
  const float right_r = image.at(61, 32, 0), right_g = image.at(61, 32, 1);
  CHECK(left_r > 2 * left_g);
  CHECK(right_g > 2 * right_r);

  const Run unknown = run_tool("render builtin:teapot --size 8x8");
  CHECK(unknown.exit_code == 1);
  CHECK_THAT(unknown.output, Catch::Contains("unknown standard scene 'teapot'") && Catch::Contains("cornell_box"));
}

TEST_CASE("sciray render: molecules as balls and sticks or space filling", "[tool][pdb]") {
  const auto out = scratch("lysozyme.png");
  const Run sticks = run_tool("render " SCIRAY_DATA_DIR "/molecules/2LYZ.pdb --size 96x96 --json -o " + out.string());
  INFO(sticks.output);
  REQUIRE(sticks.exit_code == 0);
  const auto report = nlohmann::json::parse(sticks.output);
  CHECK(report["spheres"] == 1001);          // waters are skipped
  CHECK(report["curve_segments"] == 2 * 1032);  // each bond is two half-bonds
  // A sphere costs its 16 bytes of centre and radius plus colour and BVH; a tessellated
  // sphere of 80 triangles would cost several kilobytes (docs/performance.md).
  CHECK(report["bytes_per_primitive"].get<double>() < 200);
  const auto image = sciray::io::read_png(out);
  CHECK(image.at(48, 48, 0) != image.at(0, 0, 0));

  const Run filled = run_tool("render " SCIRAY_DATA_DIR "/molecules/3GQP.pdb --style space-filling --size 64x64 "
                              "--sphere-intersector embree --json -o " + scratch("3gqp.png").string());
  INFO(filled.output);
  REQUIRE(filled.exit_code == 0);
  const auto filled_report = nlohmann::json::parse(filled.output);
  CHECK(filled_report["spheres"] == 4576);
  CHECK(filled_report["curve_segments"] == 0);
  CHECK(filled_report["sphere_intersector"] == "embree");
}

TEST_CASE("sciray render: instances and clipping", "[tool][instancing][clipping]") {
  const Run boxes = run_tool("render builtin:instanced_boxes --size 64x64 --json -o " + scratch("boxes.png").string());
  INFO(boxes.output);
  REQUIRE(boxes.exit_code == 0);
  const auto report = nlohmann::json::parse(boxes.output);
  CHECK(report["instances"] == 10000);
  CHECK(report["boxes"] == 8);
  // 10,000 instances of 8 boxes: the top-level BVH, about 100 bytes an instance.
  CHECK(report["memory_bytes"]["total"].get<double>() < 10000 * 200);

  // The bunny cut in half by a plane through its centre: the kept half's pixels only.
  const auto whole = scratch("whole.pfm"), half = scratch("half.pfm");
  const std::string bunny = "render " SCIRAY_DATA_DIR "/meshes/bunny.ply --size 64x64 -o ";
  REQUIRE(run_tool(bunny + whole.string()).exit_code == 0);
  const Run clipped = run_tool(bunny + half.string() + " --clip-plane 1,0,0,0.0168");
  INFO(clipped.output);
  REQUIRE(clipped.exit_code == 0);
  const auto a = sciray::io::read_pfm(whole), b = sciray::io::read_pfm(half);
  int covered_whole = 0, covered_half = 0;
  const float background = a.at(0, 0, 0);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) covered_whole += a.at(x, y, 0) != background, covered_half += b.at(x, y, 0) != background;
  CHECK(covered_half < covered_whole * 3 / 4);
  CHECK(covered_half > covered_whole / 4);
}

TEST_CASE("sciray render: volumes through a transfer function and as isosurfaces", "[tool][volume]") {
  const auto out = scratch("neghip.pfm");
  const Run dvr = run_tool("render " SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw --size 48x48 --json --layout bricked "
                           "--sampling-rate 2 -o " + out.string());
  INFO(dvr.output);
  REQUIRE(dvr.exit_code == 0);
  const auto report = nlohmann::json::parse(dvr.output);
  CHECK(report["volumes"] == 1);
  CHECK(report["volume"]["dims"] == nlohmann::json::array({66, 66, 66}));
  CHECK(report["volume"]["type"] == "uint8");
  // Bricked voxels are a copy: at least the 66³ bytes.
  CHECK(report["memory_bytes"]["total"].get<double>() >= 66.0 * 66 * 66);
  const auto image = sciray::io::read_pfm(out);
  CHECK(image.at(24, 24, 1) != image.at(0, 0, 1));  // the protein's density shows in the middle

  const auto tf = scratch("tf.json");
  std::ofstream(tf) << R"({"colors": [[1, 0, 0], [1, 1, 0]], "opacities": [0, 0.2, 1], "range": [50, 200]})";
  const Run custom = run_tool("render " SCIRAY_DATA_DIR "/volumes/hydrogen_64x64x64_float32.raw --size 32x32 --tf " +
                              tf.string() + " -o " + scratch("hydrogen.png").string());
  INFO(custom.output);
  CHECK(custom.exit_code == 0);

  const Run iso = run_tool("render " SCIRAY_DATA_DIR "/volumes/headsq_64x64x93_uint16.raw --iso 1000 --size 48x48 --json -o " +
                           scratch("headsq.png").string());
  INFO(iso.output);
  REQUIRE(iso.exit_code == 0);
  CHECK(nlohmann::json::parse(iso.output)["volumes"] == 0);  // surfaces only

  // The procedural standard volumes come through the same path.
  const Run gravity = run_tool("render builtin:gravity_spheres_128 --size 16x16 --json -o " + scratch("g.png").string());
  INFO(gravity.output);
  REQUIRE(gravity.exit_code == 0);
  CHECK(nlohmann::json::parse(gravity.output)["volume"]["dims"] == nlohmann::json::array({128, 128, 128}));

  // A slice through the middle of the hydrogen density: coloured where it cuts the volume.
  const auto slice = scratch("slice.pfm");
  const Run sliced = run_tool("render " SCIRAY_DATA_DIR "/volumes/hydrogen_64x64x64_float32.raw --slice 0,0,1,-31.5 "
                              "--size 32x32 -o " + slice.string());
  INFO(sliced.output);
  REQUIRE(sliced.exit_code == 0);
  const auto cut = sciray::io::read_pfm(slice);
  CHECK(cut.at(16, 16, 0) != cut.at(0, 0, 0));
}

TEST_CASE("sciray reports bad input clearly", "[tool][errors]") {
  const auto truncated = scratch("truncated.ply");
  {
    std::ifstream in(SCIRAY_DATA_DIR "/meshes/lucy.ply", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const auto truncated_pdb = scratch("truncated.pdb");
  {
    std::ifstream in(SCIRAY_DATA_DIR "/molecules/2LYZ.pdb");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    // Cut inside the coordinates of an ATOM record.
    std::ofstream(truncated_pdb) << text.substr(0, text.find("\nATOM", text.size() / 2) + 40);
  }
  const auto bad_camera = scratch("bad_cam.json");
  std::ofstream(bad_camera) << R"({"position": [0, 0], "look_at": [0, 0, -1]})";

  const std::pair<std::string, std::string> cases[] = {
      {"render " + truncated.string(), "truncated"},
      {"render /nonexistent.ply", "/nonexistent.ply"},
      {"render --isa avx9000", "unknown ISA 'avx9000'"},
      {"render --size 12by7", "--size"},
      {"render --frames 0", "--frames"},
      {"render --camera " + bad_camera.string(), "\"position\" must be an array of 3 numbers"},
      {"render -o image.bmp --size 8x8", "unknown image extension"},
      {"render " SCIRAY_DATA_DIR "/molecules/2LYZ.pdb --style cartoon", "unknown molecule style 'cartoon'"},
      {"render " SCIRAY_DATA_DIR "/molecules/2LYZ.pdb --sphere-intersector naive", "--sphere-intersector"},
      {"render " + truncated_pdb.string(), "truncated.pdb: line"},
      {"render --size 8x8 --clip-plane 1,0,0", "--clip-plane: expected 4 comma-separated numbers"},
      {"render " SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw --layout diagonal --size 8x8", "--layout"},
      {"render " SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw --tf " + bad_camera.string() + " --size 8x8",
       "expected an object with \"colors\" and \"opacities\""},
      {"render --size 8x8 --clip-sphere 0,0,0,x", "--clip-sphere: 'x' is not a finite number"},
      {"render --size 8x8 --clip-sphere 0,0,0,-1", "positive radius"},
      {"render " SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw --slice 0,0,1 --size 8x8", "--slice: expected 4"},
  };
  for (const auto& [arguments, expected] : cases) {
    const Run run = run_tool(arguments);
    INFO(arguments << "\n" << run.output);
    CHECK(run.exit_code == 1);
    CHECK_THAT(run.output, Catch::Contains(expected) && Catch::Contains("sciray: error"));
  }
}

TEST_CASE("sciray info and SCIRAY_ISA", "[tool]") {
  const Run info = run_tool("info");
  REQUIRE(info.exit_code == 0);
  CHECK_THAT(info.output, Catch::Contains("supported ISAs:") && Catch::Contains("scalar"));
  const Run forced = run_tool("info --isa scalar");
  CHECK_THAT(forced.output, Catch::Contains("chosen: scalar (1 lanes)"));
  const Run env = run_tool("info 2>&1; SCIRAY_ISA=sse4.2 " SCIRAY_TOOL " info");
  CHECK_THAT(env.output, Catch::Contains("chosen: sse4.2"));
  const Run bad_env = run_tool("info; SCIRAY_ISA=mmx " SCIRAY_TOOL " info");
  CHECK_THAT(bad_env.output, Catch::Contains("SCIRAY_ISA: unknown ISA 'mmx'"));
}

TEST_CASE("sciray render: the path tracer, ao and scivis with materials and lights", "[tool][renderers]") {
  const auto out = scratch("cornell_pt.pfm");
  const Run run = run_tool("render builtin:cornell_box --renderer pathtracer --spp 16 --size 32x32 --json -o " +
                           out.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK(nlohmann::json::parse(run.output)["renderer"] == "pathtracer");
  const auto image = sciray::io::read_pfm(out);
  // Lit only by the ceiling's quad light: red wall on the left, green on the right, and
  // the light itself brighter than any wall.
  CHECK(image.at(1, 16, 0) > 2 * image.at(1, 16, 1));
  CHECK(image.at(30, 16, 1) > 2 * image.at(30, 16, 0));

  // A principled metal on the bunny under a sphere light, through the ao renderer too.
  const auto metal = scratch("bunny_metal.pfm");
  const Run shaded = run_tool(
      "render " SCIRAY_DATA_DIR "/meshes/bunny.ply --renderer pathtracer --size 24x24 "
      "--material '{\"type\":\"principled\",\"metallic\":1,\"roughness\":0.3,\"baseColor\":[0.9,0.6,0.2]}' "
      "--light '{\"type\":\"sphere\",\"position\":[0,1,1],\"radius\":0.1,\"intensity\":2}' "
      "--light '{\"type\":\"ambient\",\"intensity\":0.3}' -o " + metal.string());
  INFO(shaded.output);
  CHECK(shaded.exit_code == 0);
  const Run ao = run_tool("render " SCIRAY_DATA_DIR "/molecules/2LYZ.pdb --renderer ao --ao-samples 2 --size 24x24 -o " +
                          scratch("lysozyme_ao.png").string());
  INFO(ao.output);
  CHECK(ao.exit_code == 0);

  // A mix of a red and a blue Lambertian under an ambient light, one bounce: every pixel of
  // the bunny shows 0.75 of red to 0.25 of blue (the obj of the mixed kd), no green.
  const auto mixed = scratch("bunny_mix.pfm");
  const Run mix = run_tool(
      "render " SCIRAY_DATA_DIR "/meshes/bunny.ply --renderer pathtracer --size 24x24 --spp 4 --max-path-length 1 "
      "--material '{\"type\":\"mix\",\"factor\":0.25,\"material1\":{\"type\":\"obj\",\"kd\":[1,0,0]},"
      "\"material2\":{\"type\":\"obj\",\"kd\":[0,0,1]}}' --light '{\"type\":\"ambient\",\"intensity\":1}' -o " +
      mixed.string());
  INFO(mix.output);
  REQUIRE(mix.exit_code == 0);
  const auto mixed_image = sciray::io::read_pfm(mixed);
  double red = 0., blue = 0.;
  int bunny = 0;
  for (int y = 0; y < mixed_image.height; ++y)
    for (int x = 0; x < mixed_image.width; ++x)
      if (mixed_image.at(x, y, 1) == 0.f && mixed_image.at(x, y, 0) > 0.f) {
        ++bunny;
        red += mixed_image.at(x, y, 0), blue += mixed_image.at(x, y, 2);
      }
  CHECK(bunny > 50);
  CHECK(red / blue == Approx(3.).epsilon(1e-3));
}

TEST_CASE("sciray render: the pathtracer scatters in a real volume by --anisotropy", "[tool][renderers][volume]") {
  // neghip lit from behind (the light travels towards the camera): forward scattering
  // sends light on to the camera, back scattering returns it to the light's side.
  const auto camera = scratch("neghip_cam.json");
  std::ofstream(camera) << R"({"position": [32.5, -120, 32.5], "look_at": [32.5, 32.5, 32.5], "up": [0, 0, 1], "fovy": 35})";
  const auto mean_with = [&](const std::string& g) {
    const auto out = scratch("neghip_g" + g + ".pfm");
    const Run run = run_tool("render " SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw --renderer pathtracer "
                             "--size 32x32 --spp 8 --density 0.05 --anisotropy " + g + " --camera " + camera.string() +
                             " --light '{\"type\":\"distant\",\"direction\":[0,-1,0],\"intensity\":3}' -o " +
                             out.string());
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const auto image = sciray::io::read_pfm(out);
    double sum = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) sum += image.at(x, y, 1);
    return sum / (image.width * image.height);
  };
  const double forward = mean_with("0.8"), back = mean_with("-0.8");
  INFO("forward " << forward << ", back " << back);
  CHECK(back > 0.0);
  CHECK(forward > 2 * back);  // measured: 2.9 times
  const Run bad = run_tool("render " SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw --size 8x8 --anisotropy 1.2 -o " +
                           scratch("bad.png").string());
  CHECK(bad.exit_code == 1);
  CHECK_THAT(bad.output, Catch::Contains("'anisotropy' must be in [-1, 1], got 1.2"));
}

TEST_CASE("sciray render: bad renderers, materials and lights are named", "[tool][renderers][errors]") {
  const auto error_of = [](const std::string& arguments) {
    const Run run = run_tool("render builtin:cornell_box --size 8x8 -o " + scratch("bad.png").string() + " " + arguments);
    CHECK(run.exit_code == 1);
    return run.output;
  };
  CHECK_THAT(error_of("--renderer raytracer"), Catch::Contains("--renderer: expected scivis, ao or pathtracer"));
  CHECK_THAT(error_of("--material '{\"type\":\"obj\",\"kd\":[1,2]}'"),
             Catch::Contains("--material 1: \"kd\" must be a number or an array of 3 numbers"));
  CHECK_THAT(error_of("--material '{\"type\":\"obj\",\"kdd\":0.5}'"), Catch::Contains("unknown parameter \"kdd\""));
  CHECK_THAT(error_of("--material '{\"type\":\"metal\",\"roughness\":2}'"),
             Catch::Contains("metal material: parameter 'roughness' must be in [0, 1]"));
  CHECK_THAT(error_of("--material '{\"type\":\"mix\",\"material1\":{\"type\":\"obj\"}}'"),
             Catch::Contains("mix material: parameter 'material2' (the material it mixes) is missing"));
  CHECK_THAT(error_of("--material '{\"type\":\"mix\",\"material1\":{\"type\":\"obj\",\"d\":3},"
                      "\"material2\":{\"type\":\"metal\"}}'"),
             Catch::Contains("--material 1 material1: obj material: parameter 'd' must be in [0, 1]"));
  CHECK_THAT(error_of("--material '{\"type\":\"mix\",\"material1\":[1],\"material2\":{\"type\":\"metal\"}}'"),
             Catch::Contains("\"material1\" must be a JSON object"));
  CHECK_THAT(error_of("--light '{\"type\":\"spot\",\"openingAngle\":0}'"),
             Catch::Contains("spot light: parameter 'openingAngle' must be in (0, 360] degrees"));
  CHECK_THAT(error_of("--light '{\"type\":\"sun\"}'"), Catch::Contains("unknown light type 'sun'"));
  CHECK_THAT(error_of("--light '{not json'"), Catch::Contains("--light: invalid JSON"));
  CHECK_THAT(error_of("--spp 0"), Catch::Contains("'pixelSamples' must be at least 1"));
}

TEST_CASE("sciray render: an error target stops accumulation, filters, tonemapping and cameras", "[tool][frame]") {
  const Run run = run_tool("render builtin:cornell_box --renderer pathtracer --size 32x32 --frames 500 "
                           "--error-target 0.05 --json -o " + scratch("target.png").string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto report = nlohmann::json::parse(run.output);
  CHECK(report["frames"].get<int>() < 500);
  CHECK(report["frames"].get<int>() >= 2);
  CHECK(report["estimated_error"].get<double>() <= 0.05);
  CHECK(report["frame_ms"].size() == report["frames"].get<std::size_t>());

  const Run styled = run_tool("render " SCIRAY_DATA_DIR "/meshes/bunny.ply --size 24x24 --frames 2 --tonemap "
                              "--pixel-filter blackman_harris --aperture 0.01 --focus 0.3 -o " +
                              scratch("styled.png").string());
  INFO(styled.output);
  CHECK(styled.exit_code == 0);
  const Run panorama = run_tool("render builtin:cornell_box --panoramic --size 32x16 -o " + scratch("pano.png").string());
  INFO(panorama.output);
  CHECK(panorama.exit_code == 0);
  const Run bad = run_tool("render builtin:cornell_box --size 8x8 --pixel-filter cubic -o " + scratch("bad.png").string());
  CHECK(bad.exit_code == 1);
  CHECK_THAT(bad.output, Catch::Contains("--pixel-filter: expected point, box, gauss"));
  const Run negative = run_tool("render builtin:cornell_box --size 8x8 --aperture -1 -o " + scratch("bad.png").string());
  CHECK(negative.exit_code == 1);
  CHECK_THAT(negative.output, Catch::Contains("apertureRadius"));
}

TEST_CASE("sciray render: a VTK unstructured grid, its array picked with --field", "[tool][vtk]") {
  const auto out = scratch("can.png");
  const Run run = run_tool("render " SCIRAY_DATA_DIR "/unstructured/can.vtu --field EQPS --size 64x48 --json -o " +
                           out.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto report = nlohmann::json::parse(run.output);
  CHECK(report["volumes"] == 1);
  CHECK(report["volume"]["dims"][0] == 4800);
  CHECK(report["volume"]["type"] == "unstructured (51 folded cells)");
  // The can is seen: some pixels are not the background.
  CHECK(covered_pixels(out) > 50);
  const Run missing = run_tool("render " SCIRAY_DATA_DIR "/unstructured/can.vtu --field pressure -o " + out.string());
  CHECK(missing.exit_code != 0);
  CHECK_THAT(missing.output, Catch::Contains("can.vtu: has no array 'pressure' (its arrays: 'DISPL', 'VEL', 'ACCL', "
                                             "'GlobalNodeId', 'PedigreeNodeId', 'EQPS')"));
}

TEST_CASE("sciray render --iso: isosurfaces of VTK unstructured grids, cell arrays averaged to the vertices",
          "[tool][vtk][isosurface]") {
  // The jaw's von Mises stress is given per cell: averaged to the vertices, its surface of
  // 5 psi is drawn (and said so); the can's displacement is given per vertex (a thin
  // shell of hexahedra: its surface of 10 is a narrow band across the view).
  for (const auto& [file, args, averaged, least] : {std::tuple{"kiefer_jaw.vtu", " --iso 5", true, 100},
                                                     std::tuple{"can.vtu", " --field DISPL --iso 10", false, 30}}) {
    INFO(file);
    const auto out = scratch(std::string("iso_") + file + ".png");
    const Run run = run_tool(std::string("render " SCIRAY_DATA_DIR "/unstructured/") + file + args +
                             " --size 128x96 --json -o " + out.string());
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    const auto report = nlohmann::json::parse(run.output);
    CHECK(report["volumes"] == 0);
    CHECK((report["volume"]["type"].get<std::string>().find("averaged to the vertices") != std::string::npos) == averaged);
    CHECK(covered_pixels(out) > least);
  }
}

TEST_CASE("sciray render: VTK image data, poly data and point clouds", "[tool][vtk]") {
  // The stars: 107,857 points and no polygons, drawn as spheres coloured by colour index.
  const auto stars = scratch("stars.png");
  const Run run = run_tool("render " SCIRAY_DATA_DIR "/points/stars.vtp --color-by ci --size 64x48 --json -o " +
                           stars.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto report = nlohmann::json::parse(run.output);
  CHECK(report["spheres"] == 107857);
  CHECK(report["triangles"] == 0);
  CHECK(covered_pixels(stars) > 50);
  // Sized by luminosity: the brighter stars grow, so more of the picture is covered.
  const auto by_lum_png = scratch("stars_by_lum.png");
  const Run by_lum = run_tool("render " SCIRAY_DATA_DIR "/points/stars.vtp --color-by ci --radius-by lum "
                              "--radius-exponent 0.25 --size 64x48 -o " + by_lum_png.string());
  INFO(by_lum.output);
  REQUIRE(by_lum.exit_code == 0);
  CHECK(covered_pixels(by_lum_png) > covered_pixels(stars));
  const Run no_array = run_tool("render " SCIRAY_DATA_DIR "/points/stars.vtp --radius-by mass -o " + by_lum_png.string());
  CHECK(no_array.exit_code != 0);
  CHECK(no_array.output.find("--radius-by: no point array 'mass' of one component") != std::string::npos);

  // Image data written here, f = x + 2y + 3z on 4³ points: a structured volume whose
  // isosurface f = 6 is drawn.
  const auto vti = scratch("ramp.vti");
  {
    std::ofstream f(vti);
    f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "<ImageData WholeExtent=\"0 3 0 3 0 3\" Origin=\"0 0 0\" Spacing=\"1 1 1\"><Piece Extent=\"0 3 0 3 0 3\">\n"
         "<PointData Scalars=\"f\"><DataArray type=\"Float32\" Name=\"f\" format=\"ascii\">\n";
    for (int z = 0; z < 4; ++z)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) f << x + 2 * y + 3 * z << ' ';
    f << "\n</DataArray></PointData><CellData/></Piece></ImageData></VTKFile>\n";
  }
  const auto iso = scratch("ramp.png");
  const Run image = run_tool("render " + vti.string() + " --iso 6 --size 64x48 --json -o " + iso.string());
  INFO(image.output);
  REQUIRE(image.exit_code == 0);
  CHECK(nlohmann::json::parse(image.output)["volume"]["dims"] == nlohmann::json::array({4, 4, 4}));
  CHECK(covered_pixels(iso) > 200);

  // Legacy poly data: a quad, fan-triangulated, coloured by a point scalar.
  const auto legacy = scratch("quad.vtk");
  std::ofstream(legacy) << "# vtk DataFile Version 3.0\nquad\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n"
                           "0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 1 5\n4 0 1 2 3\nPOINT_DATA 4\n"
                           "SCALARS height float 1\nLOOKUP_TABLE default\n0 1 2 3\n";
  const Run quad = run_tool("render " + legacy.string() + " --color-by height --size 32x32 --json -o " +
                            scratch("quad.png").string());
  INFO(quad.output);
  REQUIRE(quad.exit_code == 0);
  CHECK(nlohmann::json::parse(quad.output)["triangles"] == 2);

  // Options that do not fit the file are named.
  const Run wrong = run_tool("render " + vti.string() + " --color-by f -o " + iso.string());
  CHECK(wrong.exit_code != 0);
  CHECK_THAT(wrong.output, Catch::Contains("--color-by: colours poly data"));
  const Run sized = run_tool("render " + vti.string() + " --radius 0.5 -o " + iso.string());
  CHECK(sized.exit_code != 0);
  CHECK_THAT(sized.output, Catch::Contains("--radius and --radius-by: size the spheres of point clouds"));
  const Run missing = run_tool("render " + legacy.string() + " --color-by pressure -o " + iso.string());
  CHECK(missing.exit_code != 0);
  CHECK_THAT(missing.output, Catch::Contains("height"));  // the arrays it has
}

TEST_CASE("sciray render: a progress line on a terminal only, and not with --quiet", "[tool][progress]") {
  // `script` (util-linux) runs the tool on a pseudo-terminal: stderr is a terminal there.
  const std::string render = std::string(SCIRAY_TOOL) +
                             " render builtin:cornell_box --renderer pathtracer --size 256x256 --frames 24 -o " +
                             scratch("progress.png").string();
  const auto on_terminal = [](const std::string& command) {
    const Run run = run_shell("script -qec '" + command + "' /dev/null 2>&1");
    CHECK(run.exit_code == 0);
    return run.output;
  };
  const std::string shown = on_terminal(render);
  INFO(shown);
  CHECK_THAT(shown, Catch::Contains("/24 ["));
  CHECK_THAT(shown, Catch::Contains(" left"));
  CHECK(on_terminal(render + " --quiet").find("/24 [") == std::string::npos);
  // Piped (not a terminal), as run_tool runs it: nothing.
  const Run piped = run_tool(render.substr(std::string(SCIRAY_TOOL).size() + 1));
  CHECK(piped.exit_code == 0);
  CHECK(piped.output.find("/24 [") == std::string::npos);
}

TEST_CASE("sciray render: particles from a PLY of vertices only and from .xyzr text, as spheres", "[tool][points]") {
  // 1,000 particles on a helix with a radius and a temperature each.
  const auto ply = scratch("particles.ply");
  {
    std::ofstream f(ply);
    f << "ply\nformat ascii 1.0\nelement vertex 1000\nproperty float x\nproperty float y\nproperty float z\n"
         "property float radius\nproperty float temperature\nend_header\n";
    for (int i = 0; i < 1000; ++i)
      f << std::cos(0.05 * i) << ' ' << std::sin(0.05 * i) << ' ' << 0.002 * i << ' ' << 0.02 << ' ' << i << '\n';
  }
  const auto png = scratch("particles.png");
  const Run run = run_tool("render " + ply.string() + " --color-by temperature --size 64x48 --json -o " + png.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto report = nlohmann::json::parse(run.output);
  CHECK(report["spheres"] == 1000);
  CHECK(report["triangles"] == 0);
  CHECK(covered_pixels(png) > 100);

  const auto xyzr = scratch("particles.xyzr");
  std::ofstream(xyzr) << "# x y z r\n0 0 0 0.5\n1 0 0 0.25\n";
  const Run text = run_tool("render " + xyzr.string() + " --size 32x32 --json -o " + png.string());
  INFO(text.output);
  REQUIRE(text.exit_code == 0);
  CHECK(nlohmann::json::parse(text.output)["spheres"] == 2);
  const Run missing = run_tool("render " + ply.string() + " --color-by pressure -o " + png.string());
  CHECK(missing.exit_code != 0);
  CHECK_THAT(missing.output, Catch::Contains("temperature"));  // the properties it has
}

TEST_CASE("sciray render: a Wavefront OBJ scene with its materials", "[tool][obj]") {
  // Two quads in two groups, each with a material of its own from the .mtl: red and blue.
  const auto dir = scratch("obj");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "two.mtl") << "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n";
  std::ofstream(dir / "two.obj") << "mtllib two.mtl\nv -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 1 -1 0\nv 1 1 0\n"
                                    "g left\nusemtl red\nf 1 2 3 4\ng right\nusemtl blue\nf 2 5 6 3\n";
  const auto png = scratch("two.png");
  const Run run = run_tool("render " + (dir / "two.obj").string() + " --size 64x32 --json -o " + png.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK(nlohmann::json::parse(run.output)["triangles"] == 4);
  // The camera frames the two quads in the middle third of the image: one side red, the
  // other blue.
  const sciray::io::Image image = sciray::io::read_image(png.string());
  const auto reddish = [&](int x) { return image.at(x, 16, 0) > 2.f * image.at(x, 16, 2); };
  const auto bluish = [&](int x) { return image.at(x, 16, 2) > 2.f * image.at(x, 16, 0); };
  CHECK((reddish(26) && bluish(38)) != (bluish(26) && reddish(38)));
  // A face that refers to a vertex the file lacks is named.
  std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 3\n";
  const Run bad = run_tool("render " + (dir / "bad.obj").string() + " -o " + png.string());
  CHECK(bad.exit_code != 0);
  CHECK_THAT(bad.output, Catch::Contains("bad.obj"));
}

TEST_CASE("sciray render: running out of memory is an error, not an abort", "[tool][limits]") {
#ifdef SCIRAY_SANITIZED
  WARN("not under a sanitizer, whose shadow memory needs more address space than the limit leaves");
#else
  // A million triangles under address-space limits that leave too little for the mesh or
  // its BVH (about 350 MB in all): each run ends with an error naming it, exit status 1.
  int out_of_memory = 0;
  for (const int kilobytes : {220'000, 260'000}) {
    const Run run = run_shell("ulimit -v " + std::to_string(kilobytes) + "; " + std::string(SCIRAY_TOOL) +
                              " render builtin:torus_1M --size 32x32 --quiet -o " + scratch("oom.png").string() + " 2>&1");
    INFO("limit " << kilobytes << " kB: " << run.output);
    CHECK(run.exit_code == 1);  // not -1: no signal, no abort
    CHECK(run.output.find("sciray: error: ") != std::string::npos);
    out_of_memory += run.output.find("out of memory") != std::string::npos;
  }
  CHECK(out_of_memory >= 1);
#endif
}
