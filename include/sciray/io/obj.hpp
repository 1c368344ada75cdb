#pragma once
// Wavefront OBJ scenes: an .obj with its .mtl material libraries, parsed and triangulated by
// tinyobjloader (Debian's build is a shared library: link tinyobjloader::tinyobjloader, or
// -ltinyobjloader; its real_t is float unless TINYOBJLOADER_USE_DOUBLE, which needs
// tinyobjloader_double). The scene is one MeshData per (group or object, material) pair, so
// each goes to Group::add with its one material and emissive or cut-out faces stay in
// geometries of their own. OBJ indexes positions, normals and texture coordinates
// separately; each distinct (v, vt, vn) triple becomes one vertex.
//
// tinyobjloader reads a malformed number ("nan", "1.5e") as 0, a short line with defaults
// and a bad face with a warning after the fact, so the text is first checked line by line
// (numbers, face sizes, indices; no data is kept) and every error names the file and line.
// Missing .mtl files, unknown usemtl names and missing textures are errors too; what is
// read but not rendered (lines, points, maps sciray has no slot for) goes to warnings.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/mesh_data.hpp"
#include "sciray/io/image.hpp"
#include "sciray/math/color.hpp"
#include "sciray/render/material.hpp"

namespace sciray::io {

/// Which sciray material an .mtl material becomes.
enum class ObjMaterialModel {
  automatic,  ///< principled where Ke or the PBR extension (Pr, Pm, Ps, Pc, Pcr, aniso, anisor, norm...) is used
  obj,
  principled
};

struct ObjOptions {
  ObjMaterialModel materials = ObjMaterialModel::automatic;
};

/// The triangles of one group or object ('g'/'o') that share one material (and have, or lack,
/// normals and texcoords alike: faces with and without them go to separate meshes).
struct ObjMesh {
  std::string name;                      ///< the group or object name; empty before the first g/o
  MeshData mesh;                         ///< triangles, with normals, texcoords, vertex_colors where the file has them
  std::uint32_t material = no_material;  ///< index into ObjScene::materials; no_material without usemtl
};

struct ObjScene {
  std::vector<ObjMesh> meshes;
  std::vector<Material> materials;          ///< those the meshes use, in order of first use
  std::vector<std::string> material_names;  ///< the .mtl name of each material
  std::vector<std::string> warnings;        ///< what was read but is not rendered
};

namespace obj_detail {

template <class... T>
std::string cat(const T&... parts) {
  std::string s;
  ((s += parts), ...);
  return s;
}

inline std::string quote(std::string_view s) {
  return cat("'", s, "'");
}

/// The next word of `rest` (empty at its end), words being separated by blanks.
inline std::string_view next_word(std::string_view& rest) {
  const auto is_blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  std::size_t b = 0;
  while (b < rest.size() && is_blank(rest[b])) ++b;
  std::size_t e = b;
  while (e < rest.size() && !is_blank(rest[e])) ++e;
  const std::string_view word = rest.substr(b, e - b);
  rest.remove_prefix(e);
  return word;
}

/// A statement of the .obj that the reader acts on later, with its line.
struct Statement {
  std::size_t line;
  std::string text;  ///< the rest of the line
};

struct Checked {
  std::vector<Statement> mtllibs, usemtls;
  std::size_t polygon_triangles = 0;  ///< sum of (vertices - 2) over faces: what triangulation must give
  std::size_t lines_and_points = 0;
};

/// Checks every v, vt, vn and f line; keeps mtllib and usemtl lines.
inline Checked check_text(std::string_view text, const std::string& file) {
  Checked out;
  std::int64_t count[3] = {0, 0, 0};  // v, vt, vn so far (the order of a face's fields)
  std::int64_t max_index[3] = {0, 0, 0};
  std::size_t max_line[3] = {0, 0, 0};
  static constexpr const char* kind_name[3] = {"v", "vt", "vn"};
  std::size_t line_number = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t newline = std::min(text.find('\n', pos), text.size());
    std::string_view rest = text.substr(pos, newline - pos);
    pos = newline + 1, ++line_number;
    const std::string_view keyword = next_word(rest);
    const auto fail = [&](const std::string& what) {
      throw Error(cat(file, ": line ", std::to_string(line_number), ": ", what));
    };
    const auto numbers = [&](int required, int kind) {
      for (int k = 0; k < required; ++k) {
        std::string_view word = next_word(rest);
        if (word.empty())
          fail(cat(kind_name[kind], " has ", std::to_string(k), " values; it needs ", std::to_string(required),
                   " (is the file truncated?)"));
        if (word.front() == '+') word.remove_prefix(1);
        double value = 0;
        const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
        if (ec == std::errc::invalid_argument || end != word.data() + word.size())
          fail(cat(kind_name[kind], " value ", quote(word), " is not a number"));
        if (ec != std::errc() || !std::isfinite(static_cast<float>(value)))
          fail(cat(kind_name[kind], " value ", quote(word), " is not finite"));
      }
      ++count[kind];
    };
    if (keyword == "v") {
      numbers(3, 0);
    } else if (keyword == "vt") {
      numbers(1, 1);
    } else if (keyword == "vn") {
      numbers(3, 2);
    } else if (keyword == "f") {
      std::size_t n = 0;
      for (std::string_view word = next_word(rest); !word.empty(); word = next_word(rest), ++n) {
        // v, v/vt, v//vn or v/vt/vn
        std::string_view part[3];
        int parts = 0;
        for (std::string_view field = word;;) {
          if (parts == 3) fail(cat("f vertex ", quote(word), " has more than 3 indices"));
          const std::size_t slash = field.find('/');
          part[parts++] = field.substr(0, slash);
          if (slash == std::string_view::npos) break;
          field.remove_prefix(slash + 1);
        }
        for (int kind = 0; kind < parts; ++kind) {
          if (part[kind].empty() && kind == 1 && parts == 3) continue;
          if (part[kind].empty()) fail(cat("f vertex ", quote(word), " has an empty index"));
          std::int64_t index = 0;
          const std::string_view digits = part[kind];
          const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
          if (ec != std::errc() || end != digits.data() + digits.size() || index == 0)
            fail(cat("f vertex ", quote(word), ": ", quote(digits), " is not an index (they start at 1)"));
          if (index < 0 && count[kind] + index < 0)
            fail(cat("f vertex ", quote(word), ": relative index ", std::to_string(index), " reaches before the first ",
                     kind_name[kind], " (there are ", std::to_string(count[kind]), " so far)"));
          if (index > max_index[kind]) max_index[kind] = index, max_line[kind] = line_number;
        }
      }
      if (n < 3) fail(cat("face has ", std::to_string(n), " vertices; a face needs at least 3"));
      out.polygon_triangles += n - 2;
    } else if (keyword == "mtllib" || keyword == "usemtl") {
      (keyword == "mtllib" ? out.mtllibs : out.usemtls).push_back({line_number, std::string(next_word(rest))});
      if (keyword == "mtllib")
        for (std::string_view more = next_word(rest); !more.empty(); more = next_word(rest))
          out.mtllibs.push_back({line_number, std::string(more)});
    } else if (keyword == "l" || keyword == "p") {
      ++out.lines_and_points;
    }
  }
  for (int kind = 0; kind < 3; ++kind)
    if (max_index[kind] > count[kind])
      throw Error(cat(file, ": line ", std::to_string(max_line[kind]), ": f refers to ", kind_name[kind], " ",
                      std::to_string(max_index[kind]), " but the file has ", std::to_string(count[kind])));
  if (out.polygon_triangles == 0) throw Error(cat(file, ": no faces (f lines): nothing to render"));
  return out;
}

/// Whether `path` is a regular file: false, not a filesystem_error, where it cannot even be
/// looked up (a name too long for the file system, as an .obj or .mtl may write).
inline bool is_file(const std::filesystem::path& path) {
  std::error_code error;
  return std::filesystem::is_regular_file(path, error);
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in || !is_file(path)) throw Error(cat(path.string(), ": cannot open the file"));
  std::string text(static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0)), '\0');
  in.seekg(0);
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size())))
    throw Error(cat(path.string(), ": cannot read the file"));
  return text;
}

/// `name` in `folder`, its backslashes read as slashes where the name as written is not there
/// (files written on Windows).
inline std::filesystem::path resolve(const std::filesystem::path& folder, std::string name) {
  if (std::error_code error; !std::filesystem::exists(folder / name, error))
    std::replace(name.begin(), name.end(), '\\', '/');
  return folder / name;
}

/// An istream over text already in memory, so tinyobjloader reads no file twice.
struct TextBuffer : std::streambuf {
  explicit TextBuffer(std::string& text) { setg(text.data(), text.data(), text.data() + text.size()); }
};

/// Loads the .mtl files an .obj names, from the .obj's folder; records which loaded and which are missing.
class MtlReader : public tinyobj::MaterialReader {
public:
  struct Library {
    std::filesystem::path path;
    std::string text;
    std::size_t line;        ///< of its mtllib statement (0: not found)
    std::size_t first, end;  ///< its materials' range in tinyobjloader's list
  };
  struct Missing {
    std::size_t line;
    std::string name, path;  ///< as written, as looked for
  };
  MtlReader(std::filesystem::path folder, const std::vector<Statement>& mtllibs)
      : folder_(std::move(folder)), mtllibs_(mtllibs) {}
  /// The mtllib statement tinyobjloader read as `name` (it takes '\\' as an escape), or null.
  const Statement* statement(const std::string& name) const {
    for (const Statement& s : mtllibs_) {
      std::string unescaped;
      for (std::size_t i = 0; i < s.text.size(); ++i)
        if (s.text[i] != '\\' || ++i < s.text.size()) unescaped += s.text[i];
      if (s.text == name || unescaped == name) return &s;
    }
    return nullptr;
  }
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* names, std::string*, std::string* err) override {
    const Statement* written = statement(name);
    const std::size_t line = written ? written->line : 0;
    const std::filesystem::path path = resolve(folder_, written ? written->text : name);
    if (!is_file(path)) {
      missing.push_back({line, written ? written->text : name, path.string()});
      return false;
    }
    Library library{path, read_text(path), line, materials->size(), 0};
    std::istringstream stream(library.text);
    std::string mtl_warnings;
    tinyobj::LoadMtl(names, materials, &stream, &mtl_warnings, err);
    std::istringstream lines(mtl_warnings);
    for (std::string line; std::getline(lines, line);)
      if (!line.empty()) warnings.push_back(cat(path.string(), ": ", line));
    library.end = materials->size();
    libraries.push_back(std::move(library));
    return true;
  }
  std::vector<Library> libraries;
  std::vector<Missing> missing;
  std::vector<std::string> warnings;

private:
  std::filesystem::path folder_;
  const std::vector<Statement>& mtllibs_;
};

/// Loads image files as textures, each (file, use) once.
class TextureLoader {
public:
  /// What a map reads of an image: colour; its first channel; its alpha, else its first
  /// channel (map_d); only its alpha, else no texture (map_Kd's cut-out); a normal (3+ channels, else none).
  enum class Use { color, scalar, alpha, alpha_only, normal };

  /// `what` names the map for errors ("<mtl>: line 7: material 'm', map_Kd 'x.png'").
  std::shared_ptr<const Texture2D> load(const std::filesystem::path& path, Use use, bool srgb, bool clamp,
                                        const std::string& what) {
    const std::string key = cat(path.string(), "|", std::to_string(int(use)), srgb ? "s" : "", clamp ? "c" : "");
    if (const auto found = cache_.find(key); found != cache_.end()) return found->second;
    if (!is_file(path)) throw Error(cat(what, ": cannot open ", path.string()));
    try {
      // read_image takes .png and .pfm; stb behind read_png decodes .jpg, .tga and .bmp too.
      const bool known = path.extension() == ".png" || path.extension() == ".pfm";
      const Image image = known ? read_image(path) : read_png(path);
      bool has_alpha = image.channels == 2 || image.channels == 4;
      if (use == Use::alpha_only && has_alpha) {  // an opaque alpha would only cost shadow-ray work
        has_alpha = false;
        for (std::size_t i = image.pixels.size(); i > 0 && !has_alpha; i -= std::size_t(image.channels))
          has_alpha = image.pixels[i - 1] < 1.f;
      }
      if ((use == Use::normal && image.channels < 3) || (use == Use::alpha_only && !has_alpha))
        return cache_[key] = nullptr;
      // 8-bit channels encode a normal as v * 255/127 - 1, floats as 2v - 1 (normal_map_texel).
      const float normal_scale = path.extension() == ".pfm" ? 2.f : 255.f / 127.f;
      std::vector<Vec3f> texels(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
          const int row = image.height - 1 - y;  // an image's row 0 is its top, a texture's its bottom (v = 0)
          const auto channel = [&](int c) { return image.at(x, row, std::min(c, image.channels - 1)); };
          const int g = image.channels < 3 ? 0 : 1;  // grey (and alpha) or colour
          const Vec3f raw{channel(0), channel(g), channel(2 * g)};
          Vec3f& t = texels[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + x];
          if (use == Use::color)
            t = srgb ? Vec3f{srgb_to_linear(raw.x), srgb_to_linear(raw.y), srgb_to_linear(raw.z)} : raw;
          else if (use == Use::normal)
            t = normal_map_texel(raw, normal_scale);
          else
            t = splat(use == Use::scalar || !has_alpha ? raw.x : channel(image.channels - 1));
        }
      auto texture = std::make_shared<Texture2D>(image.width, image.height, std::move(texels));
      if (clamp) texture->set_wrap(TextureWrap::clamp_to_edge, TextureWrap::clamp_to_edge);
      return cache_[key] = std::move(texture);
    } catch (const Error& e) {
      throw Error(cat(what, ": ", e.what()));
    }
  }

private:
  std::map<std::string, std::shared_ptr<const Texture2D>> cache_;
};

/// The line of `library` where material `material` names `file`, for messages.
inline std::string line_of(const std::string& text, const std::string& material, const std::string& file) {
  std::size_t at = text.find(cat("newmtl ", material));
  at = text.find(file, at == std::string::npos ? 0 : at);
  if (at == std::string::npos) return "";
  return cat(": line ",
             std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n')));
}

inline Vec3f vec(const tinyobj::real_t* v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

/// An .mtl material as a sciray one, its maps loaded relative to the library's folder.
///   obj:        Kd kd, Ks ks, Ns ns, d (or 1 - Tr) d, map_Kd map_kd (its alpha cuts out), map_Ks
///               map_ks, map_Ns map_ns, map_d map_d, norm (else map_Bump/bump) map_bump.
///   principled: Kd baseColor, Ke emissiveColor, Pm metallic, Pr roughness, Ps sheen, Pc coat,
///               Pcr coatRoughness, aniso anisotropy, anisor rotation, d opacity, Ni ior, and
///               map_Kd/d/Pr/Pm/Ps/Ke to their maps, norm (else bump) map_normal, -bm normal.
inline Material convert(const tinyobj::material_t& m, const MtlReader::Library& library, ObjMaterialModel model,
                        TextureLoader& textures, std::vector<std::string>& warnings) {
  using Use = TextureLoader::Use;
  const std::string where = cat(library.path.string(), ": material ", quote(m.name));
  const auto map = [&](const std::string& file, const tinyobj::texture_option_t& option, const char* keyword, Use use,
                       TextureMap& out, bool alpha = false) {
    if (file.empty()) return;
    const std::string what = cat(library.path.string(), line_of(library.text, m.name, file), ": material ",
                                 quote(m.name), ", ", keyword, " ", quote(file));
    const std::filesystem::path path = resolve(library.path.parent_path(), file);
    const bool srgb = use == Use::color && option.colorspace != "linear" && path.extension() != ".pfm";
    out.texture = textures.load(path, use, srgb, option.clamp, what);
    if (alpha) out.alpha = textures.load(path, Use::alpha_only, false, option.clamp, what);
    // -s scales the texture coordinates, -o offsets them.
    const float s[2] = {static_cast<float>(option.scale[0]), static_cast<float>(option.scale[1])};
    out.transform = {{s[0], 0.f},
                     {0.f, s[1]},
                     {static_cast<float>(option.origin_offset[0]), static_cast<float>(option.origin_offset[1])}};
    if (!out.transform.finite() || s[0] == 0.f || s[1] == 0.f)
      throw Error(cat(what, ": -s or -o is zero or not finite"));
  };
  const auto ignored = [&](const std::string& file, const char* keyword, const char* why) {
    if (!file.empty()) warnings.push_back(cat(where, ": ", keyword, " ", quote(file), " is ignored: ", why));
  };
  const auto normal_map = [&](NormalMap& out, float* scale) {
    const bool norm = !m.normal_texname.empty();
    if (norm && !m.bump_texname.empty()) ignored(m.bump_texname, "bump", "norm gives the normal map");
    const std::string& file = norm ? m.normal_texname : m.bump_texname;
    const auto& option = norm ? m.normal_texopt : m.bump_texopt;
    map(file, option, norm ? "norm" : "map_Bump", Use::normal, out.map);
    if (!file.empty() && !out.map.texture)
      warnings.push_back(cat(where, ": ", norm ? "norm " : "map_Bump ", quote(file),
                             " is ignored: a normal map needs 3 channels (height maps are not supported)"));
    if (scale)
      *scale = static_cast<float>(option.bump_multiplier);
    else if (out && option.bump_multiplier != 1)
      warnings.push_back(cat(where, ": -bm is ignored: obj materials take the normal map as it is"));
  };
  const bool emits = m.emission[0] != 0 || m.emission[1] != 0 || m.emission[2] != 0;
  const bool pbr = m.roughness != 0 || m.metallic != 0 || m.sheen != 0 || m.clearcoat_thickness != 0 ||
                   m.clearcoat_roughness != 0 || m.anisotropy != 0 || m.anisotropy_rotation != 0 ||
                   !m.roughness_texname.empty() || !m.metallic_texname.empty() || !m.sheen_texname.empty() ||
                   !m.emissive_texname.empty() || !m.normal_texname.empty();
  Material result;
  if (model == ObjMaterialModel::principled || (model == ObjMaterialModel::automatic && (pbr || emits))) {
    PrincipledMaterial p;
    p.base_color = vec(m.diffuse), p.emissive_color = vec(m.emission);
    p.metallic = static_cast<float>(m.metallic), p.roughness = static_cast<float>(m.roughness);
    p.sheen = static_cast<float>(m.sheen), p.coat = static_cast<float>(m.clearcoat_thickness);
    p.coat_roughness = static_cast<float>(m.clearcoat_roughness), p.anisotropy = static_cast<float>(m.anisotropy);
    p.rotation = static_cast<float>(m.anisotropy_rotation), p.opacity = static_cast<float>(m.dissolve);
    // Ni 1 is also tinyobjloader's value where Ni is absent; a surface of index 1 does not reflect.
    p.ior = m.ior == 1 ? 1.5f : static_cast<float>(m.ior);
    map(m.diffuse_texname, m.diffuse_texopt, "map_Kd", Use::color, p.map_base_color, true);
    map(m.alpha_texname, m.alpha_texopt, "map_d", Use::alpha, p.map_opacity);
    map(m.roughness_texname, m.roughness_texopt, "map_Pr", Use::scalar, p.map_roughness);
    map(m.metallic_texname, m.metallic_texopt, "map_Pm", Use::scalar, p.map_metallic);
    map(m.sheen_texname, m.sheen_texopt, "map_Ps", Use::scalar, p.map_sheen);
    map(m.emissive_texname, m.emissive_texopt, "map_Ke", Use::color, p.map_emissive_color);
    normal_map(p.map_normal, &p.normal);
    ignored(m.specular_texname, "map_Ks", "principled materials have no specular colour");
    ignored(m.specular_highlight_texname, "map_Ns", "principled materials take roughness (Pr, map_Pr)");
    result = std::move(p);
  } else {
    ObjMaterial o;
    o.kd = vec(m.diffuse), o.ks = vec(m.specular), o.ns = static_cast<float>(m.shininess);
    o.d = static_cast<float>(m.dissolve);
    map(m.diffuse_texname, m.diffuse_texopt, "map_Kd", Use::color, o.map_kd, true);
    map(m.specular_texname, m.specular_texopt, "map_Ks", Use::color, o.map_ks);
    map(m.specular_highlight_texname, m.specular_highlight_texopt, "map_Ns", Use::scalar, o.map_ns);
    map(m.alpha_texname, m.alpha_texopt, "map_d", Use::alpha, o.map_d);
    normal_map(o.map_bump, nullptr);
    if (emits) warnings.push_back(cat(where, ": Ke is ignored: obj materials do not emit"));
    if (pbr) warnings.push_back(cat(where, ": the PBR parameters are ignored: obj materials do not have them"));
    result = std::move(o);
  }
  ignored(m.ambient_texname, "map_Ka", "there is no ambient colour");
  ignored(m.displacement_texname, "disp", "displacement is not supported");
  ignored(m.reflection_texname, "refl", "reflection maps are not supported");
  try {
    validate(result);
  } catch (const Error& e) {
    throw Error(cat(where, ": ", e.what()));
  }
  return result;
}

}  // namespace obj_detail

/// Reads an .obj file and the .mtl libraries it names (relative to its folder), their
/// textures relative to each library's folder. Throws Error naming the file and line for
/// malformed files, missing libraries, materials or textures.
inline ObjScene read_obj(const std::filesystem::path& path, const ObjOptions& options = {}) {
  using namespace obj_detail;
  const std::string file = path.string();
  std::string text = read_text(path);
  const Checked checked = check_text(text, file);

  TextBuffer buffer(text);
  std::istream stream(&buffer);
  MtlReader reader(path.parent_path(), checked.mtllibs);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, &reader, true, false);
  if (!ok || !err.empty()) throw Error(cat(file, ": ", err.empty() ? std::string("cannot parse the file") : err));
  for (const MtlReader::Missing& m : reader.missing)
    throw Error(cat(file, ": line ", std::to_string(m.line), ": mtllib ", quote(m.name), ": cannot open ", m.path));
  // usemtl only finds materials of libraries loaded on lines before it (as tinyobjloader reads).
  std::map<std::string, std::size_t> defined_on;
  for (const MtlReader::Library& library : reader.libraries)
    for (std::size_t k = library.first; k < library.end; ++k) defined_on.emplace(materials[k].name, library.line);
  for (const Statement& use : checked.usemtls) {
    const auto found = defined_on.find(use.text);
    if (found == defined_on.end() || found->second > use.line)
      throw Error(cat(file, ": line ", std::to_string(use.line), ": usemtl ", quote(use.text), ": ",
                      found != defined_on.end()
                          ? cat("its mtllib is on line ", std::to_string(found->second), ", after it")
                      : checked.mtllibs.empty() ? std::string("the file names no material library (mtllib)")
                                                : "no material of that name in the material libraries"));
  }
  ObjScene scene;
  scene.warnings = std::move(reader.warnings);
  std::istringstream warnings(warn);
  for (std::string line; std::getline(warnings, line);) {
    if (line.find("egenerate") != std::string::npos || line.find("index") != std::string::npos ||
        line.find("indices") != std::string::npos || line.find("not found") != std::string::npos)
      throw Error(cat(file, ": ", line));  // the checks above should have caught it first
    if (!line.empty()) scene.warnings.push_back(cat(file, ": ", line));
  }
  if (checked.lines_and_points)
    scene.warnings.push_back(
        cat(file, ": ", std::to_string(checked.lines_and_points), " line (l) and point (p) elements are ignored"));

  // Materials in order of first use; faces without usemtl take no_material (the engine's
  // default: the geometry's own colours, 0.8 grey where it has none).
  TextureLoader textures;
  std::vector<std::uint32_t> material_index(materials.size(), no_material);
  const auto scene_material = [&](int id) {
    if (id < 0) return no_material;
    std::uint32_t& index = material_index[static_cast<std::size_t>(id)];
    if (index != no_material) return index;
    const auto library = std::find_if(reader.libraries.begin(), reader.libraries.end(), [&](const auto& l) {
      return static_cast<std::size_t>(id) >= l.first && static_cast<std::size_t>(id) < l.end;
    });
    if (library == reader.libraries.end()) throw Error(cat(file, ": material ", std::to_string(id), " has no library"));
    scene.materials.push_back(
        convert(materials[static_cast<std::size_t>(id)], *library, options.materials, textures, scene.warnings));
    scene.material_names.push_back(materials[static_cast<std::size_t>(id)].name);
    return index = static_cast<std::uint32_t>(scene.materials.size() - 1);
  };

  // One vertex per distinct (v, vt, vn) in each mesh: the first triple met for a position
  // sits in `first`, stamped with the mesh, so no table is cleared between meshes; the rare
  // others (the same position with another normal or texcoord) go to a hash map.
  const std::size_t positions = attrib.vertices.size() / 3;
  const bool colors = attrib.colors.size() == attrib.vertices.size();
  struct First {
    std::uint32_t mesh = 0xffffffffu, vertex = 0;
    int normal = 0, texcoord = 0;
  };
  std::vector<First> first(positions);
  struct Triple {
    int v, n, t;
    bool operator==(const Triple&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Triple& k) const {
      return std::hash<std::uint64_t>()(
          (std::uint64_t(std::uint32_t(k.v)) << 32 | std::uint32_t(k.n)) * 0x9e3779b97f4a7c15u ^ std::uint32_t(k.t));
    }
  };
  std::unordered_map<Triple, std::uint32_t, Hash> others;
  const auto append = [](PaddedVector<float>& to, const std::vector<tinyobj::real_t>& from, std::size_t at, int n) {
    for (int c = 0; c < n; ++c) to.push_back(static_cast<float>(from[at + static_cast<std::size_t>(c)]));
  };
  std::size_t triangles = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    const tinyobj::mesh_t& faces = shape.mesh;
    const std::size_t count = faces.num_face_vertices.size();
    // The distinct (material, has normals, has texcoords) of the shape's triangles.
    struct Key {
      int material;
      bool normals, texcoords;
      bool operator==(const Key&) const = default;
    };
    std::vector<Key> keys;
    std::vector<std::uint32_t> key_of(count);
    for (std::size_t t = 0; t < count; ++t) {
      if (faces.num_face_vertices[t] != 3) throw Error(cat(file, ": tinyobjloader left a face untriangulated"));
      const tinyobj::index_t* v = &faces.indices[3 * t];
      const Key key{faces.material_ids[t], v[0].normal_index >= 0 && v[1].normal_index >= 0 && v[2].normal_index >= 0,
                    v[0].texcoord_index >= 0 && v[1].texcoord_index >= 0 && v[2].texcoord_index >= 0};
      const auto found = std::find(keys.begin(), keys.end(), key);
      key_of[t] = static_cast<std::uint32_t>(found - keys.begin());
      if (found == keys.end()) keys.push_back(key);
    }
    for (std::uint32_t k = 0; k < keys.size(); ++k) {
      const Key& key = keys[k];
      ObjMesh out{shape.name, {}, scene_material(key.material)};
      MeshData& mesh = out.mesh;
      const auto stamp = static_cast<std::uint32_t>(scene.meshes.size());
      if (!others.empty()) others.clear();
      std::uint32_t vertices = 0;
      const auto vertex = [&](tinyobj::index_t i) {
        const int n = key.normals ? i.normal_index : -1, t = key.texcoords ? i.texcoord_index : -1;
        if (i.vertex_index < 0 || static_cast<std::size_t>(i.vertex_index) >= positions ||
            static_cast<std::size_t>(n + 1) > attrib.normals.size() / 3 ||
            static_cast<std::size_t>(t + 1) > attrib.texcoords.size() / 2)
          throw Error(cat(file, ": tinyobjloader gave a vertex index out of range in ", quote(shape.name)));
        First& f = first[static_cast<std::size_t>(i.vertex_index)];
        if (f.mesh != stamp) {
          f = {stamp, vertices, n, t};
        } else if (f.normal == n && f.texcoord == t) {
          return f.vertex;
        } else if (const auto [it, added] = others.try_emplace({i.vertex_index, n, t}, vertices); !added) {
          return it->second;
        }
        const auto v = static_cast<std::size_t>(i.vertex_index);
        append(mesh.positions, attrib.vertices, 3 * v, 3);
        if (key.normals) append(mesh.normals, attrib.normals, 3 * static_cast<std::size_t>(n), 3);
        if (key.texcoords) append(mesh.texcoords, attrib.texcoords, 2 * static_cast<std::size_t>(t), 2);
        if (colors) append(mesh.vertex_colors, attrib.colors, 3 * v, 3), mesh.vertex_colors.push_back(1.f);
        return vertices++;
      };
      for (std::size_t t = 0; t < count; ++t)
        if (key_of[t] == k)
          for (int c = 0; c < 3; ++c)
            mesh.indices.push_back(vertex(faces.indices[3 * t + static_cast<std::size_t>(c)]));
      triangles += mesh.face_count();
      scene.meshes.push_back(std::move(out));
    }
  }
  if (triangles < checked.polygon_triangles)
    scene.warnings.push_back(cat(file, ": tinyobjloader's triangulation dropped ",
                                 std::to_string(checked.polygon_triangles - triangles),
                                 " triangles of degenerate or self-intersecting polygons"));
  return scene;
}

}  // namespace sciray::io
