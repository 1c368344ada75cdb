// OSPRay's materials and textures (texture2d, volume).
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
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
    if (texture->volume_model()) {
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
      if (p->type != OSP_AFFINE2F)
        throw Error(name() + ": parameter '" + map + ".transform' must be an affine2f, got " + type_name(p->type));
      std::memcpy(&transform, p->bytes.data(), sizeof transform);  // vx, vy, p: as OSPRay's affine2f
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

void TextureObject::commit_texture2d() {
  const int format = get_int("format", OSP_TEXTURE_FORMAT_INVALID);
  const Param* p = find("data");
  if (!p || !p->object) throw Error(name() + ": required parameter 'data' (a 2D array of texels) is missing");
  if (p->object->kind() != OSP_DATA)
    throw Error(name() + ": parameter 'data' must be an OSPData array, got " + type_name(p->object->kind()));
  const auto* data = static_cast<const Data*>(p->object.get());
  if (data->counts()[2] != 1) throw Error(name() + ": parameter 'data' must be a 2D array");
  // The layouts sciray reads; the element type must agree with the format.
  struct Layout {
    int format;
    OSPDataType type;
    const char* type_name;
    int channels;
    bool srgb;
  };
  static constexpr Layout layouts[] = {
      {OSP_TEXTURE_RGB32F, OSP_VEC3F, "OSP_VEC3F", 3, false},    {OSP_TEXTURE_RGBA32F, OSP_VEC4F, "OSP_VEC4F", 4, false},
      {OSP_TEXTURE_R32F, OSP_FLOAT, "OSP_FLOAT", 1, false},      {OSP_TEXTURE_RGB8, OSP_VEC3UC, "OSP_VEC3UC", 3, false},
      {OSP_TEXTURE_RGBA8, OSP_VEC4UC, "OSP_VEC4UC", 4, false},   {OSP_TEXTURE_SRGB, OSP_VEC3UC, "OSP_VEC3UC", 3, true},
      {OSP_TEXTURE_SRGBA, OSP_VEC4UC, "OSP_VEC4UC", 4, true},    {OSP_TEXTURE_R8, OSP_UCHAR, "OSP_UCHAR", 1, false},
      {OSP_TEXTURE_L8, OSP_UCHAR, "OSP_UCHAR", 1, true}};
  const Layout* layout = nullptr;
  for (const Layout& l : layouts)
    if (l.format == format) layout = &l;
  if (!layout)
    throw Error(name() + ": parameter 'format' " + std::to_string(format) +
                " is not supported (RGB32F, RGBA32F, R32F, RGB8, RGBA8, SRGB, SRGBA, R8 and L8 are)");
  if (data->element_type() != layout->type)
    throw Error(name() + ": parameter 'data' holds " + type_name(data->element_type()) + " elements but 'format' " +
                std::to_string(format) + " needs " + layout->type_name);
  const bool bytes = layout->type == OSP_VEC3UC || layout->type == OSP_VEC4UC || layout->type == OSP_UCHAR;
  std::vector<Vec3f> texels = data->to_vector<Vec3f>([&](const std::byte* e) {
    float c[3];
    for (int k = 0; k < 3; ++k) {
      const int channel = layout->channels == 1 ? 0 : k;
      float v = bytes ? static_cast<float>(reinterpret_cast<const std::uint8_t*>(e)[channel]) / 255.f
                      : reinterpret_cast<const float*>(e)[channel];
      c[k] = layout->srgb ? srgb_to_linear(v) : v;
    }
    return Vec3f{c[0], c[1], c[2]};
  });
  const bool nearest = get_int("filter", OSP_TEXTURE_FILTER_LINEAR) == OSP_TEXTURE_FILTER_NEAREST;
  try {
    image_ = std::make_shared<const Texture2D>(static_cast<int>(data->counts()[0]), static_cast<int>(data->counts()[1]),
                                               std::move(texels), nearest);
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
}

void TextureObject::on_commit() {
  if (subtype() == "texture2d") return commit_texture2d();
  const Param* p = find("volume");
  if (!p || !p->object) throw Error(name() + ": required parameter 'volume' (OSPVolumetricModel) is missing");
  if (p->object->kind() != OSP_VOLUMETRIC_MODEL)
    throw Error(name() + ": parameter 'volume' must be OSPVolumetricModel, got " + type_name(p->object->kind()) +
                (p->object->kind() == OSP_VOLUME
                     ? " (a volume texture takes the volumetric model, whose transfer function gives the colours)"
                     : ""));
  Ref<VolumetricModelObject> model = static_cast<VolumetricModelObject*>(p->object.get());
  if (!model->committed()) throw Error(name() + ": its volumetric model has not been committed");
  model_ = std::move(model);
}

std::uint64_t TextureObject::version() const { return std::max(version_, model_ ? model_->version() : 0); }

}  // namespace sciray::ospray
