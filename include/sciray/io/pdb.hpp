#pragma once
// PDB molecule reader (wwPDB format v3.3, fixed columns) producing atoms with van der Waals
// radii and CPK colours, and bonds from CONECT records and from interatomic distances.
// The file is parsed from memory. Only the first model is read; waters, HETATM records and
// alternate locations other than 'A' can be left out. Every error names the file and line.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"

namespace sciray::io {

struct Atom {
  Vec3f position;            ///< Å
  std::uint8_t element = 0;  ///< atomic number; 0 when the element is unknown
  float radius = 0;          ///< van der Waals radius, Å
  Vec3f color;               ///< Jmol's CPK colour, 0..1
  bool hetero = false;       ///< read from a HETATM record
  std::int32_t serial = -1;  ///< columns 7-11; -1 when they hold no number (e.g. "*****")
  std::string name;          ///< columns 13-16, trimmed
  std::string residue;       ///< columns 18-20, trimmed
  char chain = ' ';          ///< column 22
};

struct Molecule {
  std::vector<Atom> atoms;
  std::vector<std::array<std::uint32_t, 2>> bonds;  ///< atom indices, i < j, unique, sorted
};

struct PdbOptions {
  bool conect_bonds = true;      ///< bonds listed in CONECT records
  bool distance_bonds = true;    ///< bonds between atoms closer than their covalent radii allow
  float bond_tolerance = 0.45f;  ///< Å added to the sum of the covalent radii (Jmol's default)
  bool hetero = true;            ///< read HETATM records
  bool waters = false;           ///< read HOH, WAT and DOD residues
};

namespace pdb_detail {

struct ElementData {
  std::string_view symbol;
  float vdw;       ///< Å: Bondi 1964, else Alvarez 2013, else 2.0 where neither measured one
  float covalent;  ///< Å: Cordero et al. 2008 (sp3 C, low-spin Mn/Fe/Co); 0 where not given
  std::uint32_t rgb;
};

// Indexed by atomic number; row 0 describes unknown elements (Jmol's "Xx" pink).
inline constexpr ElementData elements[] = {
    {"", 1.50f, 0.00f, 0xFF1493},    {"H", 1.20f, 0.31f, 0xFFFFFF},   {"He", 1.40f, 0.28f, 0xD9FFFF},
    {"Li", 1.82f, 1.28f, 0xCC80FF},  {"Be", 1.98f, 0.96f, 0xC2FF00},  {"B", 1.91f, 0.84f, 0xFFB5B5},
    {"C", 1.70f, 0.76f, 0x909090},   {"N", 1.55f, 0.71f, 0x3050F8},   {"O", 1.52f, 0.66f, 0xFF0D0D},
    {"F", 1.47f, 0.57f, 0x90E050},   {"Ne", 1.54f, 0.58f, 0xB3E3F5},  {"Na", 2.27f, 1.66f, 0xAB5CF2},
    {"Mg", 1.73f, 1.41f, 0x8AFF00},  {"Al", 2.25f, 1.21f, 0xBFA6A6},  {"Si", 2.10f, 1.11f, 0xF0C8A0},
    {"P", 1.80f, 1.07f, 0xFF8000},   {"S", 1.80f, 1.05f, 0xFFFF30},   {"Cl", 1.75f, 1.02f, 0x1FF01F},
    {"Ar", 1.88f, 1.06f, 0x80D1E3},  {"K", 2.75f, 2.03f, 0x8F40D4},   {"Ca", 2.62f, 1.76f, 0x3DFF00},
    {"Sc", 2.58f, 1.70f, 0xE6E6E6},  {"Ti", 2.46f, 1.60f, 0xBFC2C7},  {"V", 2.42f, 1.53f, 0xA6A6AB},
    {"Cr", 2.45f, 1.39f, 0x8A99C7},  {"Mn", 2.45f, 1.39f, 0x9C7AC7},  {"Fe", 2.44f, 1.32f, 0xE06633},
    {"Co", 2.40f, 1.26f, 0xF090A0},  {"Ni", 1.63f, 1.24f, 0x50D050},  {"Cu", 1.40f, 1.32f, 0xC88033},
    {"Zn", 1.39f, 1.22f, 0x7D80B0},  {"Ga", 1.87f, 1.22f, 0xC28F8F},  {"Ge", 2.29f, 1.20f, 0x668F8F},
    {"As", 1.85f, 1.19f, 0xBD80E3},  {"Se", 1.90f, 1.20f, 0xFFA100},  {"Br", 1.85f, 1.20f, 0xA62929},
    {"Kr", 2.02f, 1.16f, 0x5CB8D1},  {"Rb", 3.21f, 2.20f, 0x702EB0},  {"Sr", 2.84f, 1.95f, 0x00FF00},
    {"Y", 2.75f, 1.90f, 0x94FFFF},   {"Zr", 2.52f, 1.75f, 0x94E0E0},  {"Nb", 2.56f, 1.64f, 0x73C2C9},
    {"Mo", 2.45f, 1.54f, 0x54B5B5},  {"Tc", 2.44f, 1.47f, 0x3B9E9E},  {"Ru", 2.46f, 1.46f, 0x248F8F},
    {"Rh", 2.44f, 1.42f, 0x0A7D8C},  {"Pd", 1.63f, 1.39f, 0x006985},  {"Ag", 1.72f, 1.45f, 0xC0C0C0},
    {"Cd", 1.58f, 1.44f, 0xFFD98F},  {"In", 1.93f, 1.42f, 0xA67573},  {"Sn", 2.17f, 1.39f, 0x668080},
    {"Sb", 2.47f, 1.39f, 0x9E63B5},  {"Te", 2.06f, 1.38f, 0xD47A00},  {"I", 1.98f, 1.39f, 0x940094},
    {"Xe", 2.16f, 1.40f, 0x429EB0},  {"Cs", 3.48f, 2.44f, 0x57178F},  {"Ba", 3.03f, 2.15f, 0x00C900},
    {"La", 2.98f, 2.07f, 0x70D4FF},  {"Ce", 2.88f, 2.04f, 0xFFFFC7},  {"Pr", 2.92f, 2.03f, 0xD9FFC7},
    {"Nd", 2.95f, 2.01f, 0xC7FFC7},  {"Pm", 2.00f, 1.99f, 0xA3FFC7},  {"Sm", 2.90f, 1.98f, 0x8FFFC7},
    {"Eu", 2.87f, 1.98f, 0x61FFC7},  {"Gd", 2.83f, 1.96f, 0x45FFC7},  {"Tb", 2.79f, 1.94f, 0x30FFC7},
    {"Dy", 2.87f, 1.92f, 0x1FFFC7},  {"Ho", 2.81f, 1.92f, 0x00FF9C},  {"Er", 2.83f, 1.89f, 0x00E675},
    {"Tm", 2.79f, 1.90f, 0x00D452},  {"Yb", 2.80f, 1.87f, 0x00BF38},  {"Lu", 2.74f, 1.87f, 0x00AB24},
    {"Hf", 2.63f, 1.75f, 0x4DC2FF},  {"Ta", 2.53f, 1.70f, 0x4DA6FF},  {"W", 2.57f, 1.62f, 0x2194D6},
    {"Re", 2.49f, 1.51f, 0x267DAB},  {"Os", 2.48f, 1.44f, 0x266696},  {"Ir", 2.41f, 1.41f, 0x175487},
    {"Pt", 1.72f, 1.36f, 0xD0D0E0},  {"Au", 1.66f, 1.36f, 0xFFD123},  {"Hg", 1.55f, 1.32f, 0xB8B8D0},
    {"Tl", 1.96f, 1.45f, 0xA6544D},  {"Pb", 2.02f, 1.46f, 0x575961},  {"Bi", 2.54f, 1.48f, 0x9E4FB5},
    {"Po", 2.00f, 1.40f, 0xAB5C00},  {"At", 2.00f, 1.50f, 0x754F45},  {"Rn", 2.00f, 1.50f, 0x428296},
    {"Fr", 2.00f, 2.60f, 0x420066},  {"Ra", 2.00f, 2.21f, 0x007D00},  {"Ac", 2.80f, 2.15f, 0x70ABFA},
    {"Th", 2.93f, 2.06f, 0x00BAFF},  {"Pa", 2.88f, 2.00f, 0x00A1FF},  {"U", 1.86f, 1.96f, 0x008FFF},
    {"Np", 2.82f, 1.90f, 0x0080FF},  {"Pu", 2.81f, 1.87f, 0x006BFF},  {"Am", 2.83f, 1.80f, 0x545CF2},
    {"Cm", 3.05f, 1.69f, 0x785CE3},  {"Bk", 3.40f, 0.00f, 0x8A4FE3},  {"Cf", 3.05f, 0.00f, 0xA136D4},
    {"Es", 2.70f, 0.00f, 0xB31FD4},  {"Fm", 2.00f, 0.00f, 0xB31FBA},  {"Md", 2.00f, 0.00f, 0xB30DA6},
    {"No", 2.00f, 0.00f, 0xBD0D87},  {"Lr", 2.00f, 0.00f, 0xC70066},  {"Rf", 2.00f, 0.00f, 0xCC0059},
    {"Db", 2.00f, 0.00f, 0xD1004F},  {"Sg", 2.00f, 0.00f, 0xD90045},  {"Bh", 2.00f, 0.00f, 0xE00038},
    {"Hs", 2.00f, 0.00f, 0xE6002E},  {"Mt", 2.00f, 0.00f, 0xEB0026},
    // Jmol's table ends at Mt: the rest take the unknown pink.
    {"Ds", 2.00f, 0.00f, 0xFF1493},  {"Rg", 2.00f, 0.00f, 0xFF1493},  {"Cn", 2.00f, 0.00f, 0xFF1493},
    {"Nh", 2.00f, 0.00f, 0xFF1493},  {"Fl", 2.00f, 0.00f, 0xFF1493},  {"Mc", 2.00f, 0.00f, 0xFF1493},
    {"Lv", 2.00f, 0.00f, 0xFF1493},  {"Ts", 2.00f, 0.00f, 0xFF1493},  {"Og", 2.00f, 0.00f, 0xFF1493}};
inline constexpr std::size_t element_count = std::size(elements);

inline const ElementData& element_data(std::uint8_t element) {
  return elements[element < element_count ? element : 0];
}

constexpr char upper(char c) { return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c; }
constexpr bool is_letter(char c) { return upper(c) >= 'A' && upper(c) <= 'Z'; }
constexpr bool is_digit(char c) { return c >= '0' && c <= '9'; }

/// Symbol -> atomic number for one- and two-letter symbols, case-blind: slot 27 * first
/// letter + (0 for none, 1 + second letter).
inline constexpr auto symbol_table = [] {
  std::array<std::uint8_t, 26 * 27> table{};
  for (std::size_t z = 1; z < element_count; ++z) {
    const std::string_view s = elements[z].symbol;
    table[27 * static_cast<std::size_t>(upper(s[0]) - 'A') +
          (s.size() == 1 ? 0 : 1 + static_cast<std::size_t>(upper(s[1]) - 'A'))] = static_cast<std::uint8_t>(z);
  }
  table[27 * ('D' - 'A')] = 1;  // deuterium, as neutron structures write it, is drawn as hydrogen
  return table;
}();

/// Atomic number of a one-letter (second == ' ') or two-letter symbol; 0 if there is none.
inline std::uint8_t lookup_symbol(char first, char second) {
  if (!is_letter(first) || (second != ' ' && !is_letter(second))) return 0;
  const auto letter = [](char c) { return static_cast<std::size_t>(upper(c) - 'A'); };
  return symbol_table[27 * letter(first) + (second == ' ' ? 0 : 1 + letter(second))];
}

inline std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

/// Columns first..last (1-based, inclusive) of a line; trailing blanks may have been
/// stripped, so the result is cut at the line's end.
inline std::string_view columns(std::string_view line, std::size_t first, std::size_t last) {
  if (line.size() < first) return {};
  return line.substr(first - 1, std::min(last, line.size()) - first + 1);
}

/// A serial number field (5 columns): decimal, or hybrid-36 as files beyond 99,999 atoms
/// write it ("A0000" is 100,000). False when the field holds neither.
inline bool parse_serial(std::string_view field, std::int32_t& value) {
  const std::string_view digits = trim(field);
  if (digits.empty()) return false;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc{} && end == digits.data() + digits.size()) return true;
  if (field.size() != 5 || !is_letter(field[0])) return false;
  const bool lower_case = field[0] >= 'a';
  std::int64_t decoded = 0;
  for (const char c : field) {
    int digit = 0;
    if (is_digit(c)) digit = c - '0';
    else if (is_letter(c) && (c >= 'a') == lower_case) digit = upper(c) - 'A' + 10;
    else return false;
    decoded = decoded * 36 + digit;
  }
  constexpr std::int64_t block = 36 * 36 * 36 * 36;  // 36^(width - 1)
  value = static_cast<std::int32_t>(decoded - 10 * block + 100000 + (lower_case ? 26 * block : 0));
  return true;
}

[[noreturn]] inline void fail(std::string_view file, std::size_t line, std::string_view message) {
  throw Error(std::string(file) + ": line " + std::to_string(line) + ": " + std::string(message));
}

inline float parse_coordinate(std::string_view line, std::size_t first, char axis, std::string_view file,
                              std::size_t line_number) {
  const std::string_view field = trim(columns(line, first, first + 7));
  float value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc{} || end != field.data() + field.size() || !std::isfinite(value))
    fail(file, line_number,
         std::string(1, axis) + " coordinate (columns " + std::to_string(first) + "-" + std::to_string(first + 7) +
             ") '" + std::string(field) + "' is not a finite number");
  return value;
}

/// The element from the atom name (columns 13-16) when columns 77-78 are blank, as in
/// files written before v3: the symbol is right-justified in columns 13-14, so a blank or
/// digit in column 13 leaves a one-letter symbol in column 14. A letter there starts a
/// two-letter symbol only in HETATM records ("CA  " calcium); standard residues hold no
/// such elements, and their 4-character hydrogen names ("HG21") start with the H.
inline std::uint8_t element_from_name(std::string_view name, bool hetero) {
  if (name.size() < 2) return 0;
  if (name[0] == ' ' || is_digit(name[0])) return lookup_symbol(name[1], ' ');
  if (hetero && name[1] != ' ') {
    const std::uint8_t two_letters = lookup_symbol(name[0], name[1]);
    if (two_letters != 0) return two_letters;
  }
  return lookup_symbol(name[0], ' ');
}

inline bool is_water(std::string_view residue) { return residue == "HOH" || residue == "WAT" || residue == "DOD"; }

/// Pairs of atoms closer than their covalent radii plus the tolerance (and farther than
/// 0.4 Å), found in a hashed uniform grid whose cells are as wide as the longest possible
/// bond, so each atom meets only the atoms of its 27 surrounding cells.
inline void add_distance_bonds(const std::vector<Atom>& atoms, float tolerance,
                               std::vector<std::array<std::uint32_t, 2>>& bonds) {
  constexpr float min_distance = 0.4f;
  std::vector<std::uint32_t> candidates;  // atoms with a covalent radius to judge by
  float max_radius = 0;
  for (std::uint32_t i = 0; i < atoms.size(); ++i) {
    const float radius = element_data(atoms[i].element).covalent;
    if (radius > 0) candidates.push_back(i);
    max_radius = std::max(max_radius, radius);
  }
  const double longest = 2.0 * max_radius + tolerance;
  if (candidates.empty() || longest <= min_distance) return;
  // 1% wider than the longest bond, so rounding never puts a bonded pair two cells apart.
  const double inverse_cell = 1.0 / (1.01 * longest);

  struct Cell {
    std::int64_t x, y, z;
    bool operator==(const Cell&) const = default;
  };
  std::size_t buckets = 1;
  while (buckets < 2 * candidates.size()) buckets *= 2;
  const auto bucket_of = [&](const Cell& c) {
    std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ull ^
                      static_cast<std::uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full ^
                      static_cast<std::uint64_t>(c.z) * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    return static_cast<std::size_t>(h & (buckets - 1));
  };

  // Candidates sorted by bucket (counting sort): bucket b holds order[start[b] .. start[b + 1]).
  // A coordinate's cell, clamped so that the conversion is defined for any finite float (a
  // file may write "1e30"): atoms that far share edge cells, and the distance test sorts them.
  const auto cell_of = [&](float x) {
    return static_cast<std::int64_t>(std::clamp(std::floor(x * inverse_cell), -0x1p62, 0x1p62));
  };
  std::vector<Cell> cells(atoms.size());
  std::vector<std::uint32_t> start(buckets + 1, 0);
  for (const std::uint32_t i : candidates) {
    const Vec3f& p = atoms[i].position;
    cells[i] = {cell_of(p.x), cell_of(p.y), cell_of(p.z)};
    ++start[bucket_of(cells[i]) + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<std::uint32_t> order(candidates.size());
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (const std::uint32_t i : candidates) order[next[bucket_of(cells[i])]++] = i;

  for (const std::uint32_t i : candidates) {
    const Atom& a = atoms[i];
    const float radius_a = element_data(a.element).covalent + tolerance;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const Cell cell{cells[i].x + dx, cells[i].y + dy, cells[i].z + dz};
          const std::size_t b = bucket_of(cell);
          for (std::uint32_t k = start[b]; k < start[b + 1]; ++k) {
            const std::uint32_t j = order[k];
            // j > i visits each pair once; the cell test skips other cells hashed here.
            if (j <= i || !(cells[j] == cell)) continue;
            const Atom& other = atoms[j];
            if (a.element == 1 && other.element == 1) continue;
            const float limit = radius_a + element_data(other.element).covalent;
            const Vec3f d = other.position - a.position;
            const float distance2 = dot(d, d);
            if (limit > min_distance && distance2 > min_distance * min_distance && distance2 < limit * limit)
              bonds.push_back({i, j});
          }
        }
  }
}

}  // namespace pdb_detail

/// Van der Waals radius in Å: Bondi (1964) where it gives one, else Alvarez (2013), else
/// 2.0; 1.5 for unknown elements (0 or beyond 118).
inline float vdw_radius(std::uint8_t element) { return pdb_detail::element_data(element).vdw; }

/// Jmol's CPK colour (its hex table over 255); deep pink for unknown elements.
inline Vec3f cpk_color(std::uint8_t element) {
  const std::uint32_t rgb = pdb_detail::element_data(element).rgb;
  return {static_cast<float>(rgb >> 16) / 255.0f, static_cast<float>((rgb >> 8) & 0xFF) / 255.0f,
          static_cast<float>(rgb & 0xFF) / 255.0f};
}

/// Covalent radius in Å (Cordero et al. 2008); 0 where there is none (unknown elements,
/// beyond curium), which keeps such atoms out of distance bonding.
inline float covalent_radius(std::uint8_t element) { return pdb_detail::element_data(element).covalent; }

/// Atomic number of an element symbol, case-blind and ignoring surrounding blanks ("C",
/// " N", "FE", "Fe"); "D" (deuterium) is hydrogen; 0 for anything else.
inline std::uint8_t element_number(std::string_view symbol) {
  symbol = pdb_detail::trim(symbol);
  if (symbol.empty() || symbol.size() > 2) return 0;
  return pdb_detail::lookup_symbol(symbol[0], symbol.size() == 2 ? symbol[1] : ' ');
}

/// Parses PDB text; source_name names it in error messages.
inline Molecule parse_pdb(std::string_view text, const std::string& source_name, const PdbOptions& options = {}) {
  using namespace pdb_detail;
  Molecule molecule;
  std::unordered_map<std::int32_t, std::uint32_t> index_of_serial;
  std::vector<std::array<std::int32_t, 2>> conect_serials;
  bool any_atom_record = false;
  bool first_model_done = false;
  std::size_t line_number = 0;

  for (std::size_t cursor = 0; cursor < text.size();) {
    const std::size_t newline = std::min(text.find('\n', cursor), text.size());
    std::string_view line = text.substr(cursor, newline - cursor);
    cursor = newline + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

    const std::string_view record = trim(columns(line, 1, 6));
    if (record == "ENDMDL") {
      first_model_done = true;
    } else if (record == "ATOM" || record == "HETATM") {
      any_atom_record = true;
      const bool hetero = record == "HETATM";
      const char altloc = columns(line, 17, 17).empty() ? ' ' : line[16];
      const std::string_view residue = trim(columns(line, 18, 20));
      if (first_model_done || (hetero && !options.hetero) || (altloc != ' ' && altloc != 'A') ||
          (!options.waters && is_water(residue)))
        continue;
      if (line.size() < 54)
        fail(source_name, line_number,
             "the record is cut at column " + std::to_string(line.size()) +
                 ": its coordinates need columns 31-54");
      Atom atom;
      atom.position = {parse_coordinate(line, 31, 'x', source_name, line_number),
                       parse_coordinate(line, 39, 'y', source_name, line_number),
                       parse_coordinate(line, 47, 'z', source_name, line_number)};
      const std::string_view name = columns(line, 13, 16);
      const std::string_view symbol = trim(columns(line, 77, 78));
      atom.element = symbol.empty() ? element_from_name(name, hetero) : element_number(symbol);
      atom.radius = vdw_radius(atom.element);
      atom.color = cpk_color(atom.element);
      atom.hetero = hetero;
      if (!parse_serial(columns(line, 7, 11), atom.serial)) atom.serial = -1;
      atom.name = trim(name);
      atom.residue = residue;
      atom.chain = line[21];
      if (atom.serial >= 0) index_of_serial.emplace(atom.serial, static_cast<std::uint32_t>(molecule.atoms.size()));
      molecule.atoms.push_back(std::move(atom));
    } else if (record == "CONECT" && options.conect_bonds) {
      // Columns 7-11 name the atom, 12-31 up to four atoms bonded to it (blank when fewer).
      std::int32_t from = 0;
      for (std::size_t first = 7; first <= 27; first += 5) {
        const std::string_view field = columns(line, first, first + 4);
        if (first > 7 && trim(field).empty()) continue;
        std::int32_t serial = 0;
        if (!parse_serial(field, serial))
          fail(source_name, line_number,
               "CONECT serial number '" + std::string(trim(field)) + "' (columns " + std::to_string(first) + "-" +
                   std::to_string(first + 4) + ") is not a number");
        if (first == 7) from = serial;
        else conect_serials.push_back({from, serial});
      }
    }
  }
  if (!any_atom_record)
    throw Error(source_name + ": no ATOM or HETATM record in its " + std::to_string(line_number) + " lines");

  // CONECT records may name atoms that were not read (skipped waters): not an error.
  for (const auto& [a, b] : conect_serials) {
    const auto ia = index_of_serial.find(a), ib = index_of_serial.find(b);
    if (ia == index_of_serial.end() || ib == index_of_serial.end() || ia->second == ib->second) continue;
    molecule.bonds.push_back({std::min(ia->second, ib->second), std::max(ia->second, ib->second)});
  }
  if (options.distance_bonds) {
    if (!std::isfinite(options.bond_tolerance))
      throw Error(source_name + ": bond_tolerance " + std::to_string(options.bond_tolerance) + " is not finite");
    add_distance_bonds(molecule.atoms, options.bond_tolerance, molecule.bonds);
  }
  std::sort(molecule.bonds.begin(), molecule.bonds.end());
  molecule.bonds.erase(std::unique(molecule.bonds.begin(), molecule.bonds.end()), molecule.bonds.end());
  return molecule;
}

inline Molecule read_pdb(const std::filesystem::path& path, const PdbOptions& options = {}) {
  const std::string name = path.string();
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) throw Error(name + ": cannot open the file");
  const std::streamoff size = file.tellg();
  if (size < 0) throw Error(name + ": cannot read the file");
  std::string text(static_cast<std::size_t>(size), '\0');
  file.seekg(0);
  if (!file.read(text.data(), size)) throw Error(name + ": cannot read the file");
  return parse_pdb(text, name, options);
}

}  // namespace sciray::io
