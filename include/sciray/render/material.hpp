#pragma once
// Materials with OSPRay's type and parameter names (the C API maps them one to one).
// A renderer holds a list of them; every geometry names its entry by index (Group::add).
// The scivis and ao renderers read the `obj` view of any material (obj_view); the path
// tracer evaluates each type's BSDF (render/bsdf.hpp). Colours are linear RGB.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

/// OSPRay `obj`: Lambertian `kd` plus Phong `ks`/`ns`, opacity `d` and transmissive
/// filter `tf` (colour that light keeps when passing the surface).
struct ObjMaterial {
  Vec3f kd{0.8f, 0.8f, 0.8f};
  Vec3f ks{0.f, 0.f, 0.f};
  float ns = 10.f;
  float d = 1.f;
  Vec3f tf{0.f, 0.f, 0.f};
};

/// OSPRay `principled`: a layered physically based material (Disney/Burley style).
struct PrincipledMaterial {
  Vec3f base_color{0.8f, 0.8f, 0.8f};  ///< baseColor
  Vec3f edge_color{1.f, 1.f, 1.f};     ///< edgeColor: metal tint at grazing angles
  float metallic = 0.f;
  float diffuse = 1.f;
  float specular = 1.f;
  float ior = 1.5f;
  float transmission = 0.f;
  Vec3f transmission_color{1.f, 1.f, 1.f};
  float transmission_depth = 1.f;
  float roughness = 0.f;
  bool thin = false;
  float thickness = 1.f;
  float coat = 0.f;
  float coat_ior = 1.5f;
  Vec3f coat_color{1.f, 1.f, 1.f};
  float coat_thickness = 1.f;
  float coat_roughness = 0.f;
  float sheen = 0.f;
  Vec3f sheen_color{1.f, 1.f, 1.f};
  float sheen_tint = 0.f;
  float sheen_roughness = 0.2f;
  float opacity = 1.f;
  Vec3f emissive_color{0.f, 0.f, 0.f};  ///< emissiveColor (radiance)
};

/// OSPRay `glass`: a dielectric interface; light inside is attenuated to
/// `attenuation_color` over `attenuation_distance`.
struct GlassMaterial {
  float eta = 1.5f;
  Vec3f attenuation_color{1.f, 1.f, 1.f};
  float attenuation_distance = 1.f;
};

/// OSPRay `thinGlass`: a glass sheet of `thickness` with no refraction offset.
struct ThinGlassMaterial {
  float eta = 1.5f;
  Vec3f attenuation_color{1.f, 1.f, 1.f};
  float attenuation_distance = 1.f;
  float thickness = 1.f;
};

/// OSPRay `metal`: a conductor with complex index of refraction eta + i k per RGB channel
/// (default aluminium) and GGX roughness.
struct MetalMaterial {
  Vec3f eta{1.5f, 0.98f, 0.6f};
  Vec3f k{7.6f, 6.6f, 5.4f};
  float roughness = 0.1f;
};

/// OSPRay `alloy`: a conductor given by its colour at normal incidence and at the edge.
struct AlloyMaterial {
  Vec3f color{0.9f, 0.9f, 0.9f};
  Vec3f edge_color{1.f, 1.f, 1.f};
  float roughness = 0.1f;
};

/// OSPRay `luminous`: emits `color * intensity`; `transparency` lets light through.
struct LuminousMaterial {
  Vec3f color{1.f, 1.f, 1.f};
  float intensity = 1.f;
  float transparency = 0.f;
};

/// The material index of geometries added without one: they show their own colours,
/// 0.8 grey where they have none.
inline constexpr std::uint32_t no_material = 0xffffffffu;

using Material = std::variant<ObjMaterial, PrincipledMaterial, GlassMaterial, ThinGlassMaterial, MetalMaterial,
                              AlloyMaterial, LuminousMaterial>;

/// OSPRay's name of a material's type.
inline const char* type_name(const Material& m) {
  static constexpr const char* names[] = {"obj", "principled", "glass", "thinGlass", "metal", "alloy", "luminous"};
  return names[m.index()];
}

/// A default material of OSPRay type `type` (obj, principled, glass, thinGlass, metal,
/// alloy, luminous); nullopt for another name.
inline std::optional<Material> material_of_type(std::string_view type) {
  if (type == "obj") return ObjMaterial{};
  if (type == "principled") return PrincipledMaterial{};
  if (type == "glass") return GlassMaterial{};
  if (type == "thinGlass") return ThinGlassMaterial{};
  if (type == "metal") return MetalMaterial{};
  if (type == "alloy") return AlloyMaterial{};
  if (type == "luminous") return LuminousMaterial{};
  return std::nullopt;
}

/// Calls read(name, field) for every parameter of `material` under its OSPRay name
/// (field: float&, bool& or Vec3f&): the one table the C API and scene files both read.
template <class Read>
void for_each_parameter(Material& material, Read&& read) {
  std::visit(
      [&](auto& m) {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, ObjMaterial>) {
          read("kd", m.kd), read("ks", m.ks), read("ns", m.ns), read("d", m.d), read("tf", m.tf);
        } else if constexpr (std::is_same_v<M, PrincipledMaterial>) {
          read("baseColor", m.base_color), read("edgeColor", m.edge_color), read("metallic", m.metallic);
          read("diffuse", m.diffuse), read("specular", m.specular), read("ior", m.ior);
          read("transmission", m.transmission), read("transmissionColor", m.transmission_color);
          read("transmissionDepth", m.transmission_depth), read("roughness", m.roughness), read("thin", m.thin);
          read("thickness", m.thickness), read("coat", m.coat), read("coatIor", m.coat_ior);
          read("coatColor", m.coat_color), read("coatThickness", m.coat_thickness);
          read("coatRoughness", m.coat_roughness), read("sheen", m.sheen), read("sheenColor", m.sheen_color);
          read("sheenTint", m.sheen_tint), read("sheenRoughness", m.sheen_roughness), read("opacity", m.opacity);
          read("emissiveColor", m.emissive_color);
        } else if constexpr (std::is_same_v<M, GlassMaterial> || std::is_same_v<M, ThinGlassMaterial>) {
          read("eta", m.eta), read("attenuationColor", m.attenuation_color);
          read("attenuationDistance", m.attenuation_distance);
          if constexpr (std::is_same_v<M, ThinGlassMaterial>) read("thickness", m.thickness);
        } else if constexpr (std::is_same_v<M, MetalMaterial>) {
          read("eta", m.eta), read("k", m.k), read("roughness", m.roughness);
        } else if constexpr (std::is_same_v<M, AlloyMaterial>) {
          read("color", m.color), read("edgeColor", m.edge_color), read("roughness", m.roughness);
        } else if constexpr (std::is_same_v<M, LuminousMaterial>) {
          read("color", m.color), read("intensity", m.intensity), read("transparency", m.transparency);
        }
      },
      material);
}

/// What the scivis and ao renderers see of any material: diffuse and specular colour,
/// shininess, opacity and transmissive filter.
inline ObjMaterial obj_view(const Material& material) {
  return std::visit(
      [](const auto& m) -> ObjMaterial {
        using M = std::decay_t<decltype(m)>;
        ObjMaterial o;
        if constexpr (std::is_same_v<M, ObjMaterial>) {
          o = m;
        } else if constexpr (std::is_same_v<M, PrincipledMaterial>) {
          o.kd = m.base_color * ((1.f - m.metallic) * (1.f - m.transmission));
          o.ks = m.base_color * m.metallic + splat(0.04f * (1.f - m.metallic) * m.specular);
          o.ns = 2.f / std::max(1e-3f, m.roughness * m.roughness * m.roughness * m.roughness) - 2.f;
          o.d = m.opacity * (1.f - m.transmission);
          o.tf = m.transmission_color * m.transmission;
        } else if constexpr (std::is_same_v<M, GlassMaterial> || std::is_same_v<M, ThinGlassMaterial>) {
          o.kd = splat(0.f);
          o.ks = splat(0.04f);
          o.ns = 1000.f;
          o.d = 0.f;
          o.tf = m.attenuation_color;
        } else if constexpr (std::is_same_v<M, MetalMaterial>) {
          // Reflectance at normal incidence of a conductor.
          const auto r0 = [](float eta, float k) {
            return ((eta - 1.f) * (eta - 1.f) + k * k) / ((eta + 1.f) * (eta + 1.f) + k * k);
          };
          o.kd = splat(0.f);
          o.ks = {r0(m.eta.x, m.k.x), r0(m.eta.y, m.k.y), r0(m.eta.z, m.k.z)};
          o.ns = 2.f / std::max(1e-3f, m.roughness * m.roughness * m.roughness * m.roughness) - 2.f;
        } else if constexpr (std::is_same_v<M, AlloyMaterial>) {
          o.kd = splat(0.f);
          o.ks = m.color;
          o.ns = 2.f / std::max(1e-3f, m.roughness * m.roughness * m.roughness * m.roughness) - 2.f;
        } else if constexpr (std::is_same_v<M, LuminousMaterial>) {
          o.kd = m.color * m.intensity;  // shown at its emitted colour
          o.d = 1.f - m.transparency;
        }
        return o;
      },
      material);
}

namespace detail {
inline bool finite_non_negative(const Vec3f& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0.f && v.y >= 0.f && v.z >= 0.f;
}
inline void require(bool ok, const std::string& type, const char* parameter, const char* what) {
  if (!ok) throw Error(type + " material: parameter '" + parameter + "' " + what);
}
inline bool in_unit(float v) { return v >= 0.f && v <= 1.f; }
inline bool positive(float v) { return v > 0.f && std::isfinite(v); }
}  // namespace detail

/// Throws an Error naming the first parameter out of its range.
inline void validate(const Material& material) {
  using detail::finite_non_negative, detail::require, detail::in_unit, detail::positive;
  const std::string type = type_name(material);
  std::visit(
      [&](const auto& m) {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, ObjMaterial>) {
          require(finite_non_negative(m.kd), type, "kd", "must be finite and not negative");
          require(finite_non_negative(m.ks), type, "ks", "must be finite and not negative");
          require(m.ns >= 0.f && std::isfinite(m.ns), type, "ns", "must be finite and not negative");
          require(in_unit(m.d), type, "d", "must be in [0, 1]");
          require(finite_non_negative(m.tf), type, "tf", "must be finite and not negative");
        } else if constexpr (std::is_same_v<M, PrincipledMaterial>) {
          require(finite_non_negative(m.base_color), type, "baseColor", "must be finite and not negative");
          require(finite_non_negative(m.edge_color), type, "edgeColor", "must be finite and not negative");
          require(in_unit(m.metallic), type, "metallic", "must be in [0, 1]");
          require(in_unit(m.diffuse), type, "diffuse", "must be in [0, 1]");
          require(in_unit(m.specular), type, "specular", "must be in [0, 1]");
          require(positive(m.ior), type, "ior", "must be positive");
          require(in_unit(m.transmission), type, "transmission", "must be in [0, 1]");
          require(finite_non_negative(m.transmission_color), type, "transmissionColor", "must be finite and not negative");
          require(positive(m.transmission_depth), type, "transmissionDepth", "must be positive");
          require(in_unit(m.roughness), type, "roughness", "must be in [0, 1]");
          require(positive(m.thickness), type, "thickness", "must be positive");
          require(in_unit(m.coat), type, "coat", "must be in [0, 1]");
          require(positive(m.coat_ior), type, "coatIor", "must be positive");
          require(finite_non_negative(m.coat_color), type, "coatColor", "must be finite and not negative");
          require(m.coat_thickness >= 0.f && std::isfinite(m.coat_thickness), type, "coatThickness",
                  "must be finite and not negative");
          require(in_unit(m.coat_roughness), type, "coatRoughness", "must be in [0, 1]");
          require(in_unit(m.sheen), type, "sheen", "must be in [0, 1]");
          require(finite_non_negative(m.sheen_color), type, "sheenColor", "must be finite and not negative");
          require(in_unit(m.sheen_tint), type, "sheenTint", "must be in [0, 1]");
          require(in_unit(m.sheen_roughness), type, "sheenRoughness", "must be in [0, 1]");
          require(in_unit(m.opacity), type, "opacity", "must be in [0, 1]");
          require(finite_non_negative(m.emissive_color), type, "emissiveColor", "must be finite and not negative");
        } else if constexpr (std::is_same_v<M, GlassMaterial> || std::is_same_v<M, ThinGlassMaterial>) {
          require(positive(m.eta), type, "eta", "must be positive");
          require(finite_non_negative(m.attenuation_color), type, "attenuationColor", "must be finite and not negative");
          require(positive(m.attenuation_distance), type, "attenuationDistance", "must be positive");
          if constexpr (std::is_same_v<M, ThinGlassMaterial>)
            require(m.thickness >= 0.f && std::isfinite(m.thickness), type, "thickness", "must be finite and not negative");
        } else if constexpr (std::is_same_v<M, MetalMaterial>) {
          require(finite_non_negative(m.eta) && m.eta.x > 0.f && m.eta.y > 0.f && m.eta.z > 0.f, type, "eta",
                  "must be positive");
          require(finite_non_negative(m.k), type, "k", "must be finite and not negative");
          require(in_unit(m.roughness), type, "roughness", "must be in [0, 1]");
        } else if constexpr (std::is_same_v<M, AlloyMaterial>) {
          require(finite_non_negative(m.color), type, "color", "must be finite and not negative");
          require(finite_non_negative(m.edge_color), type, "edgeColor", "must be finite and not negative");
          require(in_unit(m.roughness), type, "roughness", "must be in [0, 1]");
        } else if constexpr (std::is_same_v<M, LuminousMaterial>) {
          require(finite_non_negative(m.color), type, "color", "must be finite and not negative");
          require(m.intensity >= 0.f && std::isfinite(m.intensity), type, "intensity", "must be finite and not negative");
          require(in_unit(m.transparency), type, "transparency", "must be in [0, 1]");
        }
      },
      material);
}

}  // namespace sciray
