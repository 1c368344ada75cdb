// The PDB reader: the shipped real structures (atom counts, atoms and bond counts checked
// against the file text and an independent bond search), element detection from atom names,
// CONECT mapping, distance bonds on small molecules and a 100,000-atom lattice, the record
// filters and every error path.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "sciray/io/pdb.hpp"

namespace {

using sciray::Vec3f;
using sciray::io::Molecule;
using sciray::io::parse_pdb;
using sciray::io::PdbOptions;
using sciray::io::read_pdb;
using Bond = std::array<std::uint32_t, 2>;

struct Line {
  const char* record = "ATOM";
  const char* serial = "1";
  const char* name = " C  ";  ///< columns 13-16 exactly
  char altloc = ' ';
  const char* residue = "ALA";
  char chain = 'A';
  float x = 0, y = 0, z = 0;
  const char* element = "C";  ///< right-justified in columns 77-78; "" leaves them blank
};

/// One ATOM/HETATM record in the wwPDB column layout, with trailing blanks stripped as
/// many writers do.
std::string atom_line(const Line& l) {
  char text[96];
  std::snprintf(text, sizeof text, "%-6s%5s %4s%c%3s %c%4d    %8.3f%8.3f%8.3f%6.2f%6.2f          %2s", l.record,
                l.serial, l.name, l.altloc, l.residue, l.chain, 1, static_cast<double>(l.x),
                static_cast<double>(l.y), static_cast<double>(l.z), 1.0, 0.0, l.element);
  std::string line = text;
  while (line.back() == ' ') line.pop_back();
  return line + "\n";
}

Molecule parse(const std::string& text, const PdbOptions& options = {}) { return parse_pdb(text, "test.pdb", options); }

Molecule parse_without_bonds(const std::string& text) {
  PdbOptions options;
  options.conect_bonds = false;
  options.distance_bonds = false;
  return parse(text, options);
}

struct Placed {
  const char* element;
  float x, y, z;
};

/// A molecule of one residue from element symbols and positions, serials 1, 2, ...
std::string molecule_text(const std::vector<Placed>& atoms) {
  std::string text;
  std::vector<std::string> serials;
  for (std::size_t i = 0; i < atoms.size(); ++i) serials.push_back(std::to_string(i + 1));
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    const std::string name = std::string(" ") + atoms[i].element + "  ";
    text += atom_line({.record = "HETATM", .serial = serials[i].c_str(), .name = name.c_str(), .residue = "LIG",
                       .x = atoms[i].x, .y = atoms[i].y, .z = atoms[i].z, .element = atoms[i].element});
  }
  return text;
}

}  // namespace

TEST_CASE("pdb: element symbols, radii and colours", "[io][pdb]") {
  using namespace sciray::io;
  CHECK(element_number("C") == 6);
  CHECK(element_number("N") == 7);
  CHECK(element_number("FE") == 26);
  CHECK(element_number("Fe") == 26);
  CHECK(element_number("fe") == 26);
  CHECK(element_number(" O") == 8);
  CHECK(element_number("D") == 1);
  CHECK(element_number("Og") == 118);
  for (const char* unknown : {"", " ", "X", "Xx", "Q", "C1", "1C", "CAL"}) CHECK(element_number(unknown) == 0);
  for (std::uint8_t z = 1; z < pdb_detail::element_count; ++z)
    CHECK(element_number(pdb_detail::elements[z].symbol) == z);

  CHECK(vdw_radius(1) == 1.20f);   // Bondi
  CHECK(vdw_radius(6) == 1.70f);   // Bondi
  CHECK(vdw_radius(16) == 1.80f);  // Bondi
  CHECK(vdw_radius(20) == 2.62f);  // Alvarez: Bondi gives none for calcium
  CHECK(vdw_radius(26) == 2.44f);  // Alvarez
  CHECK(vdw_radius(0) == 1.5f);
  CHECK(vdw_radius(200) == 1.5f);
  CHECK(covalent_radius(1) == 0.31f);
  CHECK(covalent_radius(6) == 0.76f);
  CHECK(covalent_radius(26) == 1.32f);
  CHECK(covalent_radius(0) == 0.0f);
  CHECK(cpk_color(6) == Vec3f(144 / 255.0f, 144 / 255.0f, 144 / 255.0f));
  CHECK(cpk_color(8) == Vec3f(1.0f, 13 / 255.0f, 13 / 255.0f));
  CHECK(cpk_color(26) == Vec3f(224 / 255.0f, 102 / 255.0f, 51 / 255.0f));
  CHECK(cpk_color(0) == Vec3f(1.0f, 20 / 255.0f, 147 / 255.0f));
  CHECK(cpk_color(250) == cpk_color(0));
}

TEST_CASE("pdb: fields are read from their columns", "[io][pdb]") {
  const Molecule m = parse_without_bonds(
      "HEADER    TEST\n" +
      atom_line({.serial = "7", .name = " CA ", .residue = "GLY", .chain = 'B', .x = -1.5f, .y = 2.25f,
                 .z = 999.125f}) +
      atom_line({.record = "HETATM", .serial = "8", .name = "ZN  ", .residue = "ZN", .chain = 'C', .x = 1,
                 .element = "ZN"}));
  REQUIRE(m.atoms.size() == 2);
  const auto& ca = m.atoms[0];
  CHECK(ca.position == Vec3f(-1.5f, 2.25f, 999.125f));
  CHECK(ca.element == 6);
  CHECK(ca.radius == 1.70f);
  CHECK(ca.color == sciray::io::cpk_color(6));
  CHECK_FALSE(ca.hetero);
  CHECK(ca.serial == 7);
  CHECK(ca.name == "CA");
  CHECK(ca.residue == "GLY");
  CHECK(ca.chain == 'B');
  const auto& zn = m.atoms[1];
  CHECK(zn.element == 30);
  CHECK(zn.hetero);
  CHECK(zn.name == "ZN");
  CHECK(zn.residue == "ZN");
}

TEST_CASE("pdb: elements come from the atom name when columns 77-78 are blank", "[io][pdb]") {
  const Molecule m = parse_without_bonds(atom_line({.name = " CA ", .element = ""}) +                // alpha carbon
                                         atom_line({.record = "HETATM", .name = "CA  ", .element = ""}) +  // calcium
                                         atom_line({.name = "CA  ", .element = ""}) +  // no calcium in ATOM
                                         atom_line({.name = "1HB ", .element = ""}) +
                                         atom_line({.name = "HG21", .element = ""}) +  // hydrogen, not mercury
                                         atom_line({.record = "HETATM", .name = "FE  ", .element = ""}) +
                                         atom_line({.record = "HETATM", .name = "CL1 ", .element = ""}) +
                                         atom_line({.record = "HETATM", .name = "C10 ", .element = ""}) +
                                         atom_line({.name = " OXT", .element = ""}) +
                                         atom_line({.name = " SD ", .element = ""}) +
                                         atom_line({.name = " D1 ", .element = ""}) +
                                         atom_line({.name = " X1 ", .element = ""}) +
                                         atom_line({.name = " CA ", .element = "FE"}) +  // columns 77-78 win
                                         atom_line({.name = " CA ", .element = "Q"}));
  std::vector<int> elements;
  for (const auto& atom : m.atoms) elements.push_back(atom.element);
  CHECK(elements == std::vector<int>{6, 20, 6, 1, 1, 26, 17, 6, 8, 16, 1, 0, 26, 0});
  // Unknown elements are no error: they get 1.5 Å and Jmol's pink.
  CHECK(m.atoms[11].radius == 1.5f);
  CHECK(m.atoms[11].color == Vec3f(1.0f, 20 / 255.0f, 147 / 255.0f));
}

TEST_CASE("pdb: alternate locations, waters, HETATM records and models are filtered", "[io][pdb]") {
  const std::string text = atom_line({.serial = "1", .name = " N  "}) +
                           atom_line({.serial = "2", .name = " CB ", .altloc = 'A'}) +
                           atom_line({.serial = "3", .name = " CB ", .altloc = 'B'}) +
                           atom_line({.serial = "4", .name = " CB ", .altloc = 'C'}) +
                           atom_line({.record = "HETATM", .serial = "5", .name = " O  ", .residue = "HOH"}) +
                           atom_line({.record = "HETATM", .serial = "6", .name = " O  ", .residue = "WAT"}) +
                           atom_line({.record = "HETATM", .serial = "7", .name = " O  ", .residue = "DOD"}) +
                           atom_line({.record = "HETATM", .serial = "8", .name = " C1 ", .residue = "LIG"});
  const auto serials_of = [](const Molecule& m) {
    std::vector<std::int32_t> serials;
    for (const auto& atom : m.atoms) serials.push_back(atom.serial);
    return serials;
  };
  PdbOptions options;
  options.distance_bonds = false;
  CHECK(serials_of(parse(text, options)) == std::vector<std::int32_t>{1, 2, 8});
  options.waters = true;
  CHECK(serials_of(parse(text, options)) == std::vector<std::int32_t>{1, 2, 5, 6, 7, 8});
  options.hetero = false;
  CHECK(serials_of(parse(text, options)) == std::vector<std::int32_t>{1, 2});

  // Only the first model is read; CONECT records after the models still count.
  const Molecule models = parse("MODEL        1\n" + atom_line({.serial = "1", .x = 0}) +
                                atom_line({.serial = "2", .x = 1.5f}) + "ENDMDL\nMODEL        2\n" +
                                atom_line({.serial = "1", .x = 0.1f}) + atom_line({.serial = "2", .x = 1.6f}) +
                                atom_line({.serial = "3", .x = 3.1f}) + "ENDMDL\nCONECT    1    2\nEND\n");
  REQUIRE(models.atoms.size() == 2);
  CHECK(models.atoms[1].position.x == 1.5f);
  CHECK(models.bonds == std::vector<Bond>{{0, 1}});
}

TEST_CASE("pdb: CONECT serials map to atom indices", "[io][pdb]") {
  const std::string atoms = atom_line({.serial = "10", .name = " C1 "}) + atom_line({.serial = "20", .name = " C2 "}) +
                            atom_line({.record = "HETATM", .serial = "25", .name = " O  ", .residue = "HOH"}) +
                            atom_line({.serial = "30", .name = " C3 "}) + atom_line({.serial = "40", .name = " C4 "});
  // Bonds listed from both ends, a self-reference, a skipped water (25), a serial no atom has
  // (99), short lines and trailing blanks.
  const std::string conect = "CONECT   10   20   30   40   25\n"
                             "CONECT   20   10\n"
                             "CONECT   30   10   30   99\n"
                             "CONECT   40   10   20                                                      \n"
                             "CONECT   25   40\n";
  PdbOptions options;
  options.distance_bonds = false;
  const Molecule m = parse(atoms + conect, options);
  REQUIRE(m.atoms.size() == 4);
  CHECK(m.bonds == std::vector<Bond>{{0, 1}, {0, 2}, {0, 3}, {1, 3}});

  options.conect_bonds = false;
  CHECK(parse(atoms + conect, options).bonds.empty());

  // Serials past 99,999 are hybrid-36: "A0000" is 100,000, "a0000" 100,000 + 26 * 36^4.
  const Molecule big = parse(atom_line({.serial = "99999"}) + atom_line({.serial = "A0000", .x = 5}) +
                                 atom_line({.serial = "A0001", .x = 10}) + atom_line({.serial = "a0000", .x = 15}) +
                                 "CONECT99999A0000\nCONECTA0001a0000\n",
                             {.distance_bonds = false});
  CHECK(big.atoms[1].serial == 100000);
  CHECK(big.atoms[2].serial == 100001);
  CHECK(big.atoms[3].serial == 100000 + 26 * 36 * 36 * 36 * 36);
  CHECK(big.bonds == std::vector<Bond>{{0, 1}, {2, 3}});

  // An unreadable serial ("*****", as VMD writes past 99,999) is no error: the atom just
  // cannot be named by CONECT records.
  const Molecule starred = parse(atom_line({.serial = "*****"}), options);
  CHECK(starred.atoms.at(0).serial == -1);
}

TEST_CASE("pdb: distance bonds on small molecules", "[io][pdb]") {
  // Benzene: six ring C-C bonds, six C-H bonds; the 2.41 Å meta C...C and the H...H
  // contacts do not bond.
  const std::string benzene = molecule_text({{"C", 1.39f, 0, 0},         {"C", 0.695f, 1.204f, 0},
                                             {"C", -0.695f, 1.204f, 0},  {"C", -1.39f, 0, 0},
                                             {"C", -0.695f, -1.204f, 0}, {"C", 0.695f, -1.204f, 0},
                                             {"H", 2.47f, 0, 0},         {"H", 1.235f, 2.139f, 0},
                                             {"H", -1.235f, 2.139f, 0},  {"H", -2.47f, 0, 0},
                                             {"H", -1.235f, -2.139f, 0}, {"H", 1.235f, -2.139f, 0}});
  CHECK(parse(benzene).bonds == std::vector<Bond>{{0, 1}, {0, 5},  {0, 6}, {1, 2},  {1, 7}, {2, 3},
                                                  {2, 8}, {3, 4},  {3, 9}, {4, 5},  {4, 10}, {5, 11}});

  // Ethanol, staggered: C-C, C-O, O-H and five C-H.
  const std::string ethanol = molecule_text({{"C", 0, 0, 0},
                                             {"C", 1.512f, 0, 0},
                                             {"O", 1.989f, 0.674f, 1.168f},
                                             {"H", -0.363f, 1.028f, 0},
                                             {"H", -0.363f, -0.514f, 0.89f},
                                             {"H", -0.363f, -0.514f, -0.89f},
                                             {"H", 1.875f, -1.028f, 0},
                                             {"H", 1.875f, 0.514f, -0.89f},
                                             {"H", 2.949f, 0.666f, 1.154f}});
  CHECK(parse(ethanol).bonds ==
        std::vector<Bond>{{0, 1}, {0, 3}, {0, 4}, {0, 5}, {1, 2}, {1, 6}, {1, 7}, {2, 8}});

  // No H-H bonds (H2 at 0.74 Å); no bond between atoms closer than 0.4 Å.
  CHECK(parse(molecule_text({{"H", 0, 0, 0}, {"H", 0.74f, 0, 0}})).bonds.empty());
  CHECK(parse(molecule_text({{"C", 0, 0, 0}, {"C", 0.3f, 0, 0}})).bonds.empty());
  // Unknown elements have no covalent radius: only CONECT bonds them.
  CHECK(parse(molecule_text({{"C", 0, 0, 0}, {"X", 1.0f, 0, 0}})).bonds.empty());

  // The tolerance: C-C at 1.6 Å bonds with the default 0.45 Å (limit 1.97 Å), not with 0.
  const std::string stretched = molecule_text({{"C", 0, 0, 0}, {"C", 1.6f, 0, 0}});
  CHECK(parse(stretched).bonds.size() == 1);
  CHECK(parse(stretched, {.bond_tolerance = 0.0f}).bonds.empty());
  CHECK(parse(stretched, {.bond_tolerance = 0.1f}).bonds.size() == 1);

  // Far-apart fragments (the grid is hashed, not a dense box): each keeps its bond.
  CHECK(parse(molecule_text({{"C", -900, 0, 0}, {"C", -898.5f, 0, 0}, {"C", 9000, 9000, 9000},
                             {"C", 9001.5f, 9000, 9000}}))
            .bonds == std::vector<Bond>{{0, 1}, {2, 3}});
}

TEST_CASE("pdb: a 100,000-atom lattice parses and bonds to the exact count", "[io][pdb]") {
  // Carbon on a 100 x 100 x 10 simple cubic lattice, 1.5 Å apart: neighbours along the
  // axes bond (1.5 < 0.76 + 0.76 + 0.45), face diagonals (2.12 Å) do not.
  constexpr int nx = 100, ny = 100, nz = 10;
  constexpr float spacing = 1.5f;
  std::string text;
  text.reserve(std::size_t{nx} * ny * nz * 80);
  int serial = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        ++serial;
        const std::string serial_text = serial < 100000 ? std::to_string(serial) : "A0000";
        text += atom_line({.serial = serial_text.c_str(), .name = " C  ", .x = spacing * static_cast<float>(i),
                           .y = spacing * static_cast<float>(j), .z = spacing * static_cast<float>(k)});
      }
  const Molecule m = parse(text);
  REQUIRE(m.atoms.size() == 100000);
  const std::size_t expected = std::size_t{nx - 1} * ny * nz + std::size_t{nx} * (ny - 1) * nz +
                               std::size_t{nx} * ny * (nz - 1);
  REQUIRE(expected == 288000);
  CHECK(m.bonds.size() == expected);
  CHECK(m.bonds.front() == Bond{0, 1});
  CHECK(m.bonds[1] == Bond{0, 100});
  CHECK(m.bonds[2] == Bond{0, 10000});
  CHECK(m.bonds.back() == Bond{99998, 99999});
  CHECK(std::is_sorted(m.bonds.begin(), m.bonds.end()));
  CHECK(std::adjacent_find(m.bonds.begin(), m.bonds.end()) == m.bonds.end());
  bool ordered = true;
  for (const Bond& bond : m.bonds) ordered = ordered && bond[0] < bond[1];
  CHECK(ordered);

  // The last atom's hybrid-36 serial reaches it from a CONECT record.
  PdbOptions conect_only;
  conect_only.distance_bonds = false;
  const Molecule linked = parse(text + "CONECT99999A0000\n", conect_only);
  CHECK(linked.atoms.back().serial == 100000);
  CHECK(linked.bonds == std::vector<Bond>{{99998, 99999}});
}

TEST_CASE("pdb: malformed input gives errors that name the file and line", "[io][pdb]") {
  using Catch::Contains;
  const std::string good = atom_line({.serial = "1"});
  REQUIRE(parse(good).atoms.size() == 1);

  REQUIRE_THROWS_WITH(read_pdb("/nonexistent/sciray/molecule.pdb"),
                      Contains("/nonexistent/sciray/molecule.pdb: cannot open the file"));
  REQUIRE_THROWS_WITH(parse(""), Contains("test.pdb: no ATOM or HETATM record"));
  REQUIRE_THROWS_WITH(parse("HEADER    NOTHING\nREMARK   1\nEND\n"),
                      Contains("test.pdb: no ATOM or HETATM record in its 3 lines"));

  std::string bad_x = good;
  bad_x.replace(30, 8, "   1.2.3");
  REQUIRE_THROWS_WITH(parse("REMARK\n" + bad_x),
                      Contains("test.pdb: line 2: x coordinate (columns 31-38) '1.2.3' is not a finite number"));
  std::string blank_x = good;
  blank_x.replace(30, 8, "        ");
  REQUIRE_THROWS_WITH(parse(blank_x), Contains("line 1: x coordinate (columns 31-38) '' is not a finite number"));
  std::string nan_y = good;
  nan_y.replace(38, 8, "     nan");
  REQUIRE_THROWS_WITH(parse(good + nan_y),
                      Contains("line 2: y coordinate (columns 39-46) 'nan' is not a finite number"));
  std::string inf_z = good;
  inf_z.replace(46, 8, "     inf");
  REQUIRE_THROWS_WITH(parse(inf_z), Contains("line 1: z coordinate (columns 47-54) 'inf' is not a finite number"));
  std::string huge_z = good;
  huge_z.replace(46, 8, "   1e999");
  REQUIRE_THROWS_WITH(parse(huge_z), Contains("z coordinate (columns 47-54) '1e999' is not a finite number"));

  REQUIRE_THROWS_WITH(parse(good + "CONECT    1   x1\n"),
                      Contains("test.pdb: line 2: CONECT serial number 'x1' (columns 12-16) is not a number"));
  REQUIRE_THROWS_WITH(parse(good + "CONECT         1\n"),
                      Contains("line 2: CONECT serial number '' (columns 7-11) is not a number"));

  REQUIRE_THROWS_WITH(parse(good, {.bond_tolerance = std::numeric_limits<float>::quiet_NaN()}),
                      Contains("test.pdb: bond_tolerance nan is not finite"));
}

TEST_CASE("pdb: a truncated last line", "[io][pdb]") {
  using Catch::Contains;
  const std::string first = atom_line({.serial = "1"});
  const std::string second = atom_line({.serial = "2", .name = " OXT", .x = 1.25f, .element = ""});
  // Cut inside the z coordinate, without a final newline: an error, not a crash.
  REQUIRE_THROWS_WITH(parse(first + second.substr(0, 50)),
                      Contains("test.pdb: line 2: the record is cut at column 50: its coordinates need columns 31-54"));
  REQUIRE_THROWS_WITH(parse(first + "ATOM      2  N"), Contains("line 2: the record is cut at column 14"));
  // Cut right after the coordinates: the atom is read, its element from its name.
  const Molecule m = parse(first + second.substr(0, 54));
  REQUIRE(m.atoms.size() == 2);
  CHECK(m.atoms[1].position == Vec3f(1.25f, 0, 0));
  CHECK(m.atoms[1].element == 8);
  CHECK(m.atoms[1].chain == 'A');
  // CRLF line ends.
  const Molecule crlf = parse("HEADER\r\n" + first.substr(0, first.size() - 1) + "\r\n");
  REQUIRE(crlf.atoms.size() == 1);
  CHECK(crlf.atoms[0].element == 6);
}

#ifdef SCIRAY_DATA_DIR

namespace {

std::filesystem::path molecule_path(const std::string& name) {
  return std::filesystem::path(SCIRAY_DATA_DIR) / "molecules" / name;
}

std::string file_contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("pdb: the real structures load with their exact atom and bond counts", "[io][pdb][data]") {
  // Atom counts from the files' text (awk over the ATOM/HETATM records, altloc blank or
  // 'A', HOH left out by default); bond counts from an independent Python bond search with
  // the same rules (no pair lies within 0.001 Å of a threshold).
  struct Expected {
    const char* file;
    std::size_t atoms, atoms_with_waters, atoms_without_hetero;
    std::size_t bonds, bonds_with_waters, conect_bonds, conect_bonds_with_waters;
  };
  const Expected expected[] = {
      {"2LYZ.pdb", 1001, 1102, 1001, 1032, 1037, 4, 4},
      {"2j6g.pdb", 1896, 2120, 1892, 1928, 1928, 3, 3},
      {"3GQP.pdb", 4576, 4793, 4404, 4720, 4723, 204, 207},
  };
  for (const Expected& e : expected) {
    INFO(e.file);
    const auto path = molecule_path(e.file);
    const Molecule m = read_pdb(path);
    CHECK(m.atoms.size() == e.atoms);
    CHECK(m.bonds.size() == e.bonds);
    const Molecule with_waters = read_pdb(path, {.waters = true});
    CHECK(with_waters.atoms.size() == e.atoms_with_waters);
    CHECK(with_waters.bonds.size() == e.bonds_with_waters);
    CHECK(read_pdb(path, {.hetero = false}).atoms.size() == e.atoms_without_hetero);
    CHECK(read_pdb(path, {.distance_bonds = false}).bonds.size() == e.conect_bonds);
    CHECK(read_pdb(path, {.distance_bonds = false, .waters = true}).bonds.size() == e.conect_bonds_with_waters);
    CHECK(read_pdb(path, {.conect_bonds = false}).bonds.size() <= e.bonds);
  }
}

TEST_CASE("pdb: real atoms match the file text", "[io][pdb][data]") {
  SECTION("2LYZ: first and last atoms, elements, disulfides from CONECT") {
    const Molecule m = read_pdb(molecule_path("2LYZ.pdb"));
    // ATOM      1  N   LYS A   1       3.246  10.041  10.379  1.00  5.28           N
    const auto& first = m.atoms.front();
    CHECK(first.position == Vec3f(3.246f, 10.041f, 10.379f));
    CHECK(first.element == 7);
    CHECK(first.radius == 1.55f);
    CHECK(first.serial == 1);
    CHECK(first.name == "N");
    CHECK(first.residue == "LYS");
    CHECK(first.chain == 'A');
    CHECK_FALSE(first.hetero);
    // ATOM   1001  OXT LEU A 129     -17.728  19.734   8.728  1.00  3.23           O
    const auto& last = m.atoms.back();
    CHECK(last.position == Vec3f(-17.728f, 19.734f, 8.728f));
    CHECK(last.element == 8);
    CHECK(last.name == "OXT");
    std::array<int, 119> counts{};
    for (const auto& atom : m.atoms) ++counts[atom.element];
    CHECK(counts[6] == 613);
    CHECK(counts[7] == 193);
    CHECK(counts[8] == 185);
    CHECK(counts[16] == 10);

    // CONECT 48-981, 238-889, 513-630, 601-724: the four disulfides, SG to SG.
    const Molecule conect = read_pdb(molecule_path("2LYZ.pdb"), {.distance_bonds = false});
    REQUIRE(conect.bonds == std::vector<Bond>{{47, 980}, {237, 888}, {512, 629}, {600, 723}});
    for (const Bond& bond : conect.bonds)
      for (const std::uint32_t i : bond) {
        CHECK(conect.atoms[i].name == "SG");
        CHECK(conect.atoms[i].residue == "CYS");
      }
    CHECK(conect.atoms[47].serial == 48);
    CHECK(conect.atoms[980].serial == 981);

    // Bonds per heavy atom: a protein is close to a tree (one bond per atom) plus its rings.
    const double per_heavy_atom = static_cast<double>(m.bonds.size()) / static_cast<double>(m.atoms.size());
    CHECK(per_heavy_atom > 0.9);
    CHECK(per_heavy_atom < 1.3);
    CHECK(m.bonds.size() == 1032);  // 1032 / 1001 = 1.031
    for (const Bond& bond : conect.bonds) CHECK(std::binary_search(m.bonds.begin(), m.bonds.end(), bond));
  }

  SECTION("2j6g: alternate location A only") {
    const Molecule m = read_pdb(molecule_path("2j6g.pdb"));
    // ATOM      1  N   SER A   0       9.726  41.294  -8.780  1.00 15.98           N
    CHECK(m.atoms.front().position == Vec3f(9.726f, 41.294f, -8.780f));
    CHECK(m.atoms.front().element == 7);
    std::vector<std::int32_t> serials;
    for (const auto& atom : m.atoms)
      if (atom.serial >= 30 && atom.serial <= 45) serials.push_back(atom.serial);
    // 33-35 are altloc A of THR 3, 36-38 B and 39-41 C.
    CHECK(serials == std::vector<std::int32_t>{30, 31, 32, 33, 34, 35, 42, 43, 44, 45});
    // HETATM 1907  CH3 ACT A1263      -9.038  52.844 -10.871  1.00 26.80           C
    const auto& last = m.atoms.back();
    CHECK(last.position == Vec3f(-9.038f, 52.844f, -10.871f));
    CHECK(last.hetero);
    CHECK(last.residue == "ACT");
  }

  SECTION("3GQP: the haem irons") {
    const Molecule m = read_pdb(molecule_path("3GQP.pdb"));
    // ATOM      1  N   VAL A   1      18.299   9.874   1.181  1.00 34.01           N
    CHECK(m.atoms.front().position == Vec3f(18.299f, 9.874f, 1.181f));
    std::vector<std::int32_t> irons;
    for (const auto& atom : m.atoms)
      if (atom.element == 26) {
        irons.push_back(atom.serial);
        CHECK(atom.hetero);
        CHECK(atom.name == "FE");
        CHECK(atom.residue == "HEM");
        CHECK(atom.radius == 2.44f);
      }
    CHECK(irons == std::vector<std::int32_t>{4451, 4494, 4537, 4580});
    // HETATM 4580 FE   HEM D 148      -7.105  -3.039  24.949  1.00 25.16          FE
    const auto& fe = m.atoms.back();
    CHECK(fe.position == Vec3f(-7.105f, -3.039f, 24.949f));
    CHECK(fe.chain == 'D');
  }
}

TEST_CASE("pdb: real files without element columns give the same elements", "[io][pdb][data]") {
  // Old files leave columns 77-78 blank: strip them from every record and the elements
  // derived from the atom names must match the listed ones, FE in HEM included.
  for (const char* file : {"2LYZ.pdb", "2j6g.pdb", "3GQP.pdb"}) {
    INFO(file);
    const std::string text = file_contents(molecule_path(file));
    std::string stripped;
    for (std::size_t begin = 0; begin < text.size();) {
      const std::size_t end = text.find('\n', begin);
      std::string line = text.substr(begin, end - begin);
      begin = end == std::string::npos ? text.size() : end + 1;
      const bool atom_record = line.starts_with("ATOM") || line.starts_with("HETATM");
      if (atom_record && line.size() > 76) line.resize(76);
      stripped += line + "\n";
    }
    const PdbOptions options{.conect_bonds = false, .distance_bonds = false, .waters = true};
    const Molecule listed = parse_pdb(text, file, options);
    const Molecule derived = parse_pdb(stripped, file, options);
    REQUIRE(derived.atoms.size() == listed.atoms.size());
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < listed.atoms.size(); ++i)
      mismatches += listed.atoms[i].element != derived.atoms[i].element;
    CHECK(mismatches == 0);
  }
}

#endif  // SCIRAY_DATA_DIR
