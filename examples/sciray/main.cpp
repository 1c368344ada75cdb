// The `sciray` command-line tool: renders meshes, molecules (or a built-in scene) to
// images and reports what the work cost.
//   sciray info
//   sciray render [MESH.ply|SCENE.obj|POINTS.ply|.xyz|.xyzr|.f32xyzr|MOLECULE.pdb|VOLUME.raw|VOLUME.nrrd|
//                  VTK.vtu|.vti|.vtp|.vtk|builtin:NAME]
//                 [--field NAME] [--color-by NAME] [--radius R] [--radius-by NAME] [--radius-exponent E]
//                 [--camera cam.json] [--size WxH]
//                 [--isa auto|avx512|avx2|sse4.2|scalar] [--threads N] [--frames N]
//                 [-o out.png|out.pfm] [--depth depth.pfm] [--json] [--quiet]
//                 [--style ball-and-stick|space-filling] [--sphere-intersector sciray|embree]
//                 [--clip-plane a,b,c,d]... [--clip-sphere x,y,z,r]...
//                 [--tf tf.json] [--layout linear|bricked] [--density D] [--anisotropy G] [--sampling-rate R] [--gradient-shading S]
//                 [--iso V]... [--slice a,b,c,d]... [--preintegration] [--adaptive-sampling] [--exact]
//                 [--no-empty-space-skipping]
//                 [--renderer scivis|ao|pathtracer] [--spp N] [--shadows] [--ao-samples N] [--ao-distance D]
//                 [--max-path-length N] [--material JSON]... [--texcoord-from PROPERTY] [--light JSON]...
//                 [--background r,g,b,a]
//                 [--pixel-filter point|box|gauss|mitchell|blackman_harris] [--error-target E] [--tonemap]
//                 [--aperture R] [--focus D] [--panoramic]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "sciray/geometry/molecule.hpp"
#include "sciray/io/frame_io.hpp"
#include "sciray/io/obj.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/io/points.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "json_float.hpp"
#include "progress.hpp"
#include "shading_json.hpp"
#include "volume_scene.hpp"
#include "vtk_scene.hpp"
#ifdef SCIRAY_TOOL_MPI
#include "mpi_frames.hpp"
#endif

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

sciray::Vec3f vec3_field(const nlohmann::json& j, const char* key, const std::string& file) {
  if (!j.contains(key)) throw sciray::Error(file + ": missing \"" + key + "\"");
  const auto& v = j[key];
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw sciray::Error(file + ": \"" + key + "\" must be an array of 3 numbers");
  const auto coordinate = [&](int k) { return sciray_tool::json_float(v[k], file + ": \"" + key + "\""); };
  return {coordinate(0), coordinate(1), coordinate(2)};
}

/// {"position":[x,y,z], "look_at":[x,y,z], "up":[x,y,z], "fovy":deg}
sciray::PerspectiveCamera read_camera(const std::string& file, float aspect) {
  std::ifstream in(file);
  if (!in) throw sciray::Error(file + ": cannot open camera file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for a number beyond double
    throw sciray::Error(file + ": invalid JSON: " + e.what());
  }
  if (!j.is_object()) throw sciray::Error(file + ": expected a JSON object");
  sciray::PerspectiveCamera camera;
  camera.position = vec3_field(j, "position", file);
  camera.direction = vec3_field(j, "look_at", file) - camera.position;
  camera.up = j.contains("up") ? vec3_field(j, "up", file) : sciray::Vec3f{0.f, 1.f, 0.f};
  if (j.contains("fovy")) {
    camera.fovy = sciray_tool::json_float(j["fovy"], file + ": \"fovy\"");
  }
  camera.aspect = aspect;
  return camera;
}

std::pair<int, int> parse_size(const std::string& size) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(size.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w <= 0 || h <= 0)
    throw sciray::Error("--size: expected WIDTHxHEIGHT (e.g. 1024x768), got '" + size + "'");
  return {w, h};
}

std::vector<float> parse_floats(const std::string& text, std::size_t count, const char* option);

struct RenderOptions {
  std::string mesh;
  std::string camera;
  std::string size = "1024x1024";
  std::string isa = "auto";
  int threads = 0;
  int frames = 1;
  bool mpi = false;
  std::string output = "sciray.png";
  std::string depth;
  bool json = false;
  std::string style = "ball-and-stick";
  std::vector<std::string> clip_planes;   ///< "a,b,c,d" each
  std::vector<std::string> clip_spheres;  ///< "x,y,z,r" each
  std::vector<std::string> slices;        ///< "a,b,c,d" each
  std::string sphere_intersector = "sciray";
  std::string bvh = "fast";
  sciray_tool::VolumeOptions volume;
  float sampling_rate = 1.f;
  bool no_empty_space_skipping = false;
  bool preintegration = false;
  std::string color_by;  // VTK poly data: the array that colours it
  float radius = 0.f;    // point clouds: the spheres' radius (0: from their spacing)
  std::string radius_by;  // point clouds: scale each radius by this property
  float radius_exponent = 1.f;
  bool quiet = false;  // no progress line
  bool adaptive_sampling = false;
  std::string renderer = "scivis";
  int pixel_samples = 1;
  bool shadows = false;
  int ao_samples = -1;  ///< -1: the renderer's default
  float ao_distance = 1e20f;
  int max_path_length = 20;
  std::vector<std::string> materials;  ///< JSON (or files), geometry k gets material k (the last one the rest)
  std::string texcoord_from;           ///< PLY vertex scalar to make texture coordinates from
  std::vector<std::string> lights;     ///< JSON (or files); replace the default lights
  std::string background;              ///< "r,g,b,a"
  std::string pixel_filter = "gauss";
  float error_target = 0.f;  ///< > 0: render up to --frames frames until the estimated error is this
  bool tonemap = false;
  float aperture = 0.f;
  float focus = 1.f;
  bool panoramic = false;
};

/// The renderer and its parameters from the options (lights: the scene's or default).
sciray::shim::RendererConfig renderer_config(const RenderOptions& opt, std::vector<sciray::Light> scene_lights,
                                             std::vector<sciray::Material> materials) {
  std::vector<sciray::Light> lights;
  for (std::size_t i = 0; i < opt.lights.size(); ++i)
    lights.push_back(sciray_tool::light_from_json(sciray_tool::parse_json_argument(opt.lights[i], "--light"),
                                                  "--light " + std::to_string(i + 1)));
  const auto common = [&](auto params) {
    if (!lights.empty()) params.lights = lights;
    else if (!scene_lights.empty()) params.lights = scene_lights;
    params.materials = materials;
    params.background_color = {0.1f, 0.1f, 0.12f};
    params.background_alpha = 1.f;
    if (!opt.background.empty()) {
      const auto c = parse_floats(opt.background, 4, "--background");
      params.background_color = {c[0], c[1], c[2]};
      params.background_alpha = c[3];
    }
    params.max_path_length = opt.max_path_length;
    params.volume_sampling_rate = opt.sampling_rate;
    params.empty_space_skipping = !opt.no_empty_space_skipping;
    params.volume_preintegration = opt.preintegration;
    params.volume_adaptive_sampling = opt.adaptive_sampling;
    params.volume_exact = opt.volume.exact;
    return params;
  };
  if (opt.renderer == "scivis") {
    auto p = common(sciray::SciVisParams{});
    p.shadows = opt.shadows;
    if (opt.ao_samples >= 0) p.ao_samples = opt.ao_samples;
    p.ao_distance = opt.ao_distance;
    return p;
  }
  if (opt.renderer == "ao") {
    auto p = common(sciray::AOParams{});
    if (opt.ao_samples >= 0) p.ao_samples = opt.ao_samples;
    p.ao_distance = opt.ao_distance;
    return p;
  }
  if (opt.renderer == "pathtracer") return common(sciray::PathTracerParams{});
  throw sciray::Error("--renderer: expected scivis, ao or pathtracer, got '" + opt.renderer + "'");
}

/// `count` comma-separated numbers, as "--clip-plane 0,0,1,-0.5" gives them.
std::vector<float> parse_floats(const std::string& text, std::size_t count, const char* option) {
  std::vector<float> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    float v = 0.f;
    try {
      v = std::stof(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw sciray::Error(std::string(option) + ": '" + item + "' is not a finite number");
    values.push_back(v);
  }
  if (values.size() != count)
    throw sciray::Error(std::string(option) + ": expected " + std::to_string(count) + " comma-separated numbers, got '" +
                        text + "'");
  return values;
}

sciray::BvhSettings parse_bvh(const std::string& name) {
  if (name == "fast") return {};
  if (name == "compact") return {.compact = true};
  if (name == "dynamic") return {.dynamic = true};
  if (name == "compact,dynamic") return {.compact = true, .dynamic = true};
  throw sciray::Error("--bvh: expected fast, compact, dynamic or compact,dynamic, got '" + name + "'");
}

sciray::SphereIntersector parse_intersector(const std::string& name) {
  if (name == "sciray") return sciray::SphereIntersector::sciray;
  if (name == "embree") return sciray::SphereIntersector::embree;
  throw sciray::Error("--sphere-intersector: expected sciray or embree, got '" + name + "'");
}

bool is_volume_file(const std::string& path) {
  const auto ext = std::filesystem::path(path).extension();
  return ext == ".raw" || ext == ".nrrd" || ext == ".nhdr" || ext == ".vtu" || ext == ".vti";
}

int render(const RenderOptions& opt) {
  const auto [width, height] = parse_size(opt.size);
  if (opt.frames < 1) throw sciray::Error("--frames must be at least 1");
  if (opt.threads < 0) throw sciray::Error("--threads must be positive (0 = all cores)");
  const sciray::simd::Isa isa = sciray::shim::select_isa(opt.isa);
  const auto& kernels = sciray::shim::kernels(isa);
  const int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  const bool float_output = std::filesystem::path(opt.output).extension() == ".pfm";
#ifdef SCIRAY_TOOL_MPI
  std::optional<sciray_tool::MpiFrames> mpi;
  if (opt.mpi) mpi.emplace();
#else
  if (opt.mpi) throw sciray::Error("--mpi: this sciray was built without MPI (OpenMPI at configure time: SCIRAY_MPI)");
#endif

  nlohmann::json report;
  tbb::task_arena arena(threads);
  arena.execute([&] {
    sciray::accel::Device device;  // before the progress line, which reads its build progress
    std::optional<sciray_tool::ProgressLine> progress(std::in_place, !opt.quiet);
    if (!opt.mesh.empty() && std::filesystem::is_regular_file(opt.mesh)) {
      char size[32];
      std::snprintf(size, sizeof size, " (%.1f MB)", static_cast<double>(std::filesystem::file_size(opt.mesh)) / 1e6);
      progress->stage("loading " + std::filesystem::path(opt.mesh).filename().string() + size);
    }
    auto start = Clock::now();
    // "builtin:NAME" is a standard scene (testing/scenes.hpp), .pdb a molecule, .obj a
    // scene of meshes, a PLY of vertices only (or .xyz...) particles, volumes and VTK files
    // below, otherwise a PLY mesh; nothing, the default scene.
    sciray::testing::StandardScene scene;
    std::optional<sciray::io::ObjScene> obj;
    const bool builtin = opt.mesh.rfind("builtin:", 0) == 0;
    const bool point_cloud = !opt.mesh.empty() && !builtin && sciray::io::is_point_cloud_file(opt.mesh);
    if (opt.mesh.empty()) {
      scene.mesh = sciray::testing::wavy_torus(400'000);
    } else if (builtin) {
      scene = sciray::testing::standard_scene(opt.mesh.substr(8), SCIRAY_DATA_DIR);
    } else if (std::filesystem::path(opt.mesh).extension() == ".pdb") {
      auto molecule = sciray::molecule_geometry(sciray::io::read_pdb(opt.mesh), sciray::parse_molecule_style(opt.style));
      scene.spheres = std::move(molecule.atoms);
      scene.curves = std::move(molecule.bonds);
    } else if (std::filesystem::path(opt.mesh).extension() == ".obj") {
      obj = sciray::io::read_obj(opt.mesh);
      for (const auto& warning : obj->warnings) std::cerr << "sciray: warning: " << warning << '\n';
    } else if (point_cloud) {
      // Particles (a PLY of vertices only, .xyz, .xyzr, .f32xyzr): spheres, coloured by a
      // property, or by the file's own colours where it has them and none is asked for.
      sciray::io::PointOptions points;
      points.radius = opt.radius;
      points.radius_by = opt.radius_by, points.radius_exponent = opt.radius_exponent;
      points.color_by = opt.color_by;
      sciray::io::PointCloud cloud = sciray::io::read_points(opt.mesh, points);
      points.file_colors = opt.color_by.empty() && cloud.find("red") != nullptr;
      scene.spheres = sciray::io::to_spheres(std::move(cloud), points, sciray::testing::colormap);
    } else if (!is_volume_file(opt.mesh) && !sciray_tool::is_vtk_file(opt.mesh)) {
      scene.mesh = sciray::io::read_ply(opt.mesh, {opt.texcoord_from});
    }
    if (!opt.texcoord_from.empty() &&
        (opt.mesh.empty() || builtin || std::filesystem::path(opt.mesh).extension() == ".pdb" ||
         is_volume_file(opt.mesh) || sciray_tool::is_vtk_file(opt.mesh) || obj || point_cloud))
      throw sciray::Error("--texcoord-from: needs a PLY mesh, whose vertex property it reads");

    sciray::shim::EngineWorld world(device);
    std::optional<sciray_tool::VolumeInfo> volume;
    const bool vtk = sciray_tool::is_vtk_file(opt.mesh);
    if (!opt.volume.field.empty() && !vtk)
      throw sciray::Error("--field: needs a VTK file (.vtu, .vti, .vtk), whose array it picks");
    if (!vtk && !point_cloud && (!opt.color_by.empty() || opt.radius != 0.f || !opt.radius_by.empty()))
      throw sciray::Error("--color-by, --radius and --radius-by: apply to point clouds (PLY without faces, .xyz, .xyzr, .f32xyzr) "
                          "and VTK poly data (.vtp, .vtk)");
    if (vtk) {
      if (auto grid = sciray_tool::load_vtk(
            opt.mesh, {opt.volume.field, opt.color_by, opt.radius, opt.radius_by, opt.radius_exponent}, scene))
        volume = sciray_tool::add_unstructured(world, *grid, opt.mesh, opt.volume);
    } else if (is_volume_file(opt.mesh)) {
      scene.volume = sciray::io::read_volume(opt.mesh);
    }
    if (scene.volume) {
      sciray_tool::VolumeOptions volume_options = opt.volume;
      for (const auto& slice : opt.slices) {
        const auto c = parse_floats(slice, 4, "--slice");
        volume_options.slices.push_back({c[0], c[1], c[2], c[3]});
      }
      volume = sciray_tool::add_volume(world, *scene.volume, volume_options);
    }
    const double load_ms = ms_since(start);
    // The scene's geometry goes into the world, or into one group the world instances.
    auto group = std::make_shared<sciray::shim::EngineWorld::GroupType>(device);
    sciray::shim::EngineWorld::GroupType& target = scene.instances.empty() ? world : *group;
    const sciray::BvhSettings bvh = parse_bvh(opt.bvh);
    world.set_bvh(bvh);
    group->set_bvh(bvh);
    // --material k shades the k-th geometry added; the last one shades the rest.
    std::vector<sciray::Material> materials;
    if (scene.material && opt.materials.empty()) materials.push_back(*scene.material);
    for (std::size_t i = 0; i < opt.materials.size(); ++i)
      materials.push_back(sciray_tool::material_from_json(
          sciray_tool::parse_json_argument(opt.materials[i], "--material"), "--material " + std::to_string(i + 1)));
    std::uint32_t geometries = 0;
    const auto next_material = [&] {
      const std::uint32_t k = geometries++;
      return materials.empty() ? sciray::no_material : std::min<std::uint32_t>(k, materials.size() - 1);
    };
    std::size_t triangles = 0, vertices = 0, spheres = 0, curve_segments = 0;
    if (scene.mesh) {
      sciray::TriangleMesh mesh(std::move(*scene.mesh));
      triangles = mesh.triangle_count(), vertices = mesh.vertex_count();
      target.add(std::move(mesh), next_material());
    }
    if (obj) {
      // A mesh per group and material, shaded by the .mtl's materials, unless --material
      // overrides them (then the k-th mesh takes the k-th, as for any geometry).
      const bool own = opt.materials.empty();
      const auto offset = static_cast<std::uint32_t>(materials.size());
      if (own) materials.insert(materials.end(), obj->materials.begin(), obj->materials.end());
      for (auto& part : obj->meshes) {
        sciray::TriangleMesh mesh(std::move(part.mesh));
        triangles += mesh.triangle_count(), vertices += mesh.vertex_count();
        target.add(std::move(mesh), !own                                  ? next_material()
                                    : part.material == sciray::no_material ? sciray::no_material
                                                                           : offset + part.material);
      }
    }
    if (scene.spheres) {
      spheres = scene.spheres->count();
      target.add(sciray::Spheres(std::move(*scene.spheres)).set_intersector(parse_intersector(opt.sphere_intersector)),
                 next_material());
    }
    if (scene.curves) {
      curve_segments = scene.curves->indices.size();
      target.add(sciray::Curves(std::move(*scene.curves)), next_material());
    }
    const std::size_t boxes = scene.boxes.size();
    if (boxes) target.add(sciray::Boxes(std::move(scene.boxes), std::move(scene.box_colors)), next_material());
    for (const auto& transform : scene.instances) world.add_instance(group, transform);
    if (!opt.clip_planes.empty() || !opt.clip_spheres.empty()) {
      auto clipping = std::make_shared<sciray::Clipping>();
      for (const auto& plane : opt.clip_planes) {
        const auto c = parse_floats(plane, 4, "--clip-plane");
        clipping->add_plane({c[0], c[1], c[2]}, c[3]);
      }
      for (const auto& sphere : opt.clip_spheres) {
        const auto c = parse_floats(sphere, 4, "--clip-sphere");
        clipping->add_sphere({c[0], c[1], c[2]}, c[3]);
      }
      world.set_clipping(clipping);
    }
    progress->stage("building the BVH", [&device] { return device.build_progress(); });
    start = Clock::now();
    kernels.commit(world);
    const double build_ms = ms_since(start);

    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    if (scene.camera) scene.camera->aspect = aspect;
    sciray::PerspectiveCamera view = !opt.camera.empty() ? read_camera(opt.camera, aspect)
                                     : scene.camera      ? *scene.camera
                                                         : sciray::frame_bounds(world.bounds(), aspect);
    view.aperture_radius = opt.aperture;
    view.focus_distance = opt.focus;
    sciray::Camera camera = view;
    if (opt.panoramic) {
      sciray::PanoramicCamera panoramic;
      static_cast<sciray::CameraCommon&>(panoramic) = view;  // the same placement
      camera = panoramic;
    }
    if (scene.lights.empty()) scene.lights = sciray_tool::desk_lamp_lights(view);
    const sciray::shim::RendererConfig config = renderer_config(opt, scene.lights, materials);
    sciray::FrameSettings settings;
    settings.pixel_samples = opt.pixel_samples;
    settings.pixel_filter = sciray::pixel_filter_named(opt.pixel_filter, "--pixel-filter");
    sciray::validate(settings);
    if (opt.error_target < 0.f || !std::isfinite(opt.error_target))
      throw sciray::Error("--error-target must be a positive number");

    sciray::FrameBuffer fb(width, height, float_output ? sciray::ColorFormat::rgba32f : sciray::ColorFormat::srgba,
                           sciray::channel_color | sciray::channel_depth | sciray::channel_accum |
                               sciray::channel_variance);
    if (opt.tonemap) fb.set_image_operations({sciray::Tonemapper()});
    std::vector<double> frame_ms;
    progress->start_frames(opt.frames, opt.error_target);
    // With an error target, frames stop once the frame buffer's estimate meets it.
    for (int f = 0;; ++f) {
      bool another = f < opt.frames && !(opt.error_target > 0.f && fb.variance() <= opt.error_target);
#ifdef SCIRAY_TOOL_MPI
      if (mpi) another = mpi->another_frame(another);  // rank 0's estimate decides
#endif
      if (!another) break;
      start = Clock::now();
#ifdef SCIRAY_TOOL_MPI
      if (mpi)
        mpi->render(kernels, world, config, camera, fb, settings);
      else
#endif
        kernels.render(world, config, camera, fb, progress->control(), settings);
      frame_ms.push_back(ms_since(start));
      progress->frame_done(fb.variance());
    }
    progress.reset();  // the line is cleared before anything else is written
#ifdef SCIRAY_TOOL_MPI
    if (mpi && !mpi->writes_outputs()) return;
#endif
    sciray::io::write_color(fb, opt.output);
    if (!opt.depth.empty()) sciray::io::write_depth(fb, opt.depth);

    const std::size_t total_bytes = world.memory_bytes();
    const std::size_t bvh_bytes = static_cast<std::size_t>(std::max<std::int64_t>(0, device.bytes_in_use()));
    const auto primitives = static_cast<double>(triangles + spheres + curve_segments + boxes);
    report = {{"file", opt.mesh.empty() ? "builtin:wavy_torus" : opt.mesh},
              {"output", opt.output},
              {"isa", std::string(sciray::simd::isa_name(isa))},
              {"simd_width", sciray::simd::isa_width(isa)},
              {"threads", threads},
#ifdef SCIRAY_TOOL_MPI
              {"ranks", mpi ? mpi->ranks() : 1},
#endif
              {"width", width},
              {"height", height},
              {"triangles", triangles},
              {"vertices", vertices},
              {"spheres", spheres},
              {"curve_segments", curve_segments},
              {"boxes", boxes},
              {"instances", world.instance_count()},
              {"renderer", opt.renderer},
              {"frames", fb.accumulated_frames()},
              {"estimated_error", std::isfinite(fb.variance()) ? nlohmann::json(fb.variance()) : nlohmann::json()},
              {"pixel_samples", opt.pixel_samples},
              {"volumes", world.volume_count()},
              {"sphere_intersector", opt.sphere_intersector},
              {"bvh", opt.bvh},
              {"load_ms", load_ms},
              {"bvh_build_ms", build_ms},
              {"frame_ms", frame_ms},
              {"memory_bytes", {{"geometry", total_bytes - bvh_bytes}, {"bvh", bvh_bytes}, {"total", total_bytes}}},
              {"volume", volume ? nlohmann::json{{"dims", volume->dims}, {"type", volume->type}} : nlohmann::json()},
              {"bytes_per_primitive", primitives ? nlohmann::json(static_cast<double>(total_bytes) / primitives)
                                                 : nlohmann::json()}};
  });
  if (report.is_null()) return 0;  // a rank of an MPI job that only rendered tiles
  if (opt.json) {
    std::cout << report.dump() << "\n";
  } else {
    double mean = 0;
    for (double ms : report["frame_ms"]) mean += ms;
    mean /= static_cast<double>(report["frame_ms"].size());
    std::cout << "rendered " << report["triangles"] << " triangles, " << report["spheres"] << " spheres and "
              << report["curve_segments"] << " curve segments at " << width << "x" << height << " with "
              << report["isa"].get<std::string>() << " on " << threads << " threads: " << mean
              << " ms/frame -> " << opt.output << "\n";
  }
  return 0;
}

int info(const std::string& isa_request) {
  std::cout << "supported ISAs:";
  for (auto isa : sciray::simd::all_isas)
    if (sciray::simd::cpu_supports(isa)) std::cout << " " << sciray::simd::isa_name(isa);
  const auto chosen = sciray::shim::select_isa(isa_request);
  std::cout << "\nchosen: " << sciray::simd::isa_name(chosen) << " (" << sciray::simd::isa_width(chosen)
            << " lanes)\nthreads: " << tbb::info::default_concurrency() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sciray: ray tracing for scientific visualization"};
  app.require_subcommand(1);

  std::string info_isa = "auto";
  auto* info_cmd = app.add_subcommand("info", "Print the ISAs this CPU supports and the one sciray picks");
  info_cmd->add_option("--isa", info_isa, "ISA to pick (also SCIRAY_ISA)");

  RenderOptions opt;
  auto* render_cmd = app.add_subcommand("render", "Render a mesh (or the built-in scene) to an image");
  render_cmd->add_option("mesh", opt.mesh,
                         "PLY mesh, Wavefront OBJ scene (.obj with its .mtl), point cloud (PLY without faces, .xyz, .xyzr, .f32xyzr), PDB molecule, raw/NRRD volume, VTK file (.vtu unstructured grid, .vti image, .vtp poly data, legacy .vtk), or builtin:NAME (torus_1M, cornell_box, spheres_1M, streamlines, bunny, "
                         "...); "
                         "without it, the default scene");
  render_cmd->add_option("--camera", opt.camera, "camera JSON {position, look_at, up, fovy}");
  render_cmd->add_option("--size", opt.size, "image size WIDTHxHEIGHT");
  render_cmd->add_option("--isa", opt.isa, "auto|avx512|avx2|sse4.2|scalar (also SCIRAY_ISA)");
  render_cmd->add_option("--threads", opt.threads, "threads (0 = all cores)");
  render_cmd->add_option("--frames", opt.frames, "frames to render and accumulate");
  render_cmd->add_option("-o,--output", opt.output, "output image (.png, or .pfm for float colour)");
  render_cmd->add_option("--depth", opt.depth, "also write Euclidean depth to this .pfm");
  render_cmd->add_flag("--json", opt.json, "print timings and sizes as one JSON object");
  render_cmd->add_flag("--quiet", opt.quiet,
                       "no progress line (shown on stderr while loading, building and rendering, on a terminal only)");
  render_cmd->add_flag("--mpi", opt.mpi,
                       "image-parallel over the ranks of an MPI job (mpirun -n 3 sciray render ... --mpi): rank 0 "
                       "writes the outputs, the others render tiles");
  render_cmd->add_option("--style", opt.style, "molecules: ball-and-stick or space-filling");
  render_cmd->add_option("--tf", opt.volume.tf, "volumes: transfer function JSON {colors, opacities, range}");
  render_cmd->add_option("--color-by", opt.color_by,
                         "point clouds and VTK poly data: colour by this property or array through the colour map");
  render_cmd->add_option("--radius", opt.radius,
                         "point clouds: the spheres' radius where the file gives none (default: a fifth of their "
                         "mean spacing)");
  render_cmd->add_option("--radius-by", opt.radius_by,
                         "point clouds: scale each sphere's radius by this property: radius x (value / median "
                         "value)^E (stars by luminosity: --radius-by lum --radius-exponent 0.25)");
  render_cmd->add_option("--radius-exponent", opt.radius_exponent, "point clouds: the exponent E of --radius-by");
  render_cmd->add_option("--field", opt.volume.field,
                         ".vtu, .vti, legacy .vtk volumes: the point or cell array to render (vectors by magnitude; default: its Scalars array)");
  render_cmd->add_option("--layout", opt.volume.layout, "volumes: linear (in place) or bricked");
  render_cmd->add_option("--density", opt.volume.density, "volumes: densityScale (default: from the size)");
  render_cmd->add_option("--anisotropy", opt.volume.anisotropy,
                         "volumes, pathtracer: Henyey-Greenstein g of the scattering, in [-1, 1]");
  render_cmd->add_option("--sampling-rate", opt.sampling_rate, "volumes: samples per cell");
  render_cmd->add_option("--iso", opt.volume.isovalues, "volumes: render the isosurface of this value (repeatable)");
  render_cmd->add_option("--slice", opt.slices, "volumes: a,b,c,d: the plane a*x+b*y+c*z+d=0 coloured by the volume "
                                                "through the transfer function (repeatable)");
  render_cmd->add_option("--gradient-shading", opt.volume.gradient_shading_scale,
                         "volumes, scivis: how much each sample is lit with the gradient as its normal, in [0, 1] "
                         "(OSPRay's gradientShadingScale; 1: fully)");
  render_cmd->add_flag("--preintegration", opt.preintegration,
                       "volumes: integrate the transfer function over each step (accurate at coarse steps)");
  render_cmd->add_flag("--adaptive-sampling", opt.adaptive_sampling,
                       "volumes: step lengths from the local density (finer in dense matter)");
  render_cmd->add_flag("--exact", opt.volume.exact,
                       "volumes: integrate meshes of tetrahedra (.vtu) exactly, cell by cell, instead of sampling");
  render_cmd->add_flag("--no-empty-space-skipping", opt.no_empty_space_skipping,
                       "volumes: take every sample (for measuring what skipping saves)");
  render_cmd->add_option("--clip-plane", opt.clip_planes, "a,b,c,d: clip where a*x+b*y+c*z+d < 0 (repeatable)");
  render_cmd->add_option("--clip-sphere", opt.clip_spheres, "x,y,z,r: clip inside the sphere (repeatable)");
  render_cmd->add_option("--renderer", opt.renderer, "scivis, ao or pathtracer");
  render_cmd->add_option("--spp", opt.pixel_samples, "samples per pixel per frame (pixelSamples)");
  render_cmd->add_flag("--shadows", opt.shadows, "scivis: cast shadows");
  render_cmd->add_option("--ao-samples", opt.ao_samples, "scivis, ao: ambient occlusion rays per sample (aoSamples)");
  render_cmd->add_option("--ao-distance", opt.ao_distance, "scivis, ao: how far occluders count (aoDistance)");
  render_cmd->add_option("--max-path-length", opt.max_path_length, "surfaces a path passes or bounces (maxPathLength)");
  render_cmd->add_option("--material", opt.materials,
                         "material JSON (or a file) with OSPRay's names, e.g. '{\"type\":\"principled\",\"roughness\":0.2}'; "
                         "the k-th shades the k-th geometry, the last the rest (repeatable); maps are image files, "
                         "e.g. '{\"type\":\"obj\",\"map_kd\":\"colormap.png\"}'");
  render_cmd->add_option("--texcoord-from", opt.texcoord_from,
                         "PLY meshes: make texture coordinates from this per-vertex scalar property (u over its range, "
                         "v = 0.5), to colour the mesh by it through a colour-map image as map_kd");
  render_cmd->add_option("--light", opt.lights,
                         "light JSON (or a file) with OSPRay's names, e.g. '{\"type\":\"sphere\",\"position\":[0,2,0]}'; "
                         "replaces the default lights (repeatable)");
  render_cmd->add_option("--background", opt.background, "r,g,b,a background colour");
  render_cmd->add_option("--pixel-filter", opt.pixel_filter, "point, box, gauss (default), mitchell or blackman_harris");
  render_cmd->add_option("--error-target", opt.error_target,
                         "render up to --frames frames, stopping once the estimated error (mean absolute "
                         "luminance difference) is at most this; the report gives frames and the estimate");
  render_cmd->add_flag("--tonemap", opt.tonemap, "apply OSPRay's filmic tonemapper to the output");
  render_cmd->add_option("--aperture", opt.aperture, "perspective: lens radius for depth of field (apertureRadius)");
  render_cmd->add_option("--focus", opt.focus, "perspective: distance in focus (focusDistance)");
  render_cmd->add_flag("--panoramic", opt.panoramic, "a 360x180 degree panoramic camera at the view's position");
  render_cmd->add_option("--sphere-intersector", opt.sphere_intersector,
                         "sciray (own packet intersector) or embree (Embree's point geometry)");
  render_cmd->add_option("--bvh", opt.bvh,
                         "fast (default), compact (less memory, quicker build, slower frames), dynamic (for scenes "
                         "rebuilt every frame) or compact,dynamic: the BVH's layout and build, as OSPRay's "
                         "compactMode and dynamicScene");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*info_cmd) return info(info_isa);
    return render(opt);
  } catch (const std::bad_alloc&) {
    std::cerr << "sciray: error: out of memory (the scene, its BVH or the image does not fit in the memory this "
                 "process may use)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "sciray: error: " << e.what() << "\n";
    return 1;
  }
}
