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

#include "kerfab/core/geometry2d.h"
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
  /// A loft (find_extrusion's second kind: a lampshade, a frustum, a vase): the outline at
  /// each height along the axis is the cap's outline scaled about `centre` by the `scale` of
  /// the profile there. Its corners (height along the axis [mm], scale [-]) from the bottom
  /// rim to the top one, scale 1 at the cap's end; empty for an extrusion (scale 1 all along).
  std::vector<std::array<double, 2>> profile;
  Vec3 centre = Vec3::Zero();  ///< a point on the axis the outlines are scaled about [mm]
  double radius = 0;           ///< a loft's: the cap's outline's mean distance from the axis [mm]
  /// Open at both ends (a lampshade, a pipe): `cap` is the fan of the rim at cap_on_top's end
  /// round `centre`, meshed for its border alone and not part of the result.
  bool cap_made = false;
  /// The way the cap faces in the target (its triangles' Newell sum: out of the solid, or in
  /// where the target's triangles face in); a made cap's, the way one glued to the wall would.
  Vec3 cap_facing = Vec3::Zero();
  /// A loft that closes to a point (a bowl, a dome, a capsule, a UV sphere: a pole vertex on
  /// the axis fanned to the ring round it): the dome between the pole and the ring nearest it
  /// whose scale is kDomeStop of the widest ring's (sooner where it steepens past kDomeSlope)
  /// is a cap, curved. `top` or `bottom` is that ring's height, and the dome's profile from it
  /// to the pole is here, (height along the axis [mm], scale [-] as `profile`'s), scale
  /// falling to 0. Where the cap's end is a dome, `cap`
  /// is its triangles moved along the axis onto the ring's plane (a flat disc, meshed as any
  /// cap), and the quads are lifted back onto the dome (sweep_extrusion()); a dome at the
  /// other end gets the cap's copy, lifted the same way. Empty: no dome at that end.
  std::vector<std::array<double, 2>> cap_dome, other_dome;
  /// A loft's outline at scale 1 (the widest ring's, about `centre`, in the plane across the
  /// axis with `across` as its first direction and axis x across as its second), and the
  /// scale of the cap's end against it: what a point lifted onto a dome has its scale measured by.
  std::vector<Vec2> outline;
  Vec3 across = Vec3::Zero();
  double outline_scale = 1;
};

/// A dome (Extrusion::cap_dome) reaches from its pole to the first ring whose scale is at least
/// this share of the widest ring's: a hemisphere's last 45 degrees (the slope there 45 degrees,
/// so a flat lattice lifted onto it is stretched at most 1.4 times across its rim), while the
/// wall's columns, which the rings scale, stay at least this share of their widest [-].
inline constexpr double kDomeStop = 0.7;

/// A dome's profile rises at most this much per unit of radius (tan 55 degrees: a flat lattice
/// lifted onto it stretched at most 1.74 times across), ring to ring; where it is steeper at
/// the pole (a cone's apex) there is no dome, and the dome ends sooner where it steepens [-].
inline constexpr double kDomeSlope = 1.4281480067421146;

/// A loft's profile turns by more than this at a corner (a frustum on a drum): its rows meet
/// there, each run between two corners in rows of its own [rad].
inline constexpr double kProfileCorner = 20.0 * 3.14159265358979323846 / 180.0;

/// A loft's outlines are scaled by at least this and at most 1 / this of the cap's (a cone
/// that comes to a point is no loft: its columns would meet there) [-].
inline constexpr double kLeastLoftScale = 0.3;

/// One border between rows of a swept wall: how far along the axis from the cap's end to the
/// other (0 to 1 of the way) and the scale of the outline there.
struct RowBorder {
  double way = 0, scale = 1;
};

/// The borders between rows of \p e's wall, from the cap's end (way 0) to the other (way 1),
/// rows about \p size high [mm] along the profile: round(height / size) rows of an extrusion,
/// and of a loft each run of its profile between corners (kProfileCorner) in rows of its own.
std::vector<RowBorder> row_borders(const Extrusion& e, double size);

/// Heights along the axis within this share of the target's bounding-box diagonal are one
/// height (a mesh written with 6 or 7 significant digits) [-].
inline constexpr double kSameHeight = 1e-5;

/// Face normals within this angle of the axis (caps) or of a right angle to it (the wall): a
/// tapered wall (a draft of 0.1 degree) is no extrusion [rad].
inline constexpr double kAxisTolerance = 0.05 * 3.14159265358979323846 / 180.0;

/// \p mesh as an extrusion, where it is one: every triangle faces along the axis (a cap, at the
/// lowest or highest height) or across it (the wall), the mesh's borders (if any) are rims
/// where a cap is missing, at least one cap is there, the wall has area, and two caps have the
/// same area. Of several axes (a box), the one with the largest cap. Else as a loft, where it
/// is one: its vertices at a few heights along an axis (a cap's or a rim's normal); the wall's
/// triangles each between two neighbouring heights, their edges along one height making
/// closed rings; every ring the largest one (star-shaped about its centroid) scaled about the
/// axis through that centroid (within kLeastLoftScale of the reference end's), every wall
/// triangle along one edge of that outline (so in the trapezoid between two scaled copies of
/// the edge); flat regions facing along the axis either steps (touching two rings) or caps
/// (touching one); the rings, joined by the wall and the steps, one path with the caps at its
/// ends; borders only on an end ring without a cap. nullopt otherwise.
std::optional<Extrusion> find_extrusion(const TriangleMesh& mesh);

/// The quads of the extrusion \p e from \p cap (an all-quad mesh of e.cap, facing either way,
/// its border on the cap's outline), facing out of the solid: the cap (unless e.cap_made), the
/// wall swept from its borders to the other end between the rows \p rows (row_borders(), the
/// border vertices scaled about the axis along a loft), and (where e has it) the other cap, a
/// mirrored (scaled) copy.
/// Empty where the quads do not make one consistent surface. \p along_rims and \p along_axis, if
/// given, get the wall's edges between its rows and between its columns (vertex index pairs of the
/// result): the wall bends only about the axis, so the first are its strips' rails (edges that
/// bend) and the second their rulings (straight).
PolyMesh sweep_extrusion(const PolyMesh& cap, const Extrusion& e,
                         const std::vector<RowBorder>& rows,
                         std::vector<std::array<int, 2>>* along_rims = nullptr,
                         std::vector<std::array<int, 2>>* along_axis = nullptr);

}  // namespace kerfab::quads
