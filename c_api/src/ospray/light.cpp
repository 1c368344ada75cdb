// OSPRay's lights.
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

namespace sciray::ospray {

void Light::on_commit() {
  sciray::Light light;
  if (subtype() == "hdri") {
    auto* map = get_object<TextureObject>("map", OSP_TEXTURE, true);
    if (!map->committed() || !map->image()) throw Error(name() + ": parameter 'map' must be a committed texture2d");
    light = HdriLight(map->image(), get_vec3f("up", {0.f, 1.f, 0.f}), get_vec3f("direction", {0.f, 0.f, 1.f}));
  } else {
    light = *light_of_type(subtype());  // the factory creates only types the engine has
  }
  for_each_parameter(light, [&](const char* id, auto& field) { read_into(id, field); });
  try {
    validate(light);
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
  light_ = std::move(light);
}

}  // namespace sciray::ospray
