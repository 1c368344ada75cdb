#pragma once
// Materials and lights for the `sciray` tool, from JSON objects that use OSPRay's type
// and parameter names: {"type": "principled", "baseColor": [0.8, 0.1, 0.1], "roughness": 0.3}
// or {"type": "sphere", "position": [0, 2, 0], "radius": 0.2, "intensity": 10}.
// A material's maps are image files (PNG or PFM): {"type": "obj", "map_kd": "colormap.png"},
// with OSPRay's "map_kd.rotation" (degrees), "map_kd.scale" and "map_kd.translation" ([u, v]).
// A mix holds its two materials as objects of their own:
// {"type": "mix", "material1": {"type": "obj"}, "material2": {"type": "metal"}, "factor": 0.3}.
#include <fstream>
#include <set>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "sciray/io/image.hpp"
#include "sciray/math/color.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/render/light.hpp"
#include "sciray/render/material.hpp"
#include "json_float.hpp"

namespace sciray_tool {

/// Reads parameters out of one JSON object, naming the object in every error, and
/// refusing parameters it does not know.
class JsonParams {
public:
  JsonParams(const nlohmann::json& j, std::string what) : j_(j), what_(std::move(what)) {
    if (!j.is_object()) throw sciray::Error(what_ + ": expected a JSON object");
  }
  std::string type() {
    used_.insert("type");
    if (!j_.contains("type") || !j_["type"].is_string()) throw sciray::Error(what_ + ": missing \"type\" (a string)");
    return j_["type"].get<std::string>();
  }
  void read(const char* key, float& v) {
    if (!take(key)) return;
    v = json_float(j_[key], named(key));
  }
  void read(const char* key, bool& v) {
    if (!take(key)) return;
    if (!j_[key].is_boolean()) throw sciray::Error(named(key) + " must be true or false");
    v = j_[key].get<bool>();
  }
  void read(const char* key, sciray::Vec3f& v) {
    if (!take(key)) return;
    const auto& a = j_[key];
    if (a.is_number()) {
      v = sciray::splat(json_float(a, named(key)));
      return;
    }
    if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
      throw sciray::Error(named(key) + " must be a number or an array of 3 numbers");
    const std::string name = named(key);
    v = {json_float(a[0], name), json_float(a[1], name), json_float(a[2], name)};
  }
  /// A colour whose absence means something (carPaint's flakeColor): set only when given.
  void read(const char* key, std::optional<sciray::Vec3f>& v) {
    if (!j_.contains(key)) return take(key), void();
    sciray::Vec3f c;
    read(key, c);
    v = c;
  }
  void read(const char* key, sciray::TexCoord<float>& v) {
    if (!take(key)) return;
    const auto& a = j_[key];
    if (!a.is_array() || a.size() != 2 || !a[0].is_number() || !a[1].is_number())
      throw sciray::Error(named(key) + " must be an array of 2 numbers");
    const std::string name = named(key);
    v = {json_float(a[0], name), json_float(a[1], name)};
  }
  /// A map `key`: an image file, with its rotation, scale and translation. PNG colour maps
  /// hold sRGB values and are made linear; scalar maps are read as they are.
  void read_map(const std::string& key, sciray::TextureMap& map, bool color) {
    if (!take(key.c_str())) return;
    if (!j_[key].is_string()) throw sciray::Error(named(key) + " must be an image file name");
    const std::string file = j_[key].get<std::string>();
    sciray::io::Image image;
    try {
      image = sciray::io::read_image(file);
    } catch (const sciray::Error& e) {
      throw sciray::Error(named(key) + ": " + e.what());
    }
    const bool srgb = color && std::filesystem::path(file).extension() == ".png";
    // Row 0 of a texture is its bottom (v = 0); an image file's is its top.
    std::vector<sciray::Vec3f> texels(static_cast<std::size_t>(image.width) * image.height);
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        float c[3];
        for (int k = 0; k < 3; ++k) {
          const float v = image.at(x, image.height - 1 - y, image.channels >= 3 ? k : 0);
          c[k] = srgb ? sciray::srgb_to_linear(v) : v;
        }
        texels[static_cast<std::size_t>(y) * image.width + x] = {c[0], c[1], c[2]};
      }
    try {
      map.texture = std::make_shared<const sciray::Texture2D>(image.width, image.height, std::move(texels));
    } catch (const sciray::Error& e) {
      throw sciray::Error(named(key) + " (" + file + "): " + e.what());
    }
    float rotation = 0.f;
    sciray::TexCoord<float> scale{1.f, 1.f}, translation{0.f, 0.f};
    read((key + ".rotation").c_str(), rotation);
    read((key + ".scale").c_str(), scale);
    read((key + ".translation").c_str(), translation);
    if (scale.u == 0.f || scale.v == 0.f) throw sciray::Error(what_ + ": \"" + key + ".scale\" must not be zero");
    map.transform = sciray::TexCoordTransform::of_texture(rotation, scale, translation);
  }
  /// The JSON object `key`, or null where it is not given.
  const nlohmann::json* object(const char* key) {
    if (!take(key)) return nullptr;
    if (!j_[key].is_object()) throw sciray::Error(named(key) + " must be a JSON object");
    return &j_[key];
  }
  /// Throws for keys nothing read: a misspelt parameter must not be silently ignored.
  void check_all_used() const {
    for (const auto& [key, value] : j_.items())
      if (!used_.count(key)) throw sciray::Error(what_ + ": unknown parameter \"" + key + "\"");
  }

private:
  bool take(const std::string& key) {
    used_.insert(key);
    return j_.contains(key);
  }
  /// `key` as messages name it: the object, then the key in quotes.
  std::string named(std::string_view key) const { return what_ + ": \"" + std::string(key) + "\""; }
  const nlohmann::json& j_;
  std::string what_;
  std::set<std::string> used_;
};

inline nlohmann::json parse_json_argument(const std::string& text, const std::string& option) {
  // A file name, or the JSON itself.
  try {
    if (!text.empty() && text.front() != '{') {
      std::ifstream in(text);
      if (!in) throw sciray::Error(option + ": cannot open '" + text + "'");
      return nlohmann::json::parse(in);
    }
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for a number beyond double
    throw sciray::Error(option + ": invalid JSON: " + e.what());
  }
}

inline sciray::Material material_from_json(const nlohmann::json& j, const std::string& what) {
  JsonParams p(j, what);
  const std::string type = p.type();
  std::optional<sciray::Material> material = sciray::material_of_type(type);
  if (!material)
    throw sciray::Error(what + ": unknown material type '" + type + "' (" + sciray::material_type_list() + ")");
  sciray::for_each_parameter(*material, [&](const char* key, auto& field) { p.read(key, field); });
  sciray::for_each_map(*material, [&](const char* key, sciray::TextureMap& map) {
    const std::string name = key;
    p.read_map(name, map, name == "map_kd" || name == "map_ks" || name == "map_baseColor");
  });
  if (auto* mix = std::get_if<sciray::MixMaterial>(&*material)) {
    if (const nlohmann::json* part = p.object("material1"))
      mix->material1 = sciray::mix_part(material_from_json(*part, what + " material1"));
    if (const nlohmann::json* part = p.object("material2"))
      mix->material2 = sciray::mix_part(material_from_json(*part, what + " material2"));
  }
  p.check_all_used();
  try {
    sciray::validate(*material);
  } catch (const sciray::Error& e) {
    throw sciray::Error(what + ": " + e.what());
  }
  return *material;
}

/// The lights of a scene without its own: one from the upper left behind the viewer, as
/// a desk lamp would be, and some ambient light.
inline std::vector<sciray::Light> desk_lamp_lights(const sciray::CameraCommon& view) {
  const sciray::Vec3f forward = normalize(view.direction);
  const sciray::Vec3f right = normalize(cross(forward, view.up));
  const sciray::Vec3f up = cross(right, forward);
  return sciray::default_lights(normalize(forward + right * 0.5f - up * 0.7f));
}

inline sciray::Light light_from_json(const nlohmann::json& j, const std::string& what) {
  JsonParams p(j, what);
  const std::string type = p.type();
  std::optional<sciray::Light> light = sciray::light_of_type(type);
  if (!light) throw sciray::Error(what + ": unknown light type '" + type + "' (ambient, distant, sphere, spot, quad)");
  sciray::for_each_parameter(*light, [&](const char* key, auto& field) { p.read(key, field); });
  p.check_all_used();
  try {
    sciray::validate(*light);
  } catch (const sciray::Error& e) {
    throw sciray::Error(what + ": " + e.what());
  }
  return *light;
}

}  // namespace sciray_tool
