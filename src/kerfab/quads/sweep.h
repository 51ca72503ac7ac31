#pragma once
/// \file Extrusions (internal to src/kerfab/quads): a target that is a planar outline swept
/// along an axis (a drum, a bench of C-shaped section, a box with rounded corners, a pot with
/// straight walls) is meshed as one: its cap as any flat patch, the cap copied to the other
/// end, and the wall between the two rims swept in rows of quads whose sides run along the
/// axis and along the rims. Every ruling of the wall then runs along the axis, its rims lie on
/// quad edges, and its quads have no irregular vertex: the strips are rings round the wall
/// (docs/quad-meshing.md, "Extrusions").
#include <array>
#include <optional>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab::quads {

/// A target found to be an extrusion.
struct Extrusion {
  Vec3 axis{0, 0, 1};                        ///< unit, from the bottom rim to the top one
  double bottom = 0, top = 0;                ///< the rims' heights along the axis [mm]
  bool bottom_cap = false, top_cap = false;  ///< closed by a flat cap there (else open)
  /// The cap to mesh: the top one where there is one, else the bottom one; the target's own
  /// triangles there, renumbered, facing out of the solid.
  TriangleMesh cap;
  bool cap_on_top = true;
  double cap_area = 0;   ///< [mm^2]
  double wall_area = 0;  ///< [mm^2]
};

/// Heights along the axis within this share of the target's bounding-box diagonal are one
/// height (a mesh written with 6 or 7 significant digits) [-].
inline constexpr double kSameHeight = 1e-5;

/// Face normals within this angle of the axis (caps) or of a right angle to it (the wall): a
/// tapered wall (a draft of 0.1 degree) is no extrusion [rad].
inline constexpr double kAxisTolerance = 0.05 * 3.14159265358979323846 / 180.0;

/// \p mesh as an extrusion, where it is one: every triangle faces along the axis (a cap, at the
/// lowest or highest height) or across it (the wall), the mesh's borders (if any) are rims
/// where a cap is missing, at least one cap is there, the wall has area, and two caps have the
/// same area. Of several axes (a box), the one with the largest cap. nullopt otherwise.
std::optional<Extrusion> find_extrusion(const TriangleMesh& mesh);

/// The quads of the extrusion \p e from \p cap (an all-quad mesh of e.cap, facing either way,
/// its border on the cap's outline), facing out of the solid: the cap, the wall swept from its
/// borders to the other end in \p rows rows, and (where e has it) the other cap, a mirrored copy.
/// Empty where the quads do not make one consistent surface. \p along_rims and \p along_axis, if
/// given, get the wall's edges between its rows and between its columns (vertex index pairs of the
/// result): the wall bends only about the axis, so the first are its strips' rails (edges that
/// bend) and the second their rulings (straight).
PolyMesh sweep_extrusion(const PolyMesh& cap, const Extrusion& e, int rows,
                         std::vector<std::array<int, 2>>* along_rims = nullptr,
                         std::vector<std::array<int, 2>>* along_axis = nullptr);

}  // namespace kerfab::quads
