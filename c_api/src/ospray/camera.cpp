// OSPRay's cameras: perspective, orthographic, panoramic.
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>

namespace sciray::ospray {

void CameraObject::on_commit() {
  CameraCommon common;
  common.position = get_vec3f("position", {0.f, 0.f, 0.f});
  common.direction = get_vec3f("direction", {0.f, 0.f, 1.f});
  common.up = get_vec3f("up", {0.f, 1.f, 0.f});
  // `transform` and `motion.*` move the camera's position, direction and up (not its
  // sizes); the engine validates every placement.
  MotionTransform placement = read_placement(*this, [this](const std::string& id) { return find(id); });
  if (placement.moving() || !placement.key(0).identity())
    common.motion = std::make_shared<const MotionTransform>(std::move(placement));
  common.near_clip = get_float("nearClip", 1e-6f);  // OSPRay's default
  const auto vec2 = [&](const char* id, float& x, float& y) {
    const Param* p = find(id);
    if (!p) return;
    if (p->type != OSP_VEC2F) throw Error(name() + ": parameter '" + id + "' must be a vec2f, got " + type_name(p->type));
    x = read_float(p->bytes.data()), y = read_float(p->bytes.data() + 4);
  };
  vec2("imageStart", common.image_region.start_x, common.image_region.start_y);
  vec2("imageEnd", common.image_region.end_x, common.image_region.end_y);
  if (const Param* p = find("shutter"))
    std::tie(common.shutter_open, common.shutter_close) = read_range(*this, *p, "shutter");
  common.shutter_type = shutter_type_from_int(subtype(), get_int("shutterType", OSP_SHUTTER_GLOBAL));
  common.rolling_shutter_duration = get_float("rollingShutterDuration", 0.f);

  const auto stereo = [&] { return stereo_mode_from_int(subtype(), get_int("stereoMode", OSP_STEREO_NONE)); };
  Camera camera;
  if (subtype() == "perspective") {
    PerspectiveCamera c;
    static_cast<CameraCommon&>(c) = common;
    c.fovy = get_float("fovy", c.fovy);
    c.aspect = get_float("aspect", c.aspect);
    c.aperture_radius = get_float("apertureRadius", c.aperture_radius);
    c.focus_distance = get_float("focusDistance", c.focus_distance);
    c.architectural = get_bool("architectural", c.architectural);
    c.stereo_mode = stereo();
    c.interpupillary_distance = get_float("interpupillaryDistance", c.interpupillary_distance);
    camera = c;
  } else if (subtype() == "orthographic") {
    OrthographicCamera c;
    static_cast<CameraCommon&>(c) = common;
    c.height = get_float("height", c.height);
    c.aspect = get_float("aspect", c.aspect);
    camera = c;
  } else {
    PanoramicCamera c;
    static_cast<CameraCommon&>(c) = common;
    c.stereo_mode = stereo();
    c.interpupillary_distance = get_float("interpupillaryDistance", c.interpupillary_distance);
    camera = c;
  }
  std::visit([](const auto& c) { prepare(c); }, camera);  // validates, naming the bad parameter
  camera_ = camera;
}

}  // namespace sciray::ospray
