// OSPRay's materials and textures (texture2d, volume).
#include "scene_common.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace sciray::ospray {

/// A map's `.translation`, `.scale`, `.rotation` (degrees) and `.transform` as OSPRay 3
/// composes them into one transform of texture coordinates: the texture moves by the
/// translation, grows by the scale and turns counterclockwise by the rotation about its
/// centre (0.5, 0.5), and the transform (a linear2f, or an affine2f) applies first.
TexCoordTransform Material::map_transform(const std::string& map) const {
  const auto vec2 = [&](const Param& p, const std::string& key) {
    if (p.type != OSP_VEC2F)
      throw Error(name() + ": parameter '" + key + "' must be a vec2f, got " + type_name(p.type));
    TexCoord<float> v;
    std::memcpy(&v, p.bytes.data(), sizeof v);
    return v;
  };
  TexCoord<float> scale{1.f, 1.f}, translation{0.f, 0.f};
  if (const Param* p = find(map + ".scale")) scale = vec2(*p, map + ".scale");
  if (!(scale.u != 0.f && scale.v != 0.f)) throw Error(name() + ": parameter '" + map + ".scale' must not be zero");
  if (const Param* p = find(map + ".translation")) translation = vec2(*p, map + ".translation");
  TexCoordTransform transform =
      TexCoordTransform::of_texture(get_float(map + ".rotation", 0.f), scale, translation);
  if (const Param* p = find(map + ".transform")) {
    TexCoordTransform given;
    if (p->type == OSP_AFFINE2F) {
      std::memcpy(&given, p->bytes.data(), sizeof given);  // vx, vy, p: as OSPRay's affine2f
    } else if (p->type == OSP_LINEAR2F || p->type == OSP_VEC4F) {  // vx, vy (vec4f: OSPRay's legacy form)
      std::memcpy(&given.vx, p->bytes.data(), sizeof given.vx);
      std::memcpy(&given.vy, p->bytes.data() + sizeof given.vx, sizeof given.vy);
    } else {
      throw Error(name() + ": parameter '" + map + ".transform' must be a linear2f or an affine2f (an " +
                  "affine3f transforms volume textures only), got " + type_name(p->type));
    }
    transform = transform * given;
  }
  if (!transform.finite()) throw Error(name() + ": parameter '" + map + "': its transform is not finite");
  return transform;
}

Ref<Material> Material::mix_part(const std::string& id) const {
  // (A mix cannot contain itself: set_param refuses every cycle of references.)
  Ref<Material> part(get_object<Material>(id, OSP_MATERIAL, true));
  if (!part->committed()) throw Error(name() + ": parameter '" + id + "': its material has not been committed");
  return part;
}

void Material::on_commit() {
  // The factory creates only types the engine has.
  sciray::Material material = *material_of_type(subtype());
  if (subtype() == "metal" && find("ior"))
    throw Error(name() + ": parameter 'ior' (a spectral array) is not supported; pass RGB 'eta' and 'k'");
  for_each_parameter(material, [&](const char* id, auto& field) { read_into(id, field); });
  Ref<Material> material1, material2;
  if (auto* mix = std::get_if<MixMaterial>(&material)) {
    material1 = mix_part("material1"), material2 = mix_part("material2");
    mix->material1 = sciray::mix_part(material1->material());
    mix->material2 = sciray::mix_part(material2->material());
  }
  try {
    validate(material);
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
  // Maps: texture2d images for every map of the type; a volume texture as obj map_kd only
  // (it colours planes: slices). Each map's transform as OSPRay names it. As in OSPRay, a
  // parameter with a map defaults to 1 (the map alone) rather than its own default.
  Ref<TextureObject> volume_map_kd;
  Affine3f volume_transform;
  std::vector<ImageMap> image_maps;
  const auto texture_of = [&](const std::string& map) {
    Ref<TextureObject> texture = get_object<TextureObject>(map, OSP_TEXTURE, false);
    if (texture && !texture->committed())
      throw Error(name() + ": parameter '" + map + "': its texture has not been committed");
    return texture;
  };
  for_each_map(material, [&](const char* id, TextureMap&) {
    const std::string map = id;
    Ref<TextureObject> texture = texture_of(map);
    if (!texture) return;
    const std::string parameter = map.substr(4);  // map_kd: kd
    if (!has(parameter))
      for_each_parameter(material, [&](const char* p, auto& field) {
        using Field = std::remove_reference_t<decltype(field)>;
        if constexpr (std::is_same_v<Field, Vec3f> || std::is_same_v<Field, std::optional<Vec3f>>) {
          if (p == parameter) field = splat(1.f);
        } else if constexpr (std::is_same_v<Field, float>) {
          if (p == parameter) field = 1.f;
        }
      });
    if (texture->is_volume_texture()) {
      if (map != "map_kd")
        throw Error(name() + ": parameter '" + map + "': a volume texture colours only an obj material's map_kd; "
                             "give a texture2d");
      volume_transform = this->volume_transform(map);
      volume_map_kd = std::move(texture);
      return;
    }
    image_maps.push_back({map, std::move(texture), map_transform(map)});
  });
  // Normal maps read the texels raw (OSPRay ignores sRGB for normals); formats of one or two
  // channels leave the normal as it is, as OSPRay's.
  for_each_normal_map(material, [&](const char* id, NormalMap&) {
    const std::string map = id;
    Ref<TextureObject> texture = texture_of(map);
    if (!texture) return;
    if (texture->is_volume_texture())
      throw Error(name() + ": parameter '" + map + "' must be a texture2d (a normal map), got a volume texture");
    const TexCoordTransform transform = map_transform(map);
    if (texture->normal_image()) image_maps.push_back({map, std::move(texture), transform});
  });
  material_ = std::move(material);
  material1_ = std::move(material1), material2_ = std::move(material2);
  volume_map_kd_ = std::move(volume_map_kd);
  volume_map_transform_ = volume_transform;
  image_maps_ = std::move(image_maps);
}

Affine3f Material::volume_transform(const std::string& map) const {
  const Param* p = find(map + ".transform");
  if (!p) return Affine3f{};
  if (p->type != OSP_AFFINE3F)
    throw Error(name() + ": parameter '" + map + ".transform' of a volume texture must be an affine3f, got " +
                type_name(p->type));
  if (has(map + ".rotation") || has(map + ".scale") || has(map + ".translation"))
    throw Error(name() + ": parameters '" + map + ".rotation', '.scale' and '.translation' transform texture2d "
                         "coordinates; a volume texture takes an affine3f '" + map + ".transform'");
  Affine3f transform;
  std::memcpy(&transform, p->bytes.data(), sizeof transform);
  const auto finite = [](const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(transform.vx) || !finite(transform.vy) || !finite(transform.vz) || !finite(transform.p)) throw Error(name() + ": parameter '" + map + ".transform' is not finite");
  return transform;
}

sciray::Material Material::material() const {
  sciray::Material m = material_;
  // Only obj and principled have an opacity that their colour map's alpha scales.
  const bool has_opacity = std::holds_alternative<ObjMaterial>(m) || std::holds_alternative<PrincipledMaterial>(m);
  for_each_map(m, [&](const char* id, TextureMap& map) {
    for (const ImageMap& image : image_maps_)
      if (image.name == id) {
        const bool alpha_is_opacity = has_opacity && (image.name == "map_kd" || image.name == "map_baseColor");
        map = {image.texture->image(), image.transform, alpha_is_opacity ? image.texture->alpha_image() : nullptr};
      }
  });
  for_each_normal_map(m, [&](const char* id, NormalMap& map) {
    for (const ImageMap& image : image_maps_)
      if (image.name == id) map = {{image.texture->normal_image(), image.transform, nullptr}};
  });
  // The parts as they are now: a part committed again changes the mix (as in OSPRay).
  if (auto* mix = std::get_if<MixMaterial>(&m)) {
    mix->material1 = sciray::mix_part(material1_->material());
    mix->material2 = sciray::mix_part(material2_->material());
  }
  return m;
}

std::optional<Vec3f> Material::base_color() const {
  if (const auto* obj = std::get_if<ObjMaterial>(&material_)) return obj->kd;
  if (const auto* principled = std::get_if<PrincipledMaterial>(&material_)) return principled->base_color;
  return std::nullopt;
}

sciray::Material Material::with_base_color(const Vec3f& color) const {
  sciray::Material m = material();
  if (auto* obj = std::get_if<ObjMaterial>(&m)) {
    // OSPRay conserves energy at the material's commit, by its own kd: judged by the
    // colour that replaces kd (white where geometries baked kd in), kd + ks would seem
    // to exceed 1 and dim the surface (by 1.2 for kd 0.8, ks 0.2).
    const float scale = energy_scale(*obj);
    obj->kd = color * scale, obj->ks = obj->ks * scale, obj->tf = obj->tf * scale;
    obj->energy_conserved = true;
  }
  if (auto* principled = std::get_if<PrincipledMaterial>(&m)) principled->base_color = color;
  return m;
}

std::uint64_t Material::version() const {
  std::uint64_t v = std::max(version_, volume_map_kd_ ? volume_map_kd_->version() : 0);
  for (const ImageMap& image : image_maps_) v = std::max(v, image.texture->version());
  for (const Material* part : {material1_.get(), material2_.get()})
    if (part) v = std::max(v, part->version());
  return v;
}

namespace {

/// An IEEE 754 binary16 value (OSPRay's half texels) as a float: exact for every half.
float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  if (exponent == 0) {  // zero or subnormal: mantissa * 2^-24
    const float magnitude = std::ldexp(static_cast<float>(mantissa), -24);
    return sign ? -magnitude : magnitude;
  }
  if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));  // inf, NaN
  return std::bit_cast<float>(sign | ((exponent + 127 - 15) << 23) | (mantissa << 13));
}

enum class Channel { unorm8, unorm16, half, float32 };

/// How a texel of an OSPTextureFormat is stored: `channels` values of one kind, in an
/// array of `type` (half formats also as OSPRay's OSP_HALF types).
struct TexelLayout {
  int format;
  const char* format_name;
  int channels;
  Channel channel;
  bool srgb;
  OSPDataType type, half_type;
};

// clang-format off
constexpr TexelLayout texel_layouts[] = {
    {OSP_TEXTURE_RGBA8, "RGBA8", 4, Channel::unorm8, false, OSP_VEC4UC, OSP_UNKNOWN},
    {OSP_TEXTURE_SRGBA, "SRGBA", 4, Channel::unorm8, true, OSP_VEC4UC, OSP_UNKNOWN},
    {OSP_TEXTURE_RGBA32F, "RGBA32F", 4, Channel::float32, false, OSP_VEC4F, OSP_UNKNOWN},
    {OSP_TEXTURE_RGB8, "RGB8", 3, Channel::unorm8, false, OSP_VEC3UC, OSP_UNKNOWN},
    {OSP_TEXTURE_SRGB, "SRGB", 3, Channel::unorm8, true, OSP_VEC3UC, OSP_UNKNOWN},
    {OSP_TEXTURE_RGB32F, "RGB32F", 3, Channel::float32, false, OSP_VEC3F, OSP_UNKNOWN},
    {OSP_TEXTURE_R8, "R8", 1, Channel::unorm8, false, OSP_UCHAR, OSP_UNKNOWN},
    {OSP_TEXTURE_R32F, "R32F", 1, Channel::float32, false, OSP_FLOAT, OSP_UNKNOWN},
    {OSP_TEXTURE_L8, "L8", 1, Channel::unorm8, true, OSP_UCHAR, OSP_UNKNOWN},
    {OSP_TEXTURE_RA8, "RA8", 2, Channel::unorm8, false, OSP_VEC2UC, OSP_UNKNOWN},
    {OSP_TEXTURE_LA8, "LA8", 2, Channel::unorm8, true, OSP_VEC2UC, OSP_UNKNOWN},
    {OSP_TEXTURE_RGBA16, "RGBA16", 4, Channel::unorm16, false, OSP_VEC4US, OSP_UNKNOWN},
    {OSP_TEXTURE_RGB16, "RGB16", 3, Channel::unorm16, false, OSP_VEC3US, OSP_UNKNOWN},
    {OSP_TEXTURE_RA16, "RA16", 2, Channel::unorm16, false, OSP_VEC2US, OSP_UNKNOWN},
    {OSP_TEXTURE_R16, "R16", 1, Channel::unorm16, false, OSP_USHORT, OSP_UNKNOWN},
    {OSP_TEXTURE_RGBA16F, "RGBA16F", 4, Channel::half, false, OSP_VEC4US, OSP_VEC4H},
    {OSP_TEXTURE_RGB16F, "RGB16F", 3, Channel::half, false, OSP_VEC3US, OSP_VEC3H},
    {OSP_TEXTURE_RA16F, "RA16F", 2, Channel::half, false, OSP_VEC2US, OSP_VEC2H},
    {OSP_TEXTURE_R16F, "R16F", 1, Channel::half, false, OSP_USHORT, OSP_HALF},
    {OSP_TEXTURE_RA32F, "RA32F", 2, Channel::float32, false, OSP_VEC2F, OSP_UNKNOWN}};
// clang-format on

float read_channel(const std::byte* texel, Channel channel, int index) {
  switch (channel) {
    case Channel::unorm8: return static_cast<float>(reinterpret_cast<const std::uint8_t*>(texel)[index]) / 255.f;
    case Channel::unorm16: {
      std::uint16_t v;
      std::memcpy(&v, texel + 2 * index, sizeof v);
      return static_cast<float>(v) / 65535.f;
    }
    case Channel::half: {
      std::uint16_t v;
      std::memcpy(&v, texel + 2 * index, sizeof v);
      return half_to_float(v);
    }
    case Channel::float32: break;
  }
  float v;
  std::memcpy(&v, texel + 4 * index, sizeof v);
  return v;
}

}  // namespace

void TextureObject::commit_texture2d() {
  const int format = get_int("format", OSP_TEXTURE_FORMAT_INVALID);
  const Param* p = find("data");
  if (!p || !p->object) throw Error(name() + ": required parameter 'data' (a 2D array of texels) is missing");
  if (p->object->kind() != OSP_DATA)
    throw Error(name() + ": parameter 'data' must be an OSPData array, got " + type_name(p->object->kind()));
  const auto* data = static_cast<const Data*>(p->object.get());
  if (data->counts()[2] != 1) throw Error(name() + ": parameter 'data' must be a 2D array");
  const TexelLayout* layout = nullptr;
  for (const TexelLayout& l : texel_layouts)
    if (l.format == format) layout = &l;
  if (!layout) {
    std::string known;
    for (const TexelLayout& l : texel_layouts)
      known += (known.empty() ? "OSP_TEXTURE_" : ", ") + std::string(l.format_name);
    throw Error(name() + ": parameter 'format' " + std::to_string(format) + " is not an OSPTextureFormat (" + known +
                ")");
  }
  if (data->element_type() != layout->type && data->element_type() != layout->half_type)
    throw Error(name() + ": parameter 'data' holds " + type_name(data->element_type()) +
                " elements but 'format' OSP_TEXTURE_" + layout->format_name + " needs " + type_name(layout->type) +
                (layout->half_type != OSP_UNKNOWN ? " or " + type_name(layout->half_type) : std::string()));
  // sciray's textures are RGB: as OSPRay's, one- and two-channel texels give red from
  // their first channel (R, RA) or grey (luminance: L, LA), and alpha is not read.
  const bool luminance = layout->format_name[0] == 'L';
  std::vector<Vec3f> texels = data->to_vector<Vec3f>([&](const std::byte* e) {
    float c[3];
    for (int k = 0; k < 3; ++k) {
      const bool first_only = layout->channels <= 2;
      const float v = first_only && k > 0 && !luminance ? 0.f : read_channel(e, layout->channel, first_only ? 0 : k);
      c[k] = layout->srgb ? srgb_to_linear(v) : v;
    }
    return Vec3f{c[0], c[1], c[2]};
  });
  const bool nearest = get_int("filter", OSP_TEXTURE_FILTER_LINEAR) == OSP_TEXTURE_FILTER_NEAREST;
  // `wrapMode`: one OSPTextureWrapMode for both axes, or a vec2ui/vec2i of one per axis.
  int wrap[2] = {OSP_TEXTURE_WRAP_REPEAT, OSP_TEXTURE_WRAP_REPEAT};
  if (const Param* w = find("wrapMode"); w && (w->type == OSP_VEC2UI || w->type == OSP_VEC2I)) {
    std::memcpy(wrap, w->bytes.data(), sizeof wrap);
  } else {
    wrap[0] = wrap[1] = get_int("wrapMode", OSP_TEXTURE_WRAP_REPEAT);
  }
  for (int m : wrap)
    if (m < static_cast<int>(OSP_TEXTURE_WRAP_REPEAT) || m > static_cast<int>(OSP_TEXTURE_WRAP_CLAMP_TO_EDGE))
      throw Error(name() + ": parameter 'wrapMode' must be OSP_TEXTURE_WRAP_REPEAT (0), _MIRRORED_REPEAT (1) or "
                           "_CLAMP_TO_EDGE (2), got " + std::to_string(m));
  try {
    const auto make = [data, nearest, wrap](std::vector<Vec3f> values) {  // by value: normal_source keeps it
      auto image = std::make_shared<Texture2D>(static_cast<int>(data->counts()[0]),
                                               static_cast<int>(data->counts()[1]), std::move(values), nearest);
      image->set_wrap(static_cast<TextureWrap>(wrap[0]), static_cast<TextureWrap>(wrap[1]));
      return image;
    };
    auto image = make(std::move(texels));
    // Derived images, made at their first use (most textures need neither, and keep no
    // second copy of their texels): as a normal map, the raw channels of formats with
    // three or four; the alpha of RA, LA and RGBA formats (linear also in sRGB ones).
    std::function<std::shared_ptr<const Texture2D>()> normal_source, alpha_source;
    if (layout->channels >= 3)
      normal_source = [data_ref = p->object, layout, make] {
        const auto* raw_data = static_cast<const Data*>(data_ref.get());
        const float scale = layout->channel == Channel::unorm8    ? 255.f / 127.f
                            : layout->channel == Channel::unorm16 ? 65535.f / 32767.f
                                                                  : 2.f;
        return make(raw_data->to_vector<Vec3f>([&](const std::byte* e) {
          // Negative channels (float formats) clamp to 0: the texture holds no negative texel.
          const auto raw = [&](int k) { return std::max(read_channel(e, layout->channel, k), 0.f); };
          return normal_map_texel({raw(0), raw(1), raw(2)}, scale);
        }));
      };
    if (layout->channels == 2 || layout->channels == 4)
      alpha_source = [data_ref = p->object, layout, make] {
        const auto* raw_data = static_cast<const Data*>(data_ref.get());
        return make(raw_data->to_vector<Vec3f>([&](const std::byte* e) {
          return splat(std::max(read_channel(e, layout->channel, layout->channels - 1), 0.f));
        }));
      };
    image_ = std::move(image);
    normal_image_.reset(std::move(normal_source));
    alpha_image_.reset(std::move(alpha_source));
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
}


void TextureObject::on_commit() {
  if (subtype() == "texture2d") return commit_texture2d();
  const Param* p = find("volume");
  if (!p || !p->object)
    throw Error(name() + ": required parameter 'volume' (OSPVolume, with 'transferFunction') is missing");
  // Read into locals: a commit that fails leaves the texture as it was.
  Ref<VolumetricModelObject> model;
  Ref<VolumeObject> volume;
  Ref<TransferFunctionObject> tf;
  if (p->object->kind() == OSP_VOLUME) {
    volume = static_cast<VolumeObject*>(p->object.get());
    if (!volume->committed()) throw Error(name() + ": its volume has not been committed");
    tf = get_object<TransferFunctionObject>("transferFunction", OSP_TRANSFER_FUNCTION, true);
    if (!tf->committed()) throw Error(name() + ": its transfer function has not been committed");
  } else if (p->object->kind() == OSP_VOLUMETRIC_MODEL) {
    model = static_cast<VolumetricModelObject*>(p->object.get());
    if (!model->committed()) throw Error(name() + ": its volumetric model has not been committed");
    if (has("transferFunction"))
      throw Error(name() + ": parameter 'transferFunction' is for an OSPVolume 'volume'; a volumetric model "
                           "brings its own");
  } else {
    throw Error(name() + ": parameter 'volume' must be OSPVolume (OSPRay 3, with 'transferFunction') or "
                         "OSPVolumetricModel (OSPRay 2), got " + type_name(p->object->kind()));
  }
  model_ = std::move(model);
  volume_ = std::move(volume);
  transfer_function_ = std::move(tf);
}

std::uint64_t TextureObject::version() const {
  std::uint64_t v = version_;
  if (model_) v = std::max(v, model_->version());
  if (volume_) v = std::max(v, volume_->version());
  if (transfer_function_) v = std::max(v, transfer_function_->version());
  return v;
}

}  // namespace sciray::ospray
