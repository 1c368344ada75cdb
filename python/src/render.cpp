// Cameras, renderers (OSPRay's names and parameters) and sessions: a scene rendered into
// a frame buffer frame after frame with the GIL released, read back as numpy arrays.
#include <cmath>
#include <memory>
#include <mutex>
#include <set>

#include <pybind11/stl.h>
#include <stb/stb_image_write.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "arrays.hpp"
#include "scene.hpp"
#include "shading_json.hpp"

namespace sciray_python {

namespace {

struct Camera {
  std::string type = "perspective";
  sciray::Vec3f position, look_at, up{0.f, 1.f, 0.f};
  float fovy = 60.f, height = 1.f, aperture_radius = 0.f, focus_distance = 1.f;

  sciray::Camera engine(float aspect) const {
    sciray::CameraCommon common;
    common.position = position, common.direction = look_at - position, common.up = up;
    if (type == "orthographic") {
      sciray::OrthographicCamera c;
      static_cast<sciray::CameraCommon&>(c) = common;
      c.height = height, c.aspect = aspect;
      return c;
    }
    if (type == "panoramic") {
      sciray::PanoramicCamera c;
      static_cast<sciray::CameraCommon&>(c) = common;
      return c;
    }
    sciray::PerspectiveCamera c;
    static_cast<sciray::CameraCommon&>(c) = common;
    c.fovy = fovy, c.aspect = aspect, c.aperture_radius = aperture_radius, c.focus_distance = focus_distance;
    return c;
  }
};

Camera make_camera(py::object position, py::object look_at, py::object up, float fovy, const std::string& type,
                   float height, float aperture_radius, float focus_distance) {
  Camera c;
  if (type != "perspective" && type != "orthographic" && type != "panoramic")
    value_error("type", "expected perspective, orthographic or panoramic, got '" + type + "'");
  c.type = type;
  c.position = vec3_of(position, "position"), c.look_at = vec3_of(look_at, "look_at"), c.up = vec3_of(up, "up");
  if (length(c.look_at - c.position) == 0.f) value_error("look_at", "is the camera's position");
  if (length(cross(c.look_at - c.position, c.up)) == 0.f) value_error("up", "is parallel to the view direction");
  if (!(fovy > 0.f && fovy < 180.f)) value_error("fovy", "must be in (0, 180) degrees, got " + std::to_string(fovy));
  if (!(height > 0.f)) value_error("height", "must be positive");
  if (!(aperture_radius >= 0.f) || !(focus_distance > 0.f))
    value_error("aperture_radius", "must not be negative, and focus_distance must be positive");
  c.fovy = fovy, c.height = height, c.aperture_radius = aperture_radius, c.focus_distance = focus_distance;
  return c;
}

/// A renderer by OSPRay's name with its parameters; `close()` ends its use.
struct Renderer {
  std::string type;
  sciray::shim::RendererConfig config;
  sciray::FrameSettings settings;
  bool closed = false;
};

/// Reads keyword parameters by OSPRay's names, refusing unknown names and wrong types.
class Parameters {
public:
  Parameters(const py::kwargs& given, std::string what) : given_(given), what_(std::move(what)) {}

  template <class T>
  void read(const char* name, T& into) {
    used_.insert(name);
    if (!given_.contains(name)) return;
    const py::handle value = given_[name];
    const bool ok = std::is_same_v<T, bool> ? py::isinstance<py::bool_>(value)
                    : std::is_integral_v<T> ? py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value)
                                            : (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)) &&
                                                  !py::isinstance<py::bool_>(value);
    if (!ok)
      throw py::type_error(what_ + ": '" + name + "' must be " +
                           (std::is_same_v<T, bool> ? "a bool" : std::is_integral_v<T> ? "an int" : "a number") +
                           ", got " + py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>());
    into = value.cast<T>();
  }
  std::optional<py::handle> get(const char* name) {
    used_.insert(name);
    if (!given_.contains(name)) return std::nullopt;
    return given_[name];
  }
  void check_all_used() const {
    for (const auto& [key, value] : given_) {
      const auto name = py::str(key).cast<std::string>();
      if (!used_.count(name)) {
        std::string known;
        for (const auto& n : used_) known += (known.empty() ? "" : ", ") + n;
        throw py::type_error(what_ + ": unknown parameter '" + name + "' (known: " + known + ")");
      }
    }
  }

private:
  const py::kwargs& given_;
  std::string what_;
  std::set<std::string> used_;
};

std::shared_ptr<Renderer> make_renderer(const std::string& type, const py::kwargs& kwargs) {
  auto r = std::make_shared<Renderer>();
  r->type = type;
  Parameters p(kwargs, "Renderer('" + type + "')");
  const auto common = [&](auto params) {
    // sciray's tool's background: dark grey, opaque (OSPRay's is transparent black).
    params.background_color = {0.1f, 0.1f, 0.12f}, params.background_alpha = 1.f;
    if (auto bg = p.get("backgroundColor")) {
      const auto rows = float_rows(py::module_::import("numpy").attr("ravel")(*bg), {"backgroundColor", 1});
      if (rows.view.count != 3 && rows.view.count != 4) value_error("backgroundColor", "expected 3 or 4 numbers");
      const float* c = rows.view.data();
      params.background_color = {c[0], c[1], c[2]};
      params.background_alpha = rows.view.count == 4 ? *rows.view.element(3) : 1.f;
    }
    p.read("maxPathLength", params.max_path_length);
    p.read("minContribution", params.min_contribution);
    p.read("volumeSamplingRate", params.volume_sampling_rate);
    if (auto integration = p.get("volumeIntegration")) {
      const auto name = py::str(*integration).cast<std::string>();
      if (name != "sampled" && name != "preintegrated" && name != "exact")
        value_error("volumeIntegration", "expected sampled, preintegrated or exact, got '" + name + "'");
      params.volume_preintegration = name == "preintegrated", params.volume_exact = name == "exact";
    }
    return params;
  };
  if (type == "scivis") {
    auto params = common(sciray::SciVisParams{});
    p.read("shadows", params.shadows);
    p.read("visibleLights", params.visible_lights);
    p.read("aoSamples", params.ao_samples);
    p.read("aoDistance", params.ao_distance);
    r->config = params;
  } else if (type == "ao") {
    auto params = common(sciray::AOParams{});
    p.read("aoSamples", params.ao_samples);
    p.read("aoDistance", params.ao_distance);
    p.read("aoIntensity", params.ao_intensity);
    r->config = params;
  } else if (type == "pathtracer") {
    auto params = common(sciray::PathTracerParams{});
    p.read("roulettePathLength", params.roulette_path_length);
    p.read("maxContribution", params.max_contribution);
    p.read("geometryLights", params.geometry_lights);
    p.read("lightSamples", params.light_samples);
    p.read("backgroundRefraction", params.background_refraction);
    r->config = params;
  } else {
    value_error("type", "expected scivis, ao or pathtracer, got '" + type + "'");
  }
  p.read("pixelSamples", r->settings.pixel_samples);
  p.read("varianceThreshold", r->settings.variance_threshold);
  if (auto filter = p.get("pixelFilter"))
    r->settings.pixel_filter = sciray::pixel_filter_named(py::str(*filter).cast<std::string>(), "pixelFilter");
  p.check_all_used();
  naming_arguments("Renderer('" + type + "')", {}, [&] { sciray::validate(r->settings); });
  return r;
}

/// The channels a session can return beside colour, and their frame buffer flags.
const std::pair<const char*, unsigned> channel_flags[] = {
    {"depth", sciray::channel_depth},
    {"normal", sciray::channel_normal},
    {"albedo", sciray::channel_albedo},
    {"primitive_id", sciray::channel_id_primitive},
    {"geometry_id", sciray::channel_id_object},
    {"instance_id", sciray::channel_id_instance}};

/// Rows of the frame buffer (bottom-up) as an image array (top-down) of `channels` per pixel.
template <class T>
py::array image_of(const std::vector<T>& values, int width, int height, int channels) {
  std::vector<py::ssize_t> shape{height, width};
  if (channels > 1) shape.push_back(channels);
  py::array_t<T> out(shape);
  const std::size_t row = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
  for (int y = 0; y < height; ++y)
    std::copy_n(values.data() + static_cast<std::size_t>(height - 1 - y) * row, row,
                out.mutable_data() + static_cast<std::size_t>(y) * row);
  return out;
}

class Session {
public:
  Session(std::shared_ptr<Scene> scene, std::optional<Camera> camera, std::shared_ptr<Renderer> renderer,
          std::pair<int, int> size, const std::string& dtype, const std::vector<std::string>& channels, int threads)
      : scene_(std::move(scene)), camera_(std::move(camera)),
        renderer_(renderer ? std::move(renderer) : make_renderer("scivis", py::kwargs())),
        arena_(threads > 0 ? threads : tbb::info::default_concurrency()),
        fb_(checked_width(size), size.second, color_format(dtype), flags(channels)) {
    if (!scene_) type_error("scene", "expected a Scene, got None");
    if (threads < 0) value_error("threads", "must not be negative (0: all cores)");
  }

  /// Renders one more frame into the accumulation (a cancel() before it is forgotten).
  void render_frame() {
    control_.cancel = false;
    render_one();
  }

  /// Up to `frames` frames, or until the estimated error is `error_target`, `callback`
  /// returns False, or cancel() is called; returns the frames rendered.
  int render(int frames, const py::object& callback, float error_target) {
    if (frames < 1) value_error("frames", "must be at least 1");
    if (!(error_target >= 0.f)) value_error("error_target", "must not be negative");
    control_.cancel = false;
    int rendered = 0;
    for (; rendered < frames; ++rendered) {
      if (error_target > 0.f && fb_.variance() <= error_target) break;
      if (control_.cancel) break;  // cancelled between frames (during a callback)
      render_one();
      if (control_.cancel) break;
      if (!callback.is_none()) {
        const py::object go_on = callback(py::cast(this, py::return_value_policy::reference));
        if (!go_on.is_none() && !go_on.cast<bool>()) {
          ++rendered;
          break;
        }
      }
    }
    return rendered;
  }

  void cancel() { control_.cancel = true; }
  float progress() const { return control_.progress(); }
  int frames() const { return static_cast<int>(fb_.accumulated_frames()); }
  py::object error() const {
    const float e = fb_.variance();
    return std::isfinite(e) ? py::object(py::float_(e)) : py::none();
  }
  void reset() { fb_.reset_accumulation(); }

  py::array color() const {
    if (fb_.format() == sciray::ColorFormat::rgba32f) return image_of(fb_.color32f(), fb_.width(), fb_.height(), 4);
    return image_of(fb_.color8(), fb_.width(), fb_.height(), 4);
  }

  py::dict channels() const {
    py::dict out;
    out["color"] = color();
    const int w = fb_.width(), h = fb_.height();
    if (fb_.has(sciray::channel_depth)) out["depth"] = image_of(fb_.depth(), w, h, 1);
    if (fb_.has(sciray::channel_normal)) out["normal"] = image_of(fb_.normal(), w, h, 3);
    if (fb_.has(sciray::channel_albedo)) out["albedo"] = image_of(fb_.albedo(), w, h, 3);
    if (fb_.has(sciray::channel_id_primitive)) out["primitive_id"] = image_of(fb_.primitive_id(), w, h, 1);
    if (fb_.has(sciray::channel_id_object)) out["geometry_id"] = image_of(fb_.object_id(), w, h, 1);
    if (fb_.has(sciray::channel_id_instance)) out["instance_id"] = image_of(fb_.instance_id(), w, h, 1);
    return out;
  }

  /// What the pixel at column x, row y (from the top, as in the image arrays) shows.
  py::object pick(float x, float y) {
    if (!(x >= 0.f && x < static_cast<float>(fb_.width()) && y >= 0.f && y < static_cast<float>(fb_.height())))
      throw py::index_error("pick: (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                            std::to_string(fb_.width()) + "x" + std::to_string(fb_.height()) + " image");
    scene_->commit_if_changed();
    const float aspect = static_cast<float>(fb_.width()) / static_cast<float>(fb_.height());
    const float sx = (std::floor(x) + 0.5f) / static_cast<float>(fb_.width());
    const float sy = 1.f - (std::floor(y) + 0.5f) / static_cast<float>(fb_.height());
    // Through the lens centre, as ospPick.
    const sciray::Ray<float> ray =
        std::visit([&](const auto& c) { return sciray::prepare(c).generate(sx, sy, 0.5f, 0.5f); }, engine_camera(aspect));
    sciray::shim::TraceResult hit{};
    scene_->with_world([&](const EngineWorld& world, const auto&) {
      scene_->kernels().trace(world, std::span(&ray, 1), std::span(&hit, 1));
    });
    if (hit.geom_id < 0) return py::none();
    const sciray::Vec3f p = ray.org + ray.dir * hit.t;
    return py::dict(py::arg("position") = py::make_tuple(p.x, p.y, p.z), py::arg("geometry") = hit.geom_id,
                    py::arg("primitive") = hit.prim_id, py::arg("distance") = hit.t * length(ray.dir));
  }

private:
  void render_one() {
    if (renderer_->closed) throw py::value_error("renderer: Renderer('" + renderer_->type + "') is closed");
    scene_->commit_if_changed();
    const float aspect = static_cast<float>(fb_.width()) / static_cast<float>(fb_.height());
    const sciray::Camera camera = engine_camera(aspect);
    const sciray::CameraCommon& view = std::visit([](const auto& c) -> const sciray::CameraCommon& { return c; }, camera);
    // Lights change only with the GIL held (add_light), materials only under commit's lock.
    const std::vector<sciray::Light> lights =
        scene_->lights().empty() ? sciray_tool::desk_lamp_lights(view) : scene_->lights();
    scene_->with_world([&](const EngineWorld& world, const std::vector<sciray::Material>& materials) {
      sciray::shim::RendererConfig config = renderer_->config;
      std::visit([&](auto& params) { params.materials = materials, params.lights = lights; }, config);
      arena_.execute([&] { scene_->kernels().render(world, config, camera, fb_, &control_, renderer_->settings); });
    });
  }

  static int checked_width(std::pair<int, int> size) {
    if (size.first < 1 || size.second < 1)
      value_error("size", "expected (width, height) of at least 1 pixel, got (" + std::to_string(size.first) + ", " +
                              std::to_string(size.second) + ")");
    if (size.first > 32768 || size.second > 32768) value_error("size", "width and height are limited to 32768");
    return size.first;
  }
  static sciray::ColorFormat color_format(const std::string& dtype) {
    if (dtype == "uint8") return sciray::ColorFormat::srgba;
    if (dtype == "float32") return sciray::ColorFormat::rgba32f;
    value_error("dtype", "expected 'uint8' (sRGB) or 'float32' (linear), got '" + dtype + "'");
  }
  static unsigned flags(const std::vector<std::string>& channels) {
    unsigned f = sciray::channel_color | sciray::channel_accum | sciray::channel_variance;
    for (const std::string& name : channels) {
      bool known = name == "color";
      for (const auto& [n, flag] : channel_flags)
        if (name == n) f |= flag, known = true;
      if (!known)
        value_error("channels", "unknown channel '" + name +
                                    "' (color, depth, normal, albedo, primitive_id, geometry_id, instance_id)");
    }
    return f;
  }
  sciray::Camera engine_camera(float aspect) {
    if (camera_) return camera_->engine(aspect);
    return naming_arguments("camera", {}, [&] { return sciray::Camera(sciray::frame_bounds(scene_->bounds(), aspect)); });
  }

  std::shared_ptr<Scene> scene_;
  std::optional<Camera> camera_;
  std::shared_ptr<Renderer> renderer_;
  tbb::task_arena arena_;
  sciray::FrameBuffer fb_;
  sciray::FrameControl control_;
};

py::bytes encode_png(const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>& image) {
  if (image.ndim() != 3 || image.shape(2) < 1 || image.shape(2) > 4)
    value_error("image", "expected shape (height, width, channels) with 1 to 4 channels");
  std::string png;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  const int w = static_cast<int>(image.shape(1)), h = static_cast<int>(image.shape(0)), c = static_cast<int>(image.shape(2));
  if (!stbi_write_png_to_func(append, &png, w, h, c, image.data(), w * c)) throw py::value_error("image: PNG encoding failed");
  return py::bytes(png);
}

}  // namespace

void bind_render(py::module_& m) {
  py::class_<Camera>(m, "Camera", "A camera by OSPRay's types: perspective (fovy, aperture_radius, focus_distance), "
                                  "orthographic (height) or panoramic")
      .def(py::init(&make_camera), py::arg("position"), py::arg("look_at"), py::arg("up") = py::make_tuple(0, 1, 0),
           py::arg("fovy") = 60.f, py::arg("type") = "perspective", py::arg("height") = 1.f,
           py::arg("aperture_radius") = 0.f, py::arg("focus_distance") = 1.f)
      .def_readonly("type", &Camera::type)
      .def_property_readonly("position", [](const Camera& c) { return py::make_tuple(c.position.x, c.position.y, c.position.z); })
      .def_property_readonly("look_at", [](const Camera& c) { return py::make_tuple(c.look_at.x, c.look_at.y, c.look_at.z); })
      .def_property_readonly("up", [](const Camera& c) { return py::make_tuple(c.up.x, c.up.y, c.up.z); })
      .def_readonly("fovy", &Camera::fovy);

  py::class_<Renderer, std::shared_ptr<Renderer>>(m, "Renderer",
                                                  "Renderer('scivis' | 'ao' | 'pathtracer', **OSPRay parameters)")
      .def(py::init(&make_renderer), py::arg("type") = "scivis")
      .def_readonly("type", &Renderer::type)
      .def_readonly("closed", &Renderer::closed)
      .def("close", [](Renderer& r) { r.closed = true; })
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](Renderer& r, py::args) { r.closed = true; });

  py::class_<Session>(m, "Session", "Frames of a scene accumulated progressively in one frame buffer")
      .def(py::init<std::shared_ptr<Scene>, std::optional<Camera>, std::shared_ptr<Renderer>, std::pair<int, int>,
                    const std::string&, const std::vector<std::string>&, int>(),
           py::arg("scene"), py::arg("camera") = py::none(), py::arg("renderer") = py::none(),
           py::arg("size") = std::pair<int, int>{640, 480}, py::arg("dtype") = "uint8",
           py::arg("channels") = std::vector<std::string>{}, py::arg("threads") = 0)
      .def("render_frame", &Session::render_frame, "Renders and accumulates one frame (the GIL released)")
      .def("render", &Session::render, py::arg("frames") = 1, py::arg("callback") = py::none(),
           py::arg("error_target") = 0.f,
           "Renders up to `frames` frames; after each, callback(session) may return False to stop")
      .def("cancel", &Session::cancel, "Stops the frame in progress (from another thread); it is discarded")
      .def_property_readonly("progress", &Session::progress, "The fraction of the current frame's tiles done")
      .def_property_readonly("frames", &Session::frames, "Frames accumulated")
      .def_property_readonly("error", &Session::error, "The accumulation's estimated error (None before 2 frames)")
      .def("reset", &Session::reset, "Starts the accumulation again (after moving the camera or changing the scene)")
      .def("color", &Session::color, "The image: (height, width, 4), uint8 sRGB or float32 linear, top row first")
      .def("channels", &Session::channels, "Colour and every channel asked for, by name")
      .def("pick", &Session::pick, py::arg("x"), py::arg("y"),
           "What pixel (x, y) shows (column, row from the top): a dict of position, geometry, primitive and "
           "distance, or None");
  // PNG bytes for sciray.Image (Jupyter's _repr_png_, Image.save).
  m.def("_encode_png", &encode_png, py::arg("image"));
}

}  // namespace sciray_python
