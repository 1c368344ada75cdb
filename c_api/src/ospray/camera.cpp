// OSPRay's cameras: perspective, orthographic, panoramic.
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

namespace sciray::ospray {

void CameraObject::on_commit() {
  const Vec3f position = get_vec3f("position", {0.f, 0.f, 0.f});
  const Vec3f direction = get_vec3f("direction", {0.f, 0.f, 1.f});
  const Vec3f up = get_vec3f("up", {0.f, 1.f, 0.f});
  const auto stereo = [&] { return stereo_mode_from_int(subtype(), get_int("stereoMode", OSP_STEREO_NONE)); };
  Camera camera;
  if (subtype() == "perspective") {
    PerspectiveCamera c;
    c.position = position, c.direction = direction, c.up = up;
    c.fovy = get_float("fovy", c.fovy);
    c.aspect = get_float("aspect", c.aspect);
    c.aperture_radius = get_float("apertureRadius", c.aperture_radius);
    c.focus_distance = get_float("focusDistance", c.focus_distance);
    c.stereo_mode = stereo();
    c.interpupillary_distance = get_float("interpupillaryDistance", c.interpupillary_distance);
    camera = c;
  } else if (subtype() == "orthographic") {
    OrthographicCamera c;
    c.position = position, c.direction = direction, c.up = up;
    c.height = get_float("height", c.height);
    c.aspect = get_float("aspect", c.aspect);
    camera = c;
  } else {
    PanoramicCamera c;
    c.position = position, c.direction = direction, c.up = up;
    c.stereo_mode = stereo();
    c.interpupillary_distance = get_float("interpupillaryDistance", c.interpupillary_distance);
    camera = c;
  }
  std::visit([](const auto& c) { prepare(c); }, camera);  // validates, naming the bad parameter
  camera_ = camera;
}

}  // namespace sciray::ospray
