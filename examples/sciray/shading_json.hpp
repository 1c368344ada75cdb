#pragma once
// Materials and lights for the `sciray` tool, from JSON objects that use OSPRay's type
// and parameter names: {"type": "principled", "baseColor": [0.8, 0.1, 0.1], "roughness": 0.3}
// or {"type": "sphere", "position": [0, 2, 0], "radius": 0.2, "intensity": 10}.
#include <fstream>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "sciray/render/light.hpp"
#include "sciray/render/material.hpp"

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
    if (!j_[key].is_number()) throw sciray::Error(what_ + ": \"" + key + "\" must be a number");
    v = j_[key].get<float>();
  }
  void read(const char* key, bool& v) {
    if (!take(key)) return;
    if (!j_[key].is_boolean()) throw sciray::Error(what_ + ": \"" + key + "\" must be true or false");
    v = j_[key].get<bool>();
  }
  void read(const char* key, sciray::Vec3f& v) {
    if (!take(key)) return;
    const auto& a = j_[key];
    if (a.is_number()) {
      v = sciray::splat(a.get<float>());
      return;
    }
    if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
      throw sciray::Error(what_ + ": \"" + key + "\" must be a number or an array of 3 numbers");
    v = {a[0].get<float>(), a[1].get<float>(), a[2].get<float>()};
  }
  /// Throws for keys nothing read: a misspelt parameter must not be silently ignored.
  void check_all_used() const {
    for (const auto& [key, value] : j_.items())
      if (!used_.count(key)) throw sciray::Error(what_ + ": unknown parameter \"" + key + "\"");
  }

private:
  bool take(const char* key) {
    used_.insert(key);
    return j_.contains(key);
  }
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
  } catch (const nlohmann::json::parse_error& e) {
    throw sciray::Error(option + ": invalid JSON: " + e.what());
  }
}

inline sciray::Material material_from_json(const nlohmann::json& j, const std::string& what) {
  using namespace sciray;
  JsonParams p(j, what);
  const std::string type = p.type();
  Material material;
  if (type == "obj") {
    ObjMaterial m;
    p.read("kd", m.kd), p.read("ks", m.ks), p.read("ns", m.ns), p.read("d", m.d), p.read("tf", m.tf);
    material = m;
  } else if (type == "principled") {
    PrincipledMaterial m;
    p.read("baseColor", m.base_color), p.read("edgeColor", m.edge_color), p.read("metallic", m.metallic);
    p.read("diffuse", m.diffuse), p.read("specular", m.specular), p.read("ior", m.ior);
    p.read("transmission", m.transmission), p.read("transmissionColor", m.transmission_color);
    p.read("transmissionDepth", m.transmission_depth), p.read("roughness", m.roughness), p.read("thin", m.thin);
    p.read("thickness", m.thickness), p.read("coat", m.coat), p.read("coatIor", m.coat_ior);
    p.read("coatColor", m.coat_color), p.read("coatThickness", m.coat_thickness);
    p.read("coatRoughness", m.coat_roughness), p.read("sheen", m.sheen), p.read("sheenColor", m.sheen_color);
    p.read("sheenTint", m.sheen_tint), p.read("sheenRoughness", m.sheen_roughness), p.read("opacity", m.opacity);
    p.read("emissiveColor", m.emissive_color);
    material = m;
  } else if (type == "glass") {
    GlassMaterial m;
    p.read("eta", m.eta), p.read("attenuationColor", m.attenuation_color);
    p.read("attenuationDistance", m.attenuation_distance);
    material = m;
  } else if (type == "thinGlass") {
    ThinGlassMaterial m;
    p.read("eta", m.eta), p.read("attenuationColor", m.attenuation_color);
    p.read("attenuationDistance", m.attenuation_distance), p.read("thickness", m.thickness);
    material = m;
  } else if (type == "metal") {
    MetalMaterial m;
    p.read("eta", m.eta), p.read("k", m.k), p.read("roughness", m.roughness);
    material = m;
  } else if (type == "alloy") {
    AlloyMaterial m;
    p.read("color", m.color), p.read("edgeColor", m.edge_color), p.read("roughness", m.roughness);
    material = m;
  } else if (type == "luminous") {
    LuminousMaterial m;
    p.read("color", m.color), p.read("intensity", m.intensity), p.read("transparency", m.transparency);
    material = m;
  } else {
    throw Error(what + ": unknown material type '" + type + "' (obj, principled, glass, thinGlass, metal, alloy, luminous)");
  }
  p.check_all_used();
  try {
    validate(material);
  } catch (const Error& e) {
    throw Error(what + ": " + e.what());
  }
  return material;
}

inline sciray::Light light_from_json(const nlohmann::json& j, const std::string& what) {
  using namespace sciray;
  JsonParams p(j, what);
  const std::string type = p.type();
  const auto common = [&](auto light) {
    p.read("color", light.color), p.read("intensity", light.intensity), p.read("visible", light.visible);
    return light;
  };
  Light light;
  if (type == "ambient") {
    light = common(AmbientLight{});
  } else if (type == "distant") {
    DistantLight l = common(DistantLight{});
    p.read("direction", l.direction), p.read("angularDiameter", l.angular_diameter);
    light = l;
  } else if (type == "sphere") {
    SphereLight l = common(SphereLight{});
    p.read("position", l.position), p.read("radius", l.radius);
    light = l;
  } else if (type == "spot") {
    SpotLight l = common(SpotLight{});
    p.read("position", l.position), p.read("direction", l.direction), p.read("openingAngle", l.opening_angle);
    p.read("penumbraAngle", l.penumbra_angle), p.read("radius", l.radius);
    light = l;
  } else if (type == "quad") {
    QuadLight l = common(QuadLight{});
    p.read("position", l.position), p.read("edge1", l.edge1), p.read("edge2", l.edge2);
    light = l;
  } else {
    throw Error(what + ": unknown light type '" + type + "' (ambient, distant, sphere, spot, quad)");
  }
  p.check_all_used();
  try {
    validate(light);
  } catch (const Error& e) {
    throw Error(what + ": " + e.what());
  }
  return light;
}

}  // namespace sciray_tool
