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

void Material::on_commit() {
  // The factory creates only types the engine has.
  sciray::Material material = *material_of_type(subtype());
  if (subtype() == "metal" && find("ior"))
    throw Error(name() + ": parameter 'ior' (a spectral array) is not supported; pass RGB 'eta' and 'k'");
  for_each_parameter(material, [&](const char* id, auto& field) { read_into(id, field); });
  try {
    validate(material);
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
  // Maps: texture2d images for every map of the type; a volume texture as obj map_kd only
  // (it colours planes: slices). Each map's transform as OSPRay names it.
  Ref<TextureObject> volume_map_kd;
  std::vector<ImageMap> image_maps;
  for_each_map(material, [&](const char* id, TextureMap&) {
    const std::string map = id;
    Ref<TextureObject> texture = get_object<TextureObject>(map, OSP_TEXTURE, false);
    if (!texture) return;
    if (!texture->committed()) throw Error(name() + ": parameter '" + map + "': its texture has not been committed");
    if (texture->is_volume_texture()) {
      if (map != "map_kd")
        throw Error(name() + ": parameter '" + map + "': a volume texture colours only an obj material's map_kd; "
                             "give a texture2d");
      volume_map_kd = std::move(texture);
      return;
    }
    const auto vec2 = [&](const std::string& key, TexCoord<float> fallback) {
      const Param* p = find(key);
      if (!p) return fallback;
      if (p->type != OSP_VEC2F) throw Error(name() + ": parameter '" + key + "' must be a vec2f, got " + type_name(p->type));
      TexCoord<float> v;
      std::memcpy(&v, p->bytes.data(), sizeof v);
      return v;
    };
    TexCoordTransform transform;
    if (const Param* p = find(map + ".transform")) {
      if (p->type == OSP_AFFINE2F) {
        std::memcpy(&transform, p->bytes.data(), sizeof transform);  // vx, vy, p: as OSPRay's affine2f
      } else if (p->type == OSP_LINEAR2F) {  // vx, vy: no translation
        std::memcpy(&transform.vx, p->bytes.data(), sizeof transform.vx);
        std::memcpy(&transform.vy, p->bytes.data() + sizeof transform.vx, sizeof transform.vy);
      } else {
        throw Error(name() + ": parameter '" + map + ".transform' must be an affine2f or a linear2f, got " +
                    type_name(p->type));
      }
    } else if (has(map + ".rotation") || has(map + ".scale") || has(map + ".translation")) {
      const TexCoord<float> scale = vec2(map + ".scale", {1.f, 1.f});
      if (!(scale.u != 0.f && scale.v != 0.f))
        throw Error(name() + ": parameter '" + map + ".scale' must not be zero");
      transform = TexCoordTransform::of_texture(get_float(map + ".rotation", 0.f), scale,
                                                vec2(map + ".translation", {0.f, 0.f}));
    }
    if (!transform.finite()) throw Error(name() + ": parameter '" + map + "': its transform is not finite");
    image_maps.push_back({map, std::move(texture), transform});
  });
  material_ = std::move(material);
  volume_map_kd_ = std::move(volume_map_kd);
  image_maps_ = std::move(image_maps);
}

sciray::Material Material::material() const {
  sciray::Material m = material_;
  for_each_map(m, [&](const char* id, TextureMap& map) {
    for (const ImageMap& image : image_maps_)
      if (image.name == id) map = {image.texture->image(), image.transform};
  });
  return m;
}

std::optional<Vec3f> Material::base_color() const {
  if (const auto* obj = std::get_if<ObjMaterial>(&material_)) return obj->kd;
  if (const auto* principled = std::get_if<PrincipledMaterial>(&material_)) return principled->base_color;
  return std::nullopt;
}

sciray::Material Material::with_base_color(const Vec3f& color) const {
  sciray::Material m = material();
  if (auto* obj = std::get_if<ObjMaterial>(&m)) obj->kd = color;
  if (auto* principled = std::get_if<PrincipledMaterial>(&m)) principled->base_color = color;
  return m;
}

std::uint64_t Material::version() const {
  std::uint64_t v = std::max(version_, volume_map_kd_ ? volume_map_kd_->version() : 0);
  for (const ImageMap& image : image_maps_) v = std::max(v, image.texture->version());
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
  // sciray's textures are RGB: one- and two-channel texels (R, L, RA, LA) give grey from
  // their first channel, and alpha is not read.
  std::vector<Vec3f> texels = data->to_vector<Vec3f>([&](const std::byte* e) {
    float c[3];
    for (int k = 0; k < 3; ++k) {
      const float v = read_channel(e, layout->channel, layout->channels <= 2 ? 0 : k);
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
    auto image = std::make_shared<Texture2D>(static_cast<int>(data->counts()[0]), static_cast<int>(data->counts()[1]),
                                             std::move(texels), nearest);
    image->set_wrap(static_cast<TextureWrap>(wrap[0]), static_cast<TextureWrap>(wrap[1]));
    image_ = std::move(image);
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
