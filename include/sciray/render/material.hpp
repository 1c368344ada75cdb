#pragma once
// Materials with OSPRay's type and parameter names (the C API maps them one to one).
// A renderer holds a list of them; every geometry names its entry by index (Group::add).
// The scivis and ao renderers read the `obj` view of any material (obj_view); the path
// tracer evaluates each type's BSDF (render/bsdf.hpp). Colours are linear RGB.
//
// Texture maps (OSPRay's `map_kd`, `map_baseColor`, ...) multiply their parameter at the
// surface's texture coordinates; `textured` resolves them at a hit, so every renderer
// and BSDF keeps reading plain parameter values.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/texture.hpp"

namespace sciray {

/// OSPRay `obj`: Lambertian `kd` plus Phong `ks`/`ns`, opacity `d` and transmissive
/// filter `tf` (colour that light keeps when passing the surface).
struct ObjMaterial {
  Vec3f kd{0.8f, 0.8f, 0.8f};
  Vec3f ks{0.f, 0.f, 0.f};
  float ns = 10.f;
  float d = 1.f;
  Vec3f tf{0.f, 0.f, 0.f};
  TextureMap map_kd{}, map_ks{}, map_ns{}, map_d{};
  NormalMap map_bump{};  ///< a normal map, as OSPRay's obj material reads map_bump
  /// Whether kd, ks and tf are already scaled for energy conservation (energy_conserving
  /// then leaves them): where kd multiplies geometry colours that baked in the
  /// material's own kd, conservation has to be judged by that kd, not by this one.
  bool energy_conserved = false;
};

/// OSPRay `principled`: a layered physically based material (Disney/Burley style).
struct PrincipledMaterial {
  Vec3f base_color{0.8f, 0.8f, 0.8f};  ///< baseColor
  Vec3f edge_color{1.f, 1.f, 1.f};     ///< edgeColor: metal tint at grazing angles
  float metallic = 0.f;
  float diffuse = 1.f;
  float specular = 1.f;
  float ior = 1.f;  ///< OSPRay's default: no specular interface (and no refraction) unless set
  float transmission = 0.f;
  Vec3f transmission_color{1.f, 1.f, 1.f};
  float transmission_depth = 1.f;  ///< 0 absorbs all but channels of transmissionColor 1
  float roughness = 0.f;
  /// In [0, 1]: GGX stretched along the tangent (the surface's dP/ds), shrunk across it,
  /// as OSPRay's (Burley 2012: alpha / aspect and alpha * aspect, aspect = sqrt(1 - 0.9 a)).
  float anisotropy = 0.f;
  float rotation = 0.f;  ///< in [0, 1]: turns the tangent about the normal by 2 pi rotation
  bool thin = false;
  float thickness = 1.f;
  float backlight = 0.f;  ///< thin only: in [0, 2], half of it is the diffuse part transmitted (1: as much as reflected)
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
  float normal = 1.f;                   ///< how strongly map_normal tilts the normal
  /// map_<parameter> of every parameter but thin and normal, as OSPRay's.
  TextureMap map_base_color{}, map_edge_color{}, map_metallic{}, map_diffuse{}, map_specular{}, map_ior{},
      map_transmission{}, map_transmission_color{}, map_transmission_depth{}, map_roughness{}, map_anisotropy{},
      map_rotation{}, map_thickness{}, map_backlight{}, map_coat{}, map_coat_ior{}, map_coat_color{},
      map_coat_thickness{}, map_coat_roughness{}, map_sheen{}, map_sheen_color{}, map_sheen_tint{},
      map_sheen_roughness{}, map_opacity{}, map_emissive_color{};
  NormalMap map_normal{};
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
  TextureMap map_attenuation_color{};
};

/// OSPRay `metal`: a conductor with complex index of refraction eta + i k per RGB channel
/// (default aluminium) and GGX roughness.
struct MetalMaterial {
  Vec3f eta{1.5f, 0.98f, 0.6f};
  Vec3f k{7.6f, 6.6f, 5.4f};
  float roughness = 0.1f;
  TextureMap map_roughness{};
};

/// OSPRay `alloy`: a conductor given by its colour at normal incidence and at the edge.
struct AlloyMaterial {
  Vec3f color{0.9f, 0.9f, 0.9f};
  Vec3f edge_color{1.f, 1.f, 1.f};
  float roughness = 0.1f;
  TextureMap map_color{}, map_edge_color{}, map_roughness{};
};

/// OSPRay `luminous`: emits `color * intensity` (times `map_color`) from both faces;
/// `transparency` lets light through. The path tracer samples such surfaces as lights
/// (render/geometry_light.hpp).
struct LuminousMaterial {
  Vec3f color{1.f, 1.f, 1.f};
  float intensity = 1.f;
  float transparency = 0.f;
  TextureMap map_color{};
};

/// OSPRay `velvet`: a Minnaert lobe of `reflectance` whose `backScattering` exponent
/// bends it towards the viewer, plus a lobe of `horizonScatteringColor` that grows as
/// sin(θo)^horizonScatteringFallOff towards grazing views (both cosine-weighted, not
/// normalised: their albedos add, as in OSPRay). The geometry's colour plays no part.
struct VelvetMaterial {
  Vec3f reflectance{0.4f, 0.f, 0.f};
  float back_scattering = 0.5f;
  Vec3f horizon_scattering_color{0.75f, 0.1f, 0.1f};
  float horizon_scattering_fall_off = 10.f;
};

/// OSPRay `metallicPaint`: a Lambertian base of `baseColor` (1 - flakeAmount) and GGX
/// aluminium flakes (Schlick from flakeColor·flakeAmount at normal incidence to
/// flakeAmount at grazing, roughness `flakeSpread`) under a smooth clear coat of index `eta`.
struct MetallicPaintMaterial {
  Vec3f base_color{0.8f, 0.8f, 0.8f};
  float flake_amount = 0.3f;
  Vec3f flake_color{0.909f, 0.916f, 0.923f};  ///< aluminium's reflectance at normal incidence
  float flake_spread = 0.5f;
  float eta = 1.5f;
  TextureMap map_base_color{};
};

/// OSPRay `carPaint`: a diffuse base (Lambertian, Oren–Nayar for `roughness` > 0) with
/// metallic flakes in it, under a clear coat. The flakes are cells of a jittered 3D grid
/// of `flakeScale` cells per world unit around the hit point; a cell holds a flake with
/// probability `flakeDensity`, tilted by a Beckmann normal of roughness `flakeSpread`, and
/// where a flake is the base is not: the flake reflects as aluminium (`flakeColor` unset)
/// or as Schlick from flakeColor to white, GGX of `flakeRoughness`. Over a flake the coat
/// turns from coatColor to `flipflopColor` at grazing angles, the faster the lower
/// `flipflopFalloff` (1: never).
struct CarPaintMaterial {
  Vec3f base_color{0.8f, 0.8f, 0.8f};
  float roughness = 0.f;
  float normal = 1.f;  ///< how strongly map_normal tilts the base's normal
  std::optional<Vec3f> flake_color{};
  float flake_scale = 100.f;
  float flake_density = 0.f;
  float flake_spread = 0.3f;
  float flake_jitter = 0.75f;
  float flake_roughness = 0.3f;
  float coat = 1.f;
  float coat_ior = 1.5f;
  Vec3f coat_color{1.f, 1.f, 1.f};
  float coat_thickness = 1.f;
  float coat_roughness = 0.f;
  float coat_normal = 1.f;  ///< how strongly map_coatNormal tilts the coat's normal
  Vec3f flipflop_color{1.f, 1.f, 1.f};
  float flipflop_falloff = 1.f;
  TextureMap map_base_color{}, map_roughness{}, map_flake_color{}, map_flake_scale{}, map_flake_density{},
      map_flake_spread{}, map_flake_jitter{}, map_flake_roughness{}, map_coat{}, map_coat_ior{}, map_coat_color{},
      map_coat_thickness{}, map_coat_roughness{}, map_flipflop_color{}, map_flipflop_falloff{};
  NormalMap map_normal{};       ///< tilts the base (not the flakes, not the coat)
  NormalMap map_coat_normal{};  ///< tilts the coat
};

/// OSPRay `plastic`: a Lambertian `pigmentColor` under a clear coat of index `eta`, GGX
/// rough by `roughness` (0: smooth). The geometry's colour plays no part.
struct PlasticMaterial {
  Vec3f pigment_color{1.f, 1.f, 1.f};
  float eta = 1.4f;
  float roughness = 0.01f;
};

struct MixPart;

/// OSPRay `mix`: two materials blended by `factor` (times `map_factor`, clamped to [0, 1]):
/// the path tracer scatters as (1 - factor)·material1 + factor·material2 (and picks between
/// their BSDFs in that proportion), emits (1 - factor)·emission1 + factor·emission2 by the
/// plain `factor` (OSPRay's, which its map leaves out) and lets through their mixed
/// transparency. The parts are materials of any type, mixes too (make them with mix_part);
/// they are shared, not copied, and immutable, so a mix cannot contain itself. The parts'
/// texture maps are read at the mix's surface coordinates; their normal maps are not applied.
struct MixMaterial {
  std::shared_ptr<const MixPart> material1, material2;
  float factor = 0.5f;
  TextureMap map_factor{};
};

/// The material index of geometries added without one: they show their own colours,
/// 0.8 grey where they have none.
inline constexpr std::uint32_t no_material = 0xffffffffu;

using Material = std::variant<ObjMaterial, PrincipledMaterial, GlassMaterial, ThinGlassMaterial, MetalMaterial,
                              AlloyMaterial, LuminousMaterial, VelvetMaterial, MetallicPaintMaterial, CarPaintMaterial,
                              PlasticMaterial, MixMaterial>;

/// A part of a mix: a Material behind a pointer (the variant cannot hold itself).
struct MixPart {
  Material material;
};

/// `material` as a part of a MixMaterial.
inline std::shared_ptr<const MixPart> mix_part(Material material) {
  return std::make_shared<const MixPart>(MixPart{std::move(material)});
}

/// OSPRay's names of the material types, in the order of Material's alternatives.
inline constexpr std::array<const char*, std::variant_size_v<Material>> material_type_names = {
    "obj",   "principled",    "glass",    "thinGlass", "metal",  "alloy",
    "luminous", "velvet", "metallicPaint", "carPaint", "plastic", "mix"};

/// The names of every material type, comma-separated: for messages.
inline std::string material_type_list() {
  std::string list;
  for (const char* name : material_type_names) list += (list.empty() ? "" : ", ") + std::string(name);
  return list;
}

/// OSPRay's name of a material's type.
inline const char* type_name(const Material& m) { return material_type_names[m.index()]; }

/// A default material of OSPRay type `type` (one of material_type_names); nullopt for
/// another name.
inline std::optional<Material> material_of_type(std::string_view type) {
  std::optional<Material> result;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    ((type == material_type_names[I] ? void(result.emplace(std::in_place_index<I>)) : void()), ...);
  }(std::make_index_sequence<std::variant_size_v<Material>>{});
  return result;
}

namespace detail {
/// read(name, field) for every parameter of one material type; M may be const.
template <class M, class Read>
void parameters_of(M& m, Read&& read) {
  using T = std::remove_const_t<M>;
  if constexpr (std::is_same_v<T, ObjMaterial>) {
    read("kd", m.kd), read("ks", m.ks), read("ns", m.ns), read("d", m.d), read("tf", m.tf);
  } else if constexpr (std::is_same_v<T, PrincipledMaterial>) {
    read("baseColor", m.base_color), read("edgeColor", m.edge_color), read("metallic", m.metallic);
    read("diffuse", m.diffuse), read("specular", m.specular), read("ior", m.ior);
    read("transmission", m.transmission), read("transmissionColor", m.transmission_color);
    read("transmissionDepth", m.transmission_depth), read("roughness", m.roughness);
    read("anisotropy", m.anisotropy), read("rotation", m.rotation), read("thin", m.thin);
    read("thickness", m.thickness), read("backlight", m.backlight), read("coat", m.coat), read("coatIor", m.coat_ior);
    read("coatColor", m.coat_color), read("coatThickness", m.coat_thickness);
    read("coatRoughness", m.coat_roughness), read("sheen", m.sheen), read("sheenColor", m.sheen_color);
    read("sheenTint", m.sheen_tint), read("sheenRoughness", m.sheen_roughness), read("opacity", m.opacity);
    read("emissiveColor", m.emissive_color), read("normal", m.normal);
  } else if constexpr (std::is_same_v<T, GlassMaterial> || std::is_same_v<T, ThinGlassMaterial>) {
    read("eta", m.eta), read("attenuationColor", m.attenuation_color);
    read("attenuationDistance", m.attenuation_distance);
    if constexpr (std::is_same_v<T, ThinGlassMaterial>) read("thickness", m.thickness);
  } else if constexpr (std::is_same_v<T, MetalMaterial>) {
    read("eta", m.eta), read("k", m.k), read("roughness", m.roughness);
  } else if constexpr (std::is_same_v<T, AlloyMaterial>) {
    read("color", m.color), read("edgeColor", m.edge_color), read("roughness", m.roughness);
  } else if constexpr (std::is_same_v<T, LuminousMaterial>) {
    read("color", m.color), read("intensity", m.intensity), read("transparency", m.transparency);
  } else if constexpr (std::is_same_v<T, VelvetMaterial>) {
    read("reflectance", m.reflectance), read("backScattering", m.back_scattering);
    read("horizonScatteringColor", m.horizon_scattering_color);
    read("horizonScatteringFallOff", m.horizon_scattering_fall_off);
  } else if constexpr (std::is_same_v<T, MetallicPaintMaterial>) {
    read("baseColor", m.base_color), read("flakeAmount", m.flake_amount), read("flakeColor", m.flake_color);
    read("flakeSpread", m.flake_spread), read("eta", m.eta);
  } else if constexpr (std::is_same_v<T, CarPaintMaterial>) {
    read("baseColor", m.base_color), read("roughness", m.roughness), read("normal", m.normal);
    read("flakeColor", m.flake_color), read("flakeScale", m.flake_scale), read("flakeDensity", m.flake_density);
    read("flakeSpread", m.flake_spread), read("flakeJitter", m.flake_jitter);
    read("flakeRoughness", m.flake_roughness), read("coat", m.coat), read("coatIor", m.coat_ior);
    read("coatColor", m.coat_color), read("coatThickness", m.coat_thickness);
    read("coatRoughness", m.coat_roughness), read("coatNormal", m.coat_normal);
    read("flipflopColor", m.flipflop_color), read("flipflopFalloff", m.flipflop_falloff);
  } else if constexpr (std::is_same_v<T, PlasticMaterial>) {
    read("pigmentColor", m.pigment_color), read("eta", m.eta), read("roughness", m.roughness);
  } else if constexpr (std::is_same_v<T, MixMaterial>) {
    read("factor", m.factor);  // material1 and material2 are materials: their readers set them
  }
}

/// map(name, map) for every texture map of one material type; M may be const.
template <class M, class Map>
void maps_of(M& m, Map&& map) {
  using T = std::remove_const_t<M>;
  if constexpr (std::is_same_v<T, ObjMaterial>) {
    map("map_kd", m.map_kd), map("map_ks", m.map_ks), map("map_ns", m.map_ns), map("map_d", m.map_d);
  } else if constexpr (std::is_same_v<T, PrincipledMaterial>) {
    map("map_baseColor", m.map_base_color), map("map_edgeColor", m.map_edge_color), map("map_metallic", m.map_metallic);
    map("map_diffuse", m.map_diffuse), map("map_specular", m.map_specular), map("map_ior", m.map_ior);
    map("map_transmission", m.map_transmission), map("map_transmissionColor", m.map_transmission_color);
    map("map_transmissionDepth", m.map_transmission_depth), map("map_roughness", m.map_roughness);
    map("map_anisotropy", m.map_anisotropy), map("map_rotation", m.map_rotation);
    map("map_thickness", m.map_thickness), map("map_backlight", m.map_backlight), map("map_coat", m.map_coat);
    map("map_coatIor", m.map_coat_ior), map("map_coatColor", m.map_coat_color);
    map("map_coatThickness", m.map_coat_thickness), map("map_coatRoughness", m.map_coat_roughness);
    map("map_sheen", m.map_sheen), map("map_sheenColor", m.map_sheen_color), map("map_sheenTint", m.map_sheen_tint);
    map("map_sheenRoughness", m.map_sheen_roughness), map("map_opacity", m.map_opacity);
    map("map_emissiveColor", m.map_emissive_color);
  } else if constexpr (std::is_same_v<T, LuminousMaterial>) {
    map("map_color", m.map_color);
  } else if constexpr (std::is_same_v<T, ThinGlassMaterial>) {
    map("map_attenuationColor", m.map_attenuation_color);
  } else if constexpr (std::is_same_v<T, MetalMaterial>) {
    map("map_roughness", m.map_roughness);
  } else if constexpr (std::is_same_v<T, AlloyMaterial>) {
    map("map_color", m.map_color), map("map_edgeColor", m.map_edge_color), map("map_roughness", m.map_roughness);
  } else if constexpr (std::is_same_v<T, MetallicPaintMaterial>) {
    map("map_baseColor", m.map_base_color);
  } else if constexpr (std::is_same_v<T, CarPaintMaterial>) {
    map("map_baseColor", m.map_base_color), map("map_roughness", m.map_roughness);
    map("map_flakeColor", m.map_flake_color), map("map_flakeScale", m.map_flake_scale);
    map("map_flakeDensity", m.map_flake_density), map("map_flakeSpread", m.map_flake_spread);
    map("map_flakeJitter", m.map_flake_jitter), map("map_flakeRoughness", m.map_flake_roughness);
    map("map_coat", m.map_coat), map("map_coatIor", m.map_coat_ior), map("map_coatColor", m.map_coat_color);
    map("map_coatThickness", m.map_coat_thickness), map("map_coatRoughness", m.map_coat_roughness);
    map("map_flipflopColor", m.map_flipflop_color), map("map_flipflopFalloff", m.map_flipflop_falloff);
  } else if constexpr (std::is_same_v<T, MixMaterial>) {
    map("map_factor", m.map_factor);
  }
}

/// The normal map of one material type and the scale of its x and y, or null.
template <class M>
auto* normal_map_of(M& m, float* scale = nullptr) {
  using T = std::remove_const_t<M>;
  using Result = std::conditional_t<std::is_const_v<M>, const NormalMap*, NormalMap*>;
  if (scale) *scale = 1.f;
  if constexpr (std::is_same_v<T, ObjMaterial>) {
    return Result(&m.map_bump);
  } else if constexpr (std::is_same_v<T, PrincipledMaterial> || std::is_same_v<T, CarPaintMaterial>) {
    if (scale) *scale = m.normal;
    return Result(&m.map_normal);
  } else {
    return Result(nullptr);
  }
}

/// The normal map of a clear coat with a normal of its own (carPaint), and its scale, or null.
template <class M>
auto* coat_normal_map_of(M& m, float* scale = nullptr) {
  using T = std::remove_const_t<M>;
  using Result = std::conditional_t<std::is_const_v<M>, const NormalMap*, NormalMap*>;
  if (scale) *scale = 1.f;
  if constexpr (std::is_same_v<T, CarPaintMaterial>) {
    if (scale) *scale = m.coat_normal;
    return Result(&m.map_coat_normal);
  } else {
    return Result(nullptr);
  }
}
}  // namespace detail

/// Calls map(name, NormalMap&) for the normal maps `material`'s type has, under their
/// OSPRay names (obj: map_bump; principled: map_normal; carPaint: map_normal,
/// map_coatNormal; other types have none).
template <class Map>
void for_each_normal_map(Material& material, Map&& map) {
  std::visit(
      [&](auto& m) {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, ObjMaterial>) map("map_bump", m.map_bump);
        if constexpr (std::is_same_v<M, PrincipledMaterial>) map("map_normal", m.map_normal);
        if constexpr (std::is_same_v<M, CarPaintMaterial>) map("map_normal", m.map_normal);
        if constexpr (std::is_same_v<M, CarPaintMaterial>) map("map_coatNormal", m.map_coat_normal);
      },
      material);
}

/// Whether `material` has a normal map: its shading needs the surface's texture derivatives.
inline bool has_normal_map(const Material& material) {
  return std::visit(
      [](const auto& m) {
        const NormalMap* map = detail::normal_map_of(m);
        const NormalMap* coat = detail::coat_normal_map_of(m);
        return (map && bool(*map)) || (coat && bool(*coat));
      },
      material);
}

/// Whether `material` reflects anisotropically (principled anisotropy > 0, or a mix with
/// such a part): its shading needs a tangent, the surface's texture derivative dP/ds.
inline bool is_anisotropic(const Material& material) {
  if (const auto* mix = std::get_if<MixMaterial>(&material))
    return (mix->material1 && is_anisotropic(mix->material1->material)) ||
           (mix->material2 && is_anisotropic(mix->material2->material));
  const auto* principled = std::get_if<PrincipledMaterial>(&material);
  return principled && principled->anisotropy > 0.f;
}

/// The normal a clear coat with a normal of its own sees (carPaint's: the interpolated
/// normal `n`, which map_normal does not tilt, tilted by map_coatNormal; the flakes lie
/// along it too); nullopt where the coat shares the material's shading normal. Arguments as
/// mapped_normal's.
inline std::optional<Vec3f> mapped_coat_normal(const Material& material, const Vec3f& n, const Vec3f& dpds,
                                               const Vec3f& dpdt, const TexCoord<float>& uv) {
  return std::visit(
      [&](const auto& m) -> std::optional<Vec3f> {
        float scale;
        const NormalMap* coat = detail::coat_normal_map_of(m, &scale);
        if (!coat) return std::nullopt;
        return *coat ? coat->perturb(n, dpds, dpdt, uv, scale) : n;
      },
      material);
}

/// The shading normal `n` (unit, on the viewer's side) as `material`'s normal map tilts it
/// at texture coordinates uv, in the frame of the surface's texture derivatives dpds and
/// dpdt; n where the material has no normal map.
inline Vec3f mapped_normal(const Material& material, const Vec3f& n, const Vec3f& dpds, const Vec3f& dpdt,
                           const TexCoord<float>& uv) {
  return std::visit(
      [&](const auto& m) {
        float scale;
        const NormalMap* map = detail::normal_map_of(m, &scale);
        return map && *map ? map->perturb(n, dpds, dpdt, uv, scale) : n;
      },
      material);
}

/// Calls read(name, field) for every parameter of `material` under its OSPRay name
/// (field: float&, bool&, Vec3f&, or std::optional<Vec3f>& for a colour whose absence means
/// something: carPaint's flakeColor): the one table the C API and scene files both read.
template <class Read>
void for_each_parameter(Material& material, Read&& read) {
  std::visit([&](auto& m) { detail::parameters_of(m, read); }, material);
}

/// Calls map(name, TextureMap&) for every texture map `material`'s type has, under its
/// OSPRay name map_<parameter>, as OSPRay 3 maps them (obj: map_kd, map_ks, map_ns, map_d;
/// principled: every parameter but thin and normal; luminous: map_color; thinGlass:
/// map_attenuationColor; metal: map_roughness; alloy: map_color, map_edgeColor,
/// map_roughness; metallicPaint: map_baseColor; carPaint: every colour and float parameter
/// but normal and coatNormal; mix: map_factor; other types have none).
template <class Map>
void for_each_map(Material& material, Map&& map) {
  std::visit([&](auto& m) { detail::maps_of(m, map); }, material);
}

/// Whether any of `material`'s maps is set.
inline bool has_maps(const Material& material) {
  bool any = false;
  std::visit([&](const auto& m) { detail::maps_of(m, [&](const char*, const TextureMap& map) { any |= bool(map); }); },
             material);
  return any;
}

namespace detail {
/// More than any material type has parameters (or maps).
inline constexpr std::size_t max_parameters = 32;

/// For each parameter of type M (parameters_of's order), the index of its map (maps_of's
/// order) or -1: map_<name> scales the parameter <name>. Paired by name once per type,
/// so that resolving maps at a hit compares no strings.
template <class M>
const std::array<int, max_parameters>& map_of_parameter() {
  static const std::array<int, max_parameters> table = [] {
    std::array<int, max_parameters> pairs;
    pairs.fill(-1);
    const M m{};
    std::array<std::string_view, max_parameters> names{};
    std::size_t n = 0;
    parameters_of(m, [&](const char* name, const auto&) { names[n++] = name; });
    int k = 0;
    maps_of(m, [&](const char* map, const TextureMap&) {
      const std::string_view parameter = std::string_view(map).substr(4);  // map_kd: kd
      for (std::size_t j = 0; j < n; ++j)
        if (names[j] == parameter) pairs[j] = k;
      ++k;
    });
    return pairs;
  }();
  return table;
}
}  // namespace detail

/// The material at surface texture coordinates `uv`: `material` itself where it has no
/// maps (no copy: the untextured path costs a test), otherwise `storage`, filled with its
/// parameters times their maps (scalar maps by the first channel; parameters in [0, 1]
/// stay there, as OSPRay clamps them; the alpha of obj map_kd and principled map_baseColor
/// multiplies the opacity) and no maps. Shared textures are not copied, so the many threads
/// that shade one textured material contend on no reference count. A mix is returned as it
/// is: its factor map and its parts' maps are read where it is shaded (render/bsdf.hpp),
/// which copies no part.
inline const Material& textured(const Material& material, const TexCoord<float>& uv, Material& storage) {
  if (!has_maps(material) || std::holds_alternative<MixMaterial>(material)) return material;
  std::visit(
      [&](const auto& m) {
        using M = std::decay_t<decltype(m)>;
        // The parameters alone, field by field: copying m would copy its maps.
        M& out = storage.emplace<M>();
        std::array<const void*, detail::max_parameters> from{};
        std::array<const TextureMap*, detail::max_parameters> maps{};
        std::size_t n = 0;
        detail::parameters_of(m, [&](const char*, const auto& field) { from[n++] = &field; });
        n = 0;
        detail::maps_of(m, [&](const char*, const TextureMap& map) { maps[n++] = &map; });
        const auto& map_of = detail::map_of_parameter<M>();
        n = 0;
        detail::parameters_of(out, [&](const char*, auto& field) {
          using Field = std::remove_reference_t<decltype(field)>;
          field = *static_cast<const Field*>(from[n]);
          const int k = map_of[n++];
          if (k < 0 || !*maps[k]) return;
          const Vec3f t = maps[k]->at(uv);
          if constexpr (std::is_same_v<Field, Vec3f>)
            field = field * t;
          else if constexpr (std::is_same_v<Field, std::optional<Vec3f>>)
            field = field.value_or(Vec3f{1.f, 1.f, 1.f}) * t;
          else if constexpr (std::is_same_v<Field, float>)
            field = field * t.x;
        });
        const auto unit = [](auto&... v) { ((v = std::min(v, 1.f)), ...); };
        // The colour map's alpha is opacity too (OSPRay's OBJ and Principled materials).
        const auto cut_out = [&](const TextureMap& map, float& opacity) {
          if (map.alpha) opacity *= map.alpha_at(uv);
        };
        // Ranges a texel above 1 could leave; carPaint's are kept where the BSDF reads
        // them (render/bsdf_paint.hpp), as OSPRay clamps.
        if constexpr (std::is_same_v<M, ObjMaterial>) {
          cut_out(m.map_kd, out.d);
          unit(out.d);
        } else if constexpr (std::is_same_v<M, PrincipledMaterial>) {
          unit(out.metallic, out.diffuse, out.specular, out.transmission, out.roughness, out.anisotropy, out.rotation,
               out.coat, out.coat_roughness, out.sheen, out.sheen_tint, out.sheen_roughness, out.opacity);
          out.backlight = std::min(out.backlight, 2.f);
          // A mapped index stays in [1/3, 3], where OSPRay clamps every relative index (its
          // albedo tables' range), so that a texel 0 does not make it 0.
          if (m.map_ior) out.ior = std::clamp(out.ior, 1.f / 3.f, 3.f);
          if (m.map_coat_ior) out.coat_ior = std::clamp(out.coat_ior, 1.f / 3.f, 3.f);
          cut_out(m.map_base_color, out.opacity);
        } else if constexpr (std::is_same_v<M, MetalMaterial> || std::is_same_v<M, AlloyMaterial>) {
          unit(out.roughness);
        }
      },
      material);
  return storage;
}

/// The factor OSPRay's energy conservation scales kd, ks and tf by: 1 / their largest
/// per-channel sum where that exceeds 1, else 1.
inline float energy_scale(const ObjMaterial& m) {
  const Vec3f sum = m.kd + m.ks + m.tf;
  const float total = std::max({sum.x, sum.y, sum.z});
  return total > 1.f ? 1.f / total : 1.f;
}

/// `m` as every renderer shades it: OSPRay's energy conservation scales kd, ks and tf
/// down together where they add up to more than 1 in a channel (once: not where
/// `energy_conserved` says it was done).
inline ObjMaterial energy_conserving(ObjMaterial m) {
  if (m.energy_conserved) return m;
  const float scale = energy_scale(m);
  m.kd = m.kd * scale, m.ks = m.ks * scale, m.tf = m.tf * scale;
  m.energy_conserved = true;
  return m;
}

/// What the scivis and ao renderers see of any material: diffuse and specular colour,
/// shininess, opacity and transmissive filter. Of velvet, metallicPaint, carPaint, plastic and
/// mix they see what OSPRay's scivis sees of every material but obj: an opaque white diffuse
/// surface, which the geometry's colours tint (for mix measured with OSPRay 3.1's scivis and
/// ao: a mix of red and blue obj materials shows white).
inline ObjMaterial obj_view(const Material& material) {
  return std::visit(
      [](const auto& m) -> ObjMaterial {
        using M = std::decay_t<decltype(m)>;
        ObjMaterial o;
        if constexpr (std::is_same_v<M, ObjMaterial>) {
          o = energy_conserving(m);
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
        } else {
          o.kd = splat(1.f);
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
inline bool non_negative(float v) { return v >= 0.f && std::isfinite(v); }
}  // namespace detail

/// Throws an Error naming the first parameter out of its range.
inline void validate(const Material& material) {
  using detail::finite_non_negative, detail::require, detail::in_unit, detail::positive, detail::non_negative;
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
          require(non_negative(m.transmission_depth), type, "transmissionDepth", "must be finite and not negative");
          require(in_unit(m.roughness), type, "roughness", "must be in [0, 1]");
          require(in_unit(m.anisotropy), type, "anisotropy", "must be in [0, 1]");
          require(in_unit(m.rotation), type, "rotation", "must be in [0, 1]");
          require(positive(m.thickness), type, "thickness", "must be positive");
          require(m.backlight >= 0.f && m.backlight <= 2.f, type, "backlight", "must be in [0, 2]");
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
          require(std::isfinite(m.normal), type, "normal", "must be finite");
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
        } else if constexpr (std::is_same_v<M, VelvetMaterial>) {
          require(finite_non_negative(m.reflectance), type, "reflectance", "must be finite and not negative");
          require(non_negative(m.back_scattering), type, "backScattering", "must be finite and not negative");
          require(finite_non_negative(m.horizon_scattering_color), type, "horizonScatteringColor",
                  "must be finite and not negative");
          require(non_negative(m.horizon_scattering_fall_off), type, "horizonScatteringFallOff",
                  "must be finite and not negative");
        } else if constexpr (std::is_same_v<M, MetallicPaintMaterial>) {
          require(finite_non_negative(m.base_color), type, "baseColor", "must be finite and not negative");
          require(in_unit(m.flake_amount), type, "flakeAmount", "must be in [0, 1]");
          require(finite_non_negative(m.flake_color), type, "flakeColor", "must be finite and not negative");
          require(non_negative(m.flake_spread), type, "flakeSpread", "must be finite and not negative");
          require(positive(m.eta), type, "eta", "must be positive");
        } else if constexpr (std::is_same_v<M, CarPaintMaterial>) {
          require(finite_non_negative(m.base_color), type, "baseColor", "must be finite and not negative");
          require(non_negative(m.roughness), type, "roughness", "must be finite and not negative");
          require(std::isfinite(m.normal), type, "normal", "must be finite");
          require(!m.flake_color || finite_non_negative(*m.flake_color), type, "flakeColor",
                  "must be finite and not negative");
          require(non_negative(m.flake_scale), type, "flakeScale", "must be finite and not negative");
          require(in_unit(m.flake_density), type, "flakeDensity", "must be in [0, 1]");
          require(non_negative(m.flake_spread), type, "flakeSpread", "must be finite and not negative");
          require(in_unit(m.flake_jitter), type, "flakeJitter", "must be in [0, 1]");
          require(non_negative(m.flake_roughness), type, "flakeRoughness", "must be finite and not negative");
          require(in_unit(m.coat), type, "coat", "must be in [0, 1]");
          require(positive(m.coat_ior), type, "coatIor", "must be positive");
          require(finite_non_negative(m.coat_color), type, "coatColor", "must be finite and not negative");
          require(non_negative(m.coat_thickness), type, "coatThickness", "must be finite and not negative");
          require(non_negative(m.coat_roughness), type, "coatRoughness", "must be finite and not negative");
          require(std::isfinite(m.coat_normal), type, "coatNormal", "must be finite");
          require(finite_non_negative(m.flipflop_color), type, "flipflopColor", "must be finite and not negative");
          require(in_unit(m.flipflop_falloff), type, "flipflopFalloff", "must be in [0, 1]");
        } else if constexpr (std::is_same_v<M, PlasticMaterial>) {
          require(finite_non_negative(m.pigment_color), type, "pigmentColor", "must be finite and not negative");
          require(positive(m.eta), type, "eta", "must be positive");
          require(non_negative(m.roughness), type, "roughness", "must be finite and not negative");
        } else if constexpr (std::is_same_v<M, MixMaterial>) {
          require(in_unit(m.factor), type, "factor", "must be in [0, 1]");
          const auto part = [&](const std::shared_ptr<const MixPart>& p, const char* name) {
            require(p != nullptr, type, name, "(the material it mixes) is missing");
            try {
              validate(p->material);
            } catch (const Error& e) {
              throw Error(type + " material: parameter '" + name + "': " + e.what());
            }
          };
          part(m.material1, "material1"), part(m.material2, "material2");
        }
        detail::maps_of(m, [&](const char* name, const TextureMap& map) {
          require(map.transform.finite(), type, name, "has a transform that is not finite");
        });
        if (const NormalMap* normals = detail::normal_map_of(m))
          require(normals->map.transform.finite(), type, type == "obj" ? "map_bump" : "map_normal",
                  "has a transform that is not finite");
        if (const NormalMap* normals = detail::coat_normal_map_of(m))
          require(normals->map.transform.finite(), type, "map_coatNormal", "has a transform that is not finite");
      },
      material);
}

}  // namespace sciray
