#pragma once
// A molecule as ray-traced geometry: atoms as spheres, bonds as round linear tubes.
//   space filling:  atoms at their van der Waals radius, no bonds (the molecular surface
//                   chemists read shape and packing from)
//   ball and stick: atoms at a quarter of that radius, bonds as thin tubes; each bond is
//                   two segments that meet at its midpoint, each half in its atom's colour
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sciray/error.hpp"
#include "sciray/geometry/curves.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/io/pdb.hpp"

namespace sciray {

enum class MoleculeStyle { ball_and_stick, space_filling };

inline MoleculeStyle parse_molecule_style(std::string_view name) {
  if (name == "ball-and-stick") return MoleculeStyle::ball_and_stick;
  if (name == "space-filling") return MoleculeStyle::space_filling;
  throw Error("unknown molecule style '" + std::string(name) + "' (expected ball-and-stick or space-filling)");
}

struct MoleculeGeometry {
  SphereData atoms;
  std::optional<CurveData> bonds;  ///< empty for space filling, or when there are no bonds
};

inline constexpr float ball_scale = 0.25f;   ///< ball radius / van der Waals radius
inline constexpr float stick_radius = 0.12f; ///< Å

inline MoleculeGeometry molecule_geometry(const io::Molecule& molecule, MoleculeStyle style) {
  MoleculeGeometry out;
  const float scale = style == MoleculeStyle::space_filling ? 1.f : ball_scale;
  out.atoms.positions.reserve(3 * molecule.atoms.size());
  out.atoms.radii.reserve(molecule.atoms.size());
  out.atoms.colors.reserve(4 * molecule.atoms.size());
  for (const io::Atom& atom : molecule.atoms) {
    out.atoms.positions.insert(out.atoms.positions.end(), {atom.position.x, atom.position.y, atom.position.z});
    out.atoms.radii.push_back(atom.radius * scale);
    out.atoms.colors.insert(out.atoms.colors.end(), {atom.color.x, atom.color.y, atom.color.z, 1.f});
  }
  if (style == MoleculeStyle::space_filling || molecule.bonds.empty()) return out;

  CurveData& bonds = out.bonds.emplace();
  bonds.position_radius.reserve(16 * molecule.bonds.size());
  bonds.colors.reserve(16 * molecule.bonds.size());
  bonds.indices.reserve(2 * molecule.bonds.size());
  for (const auto& [a, b] : molecule.bonds) {
    const io::Atom &from = molecule.atoms[a], &to = molecule.atoms[b];
    const Vec3f middle = (from.position + to.position) * 0.5f;
    const auto first = static_cast<std::uint32_t>(bonds.vertex_count());
    for (const auto& [p, color] : {std::pair{from.position, from.color}, std::pair{middle, from.color},
                                   std::pair{middle, to.color}, std::pair{to.position, to.color}}) {
      bonds.position_radius.insert(bonds.position_radius.end(), {p.x, p.y, p.z, stick_radius});
      bonds.colors.insert(bonds.colors.end(), {color.x, color.y, color.z, 1.f});
    }
    bonds.indices.insert(bonds.indices.end(), {first, first + 2});
  }
  return out;
}

}  // namespace sciray
