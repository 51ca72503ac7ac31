#pragma once
/// \file Flattening (paper Sec. 3.2): each patch is unfolded into the plane by least-squares
/// conformal maps on a temporary triangulation, then refined with the paper's Eq. 2 on the
/// quads: lambda * sum over border edges of the squared length error plus (1 - lambda) * sum
/// over quad corners of the squared angle error, solved by Gauss-Newton (the energy is a sum of
/// squares, so J^T J is the positive semi-definite projected Hessian) with a sparse Cholesky
/// factorisation, a backtracking line search and the Newton decrement as stopping test. A
/// facet (a flat plate) whose quads cannot lie flat together may be cut along its outline alone
/// (flatten_facet_by_outline).
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "kerfab/core/geometry2d.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

struct FlattenOptions {
  double lambda = 0.99;      ///< weight of the border-length term in Eq. 2 [-], in [0, 1];
                             ///< length errors are measured relative to the patch's mean border
                             ///< edge length so that the balance does not depend on units
  int max_iterations = 100;  ///< Gauss-Newton iterations per patch [-], >= 1
  double tolerance = 1e-14;  ///< stop when half the Newton decrement falls below this [-], > 0
  int threads = 0;           ///< patches solved in parallel; 0: one per hardware thread
  bool mimic_3d = true;      ///< also deform the 3D strips to the flat metric (evaluation)
  /// A strip flattening with a larger corner angle error than this is split (flatten_cuttable)
  /// [rad], in (0, pi].
  double max_angle_error = 20 * M_PI / 180;
  /// Paper (it folds, wood cannot): in a strip that flattens more than kCreaseNeeded off, a
  /// quad that twists, its 3D corner angles falling short of 360 deg by more than kTwistCrease,
  /// is flattened as the two triangles it is made of, creased along its shorter diagonal
  /// (PatchFlattening::creases): their angles are the corners' targets, which a flat quad meets
  /// exactly, where its own are met by none. The run sets it for a material of no thickness.
  bool crease_twisted = false;
};

/// A strip's quad whose 3D corner angles fall short of 360 deg by more than this is creased
/// along a diagonal in paper (FlattenOptions::crease_twisted) [rad].
inline constexpr double kTwistCrease = 4 * M_PI / 180;
/// ... where its strip flattens more than this off without creases [rad]: the others flatten
/// close enough as they are and take no fold lines they do not need (Spot's cage in paper: none,
/// its sheets as before; 15-253 diagonals on the shared triangle meshes instead of 25-266).
inline constexpr double kCreaseNeeded = 3 * M_PI / 180;

/// Paper: the diagonal a twisted quad is creased along (FlattenOptions::crease_twisted).
struct Crease {
  std::array<int, 2> ends{};  ///< its local vertices (PatchFlattening::points)
  double fold = 0;            ///< [rad]: > 0 mountain (the surface convex there), < 0 valley
};

/// One patch's flattening. Vertices are the patch's own, 2 * ruling + rail (Patch::local_quads).
struct PatchFlattening {
  std::vector<Vec2> points;       ///< 2D positions [mm], quads counter-clockwise
  std::vector<Vec3> deformed_3d;  ///< 3D positions whose metric matches the flat one [mm]
                                  ///< (empty unless mimic_3d)
  int iterations = 0;
  double initial_energy = 0;   ///< Eq. 2 after the conformal initialisation [-]
  double energy = 0;           ///< Eq. 2 at the end [-]
  bool converged = false;      ///< Newton decrement test met within max_iterations
  double max_angle_error = 0;  ///< largest |alpha - alpha*| over quad corners [rad]; over the
                               ///< outline's corners for a facet cut along its outline alone
  double max_border_length_error_rel = 0;  ///< largest |l - l*| / l* over border edges [-]
  int inverted_quads = 0;                  ///< quads with a corner angle outside (0, pi) in 2D
  bool outline_simple = true;              ///< the outline does not cross itself
  double area_3d = 0, area_2d = 0;         ///< [mm^2]
  std::vector<Crease> creases;             ///< paper: where its twisted quads are creased
};

/// A border piece: the part of one coarse quad-mesh edge on which two patch sides meet.
struct BorderPiece {
  int edge = -1;  ///< coarse edge
  std::array<int, 2> patches{-1, -1};
  double length_3d = 0;                   ///< [mm]
  std::array<double, 2> length_2d{0, 0};  ///< the piece's length in each patch's flattening [mm]
};

/// All pieces shared by one pair of patches (a patch may pair with itself after a loop cut).
struct SharedBorder {
  std::array<int, 2> patches{-1, -1};
  int pieces = 0;
  double length_3d = 0;
  std::array<double, 2> length_2d{0, 0};
};

struct Flattening {
  std::vector<PatchFlattening> patches;
  std::vector<BorderPiece> pieces;
  std::vector<SharedBorder> borders;
  double max_angle_error = 0;                 ///< over all patches [rad]
  double max_border_length_error_rel = 0;     ///< over all patches' border edges [-]
  double max_mating_mismatch_rel = 0;         ///< max over pieces |l2d_a - l2d_b| / l3d [-]
  double max_shared_border_mismatch_rel = 0;  ///< same over whole shared borders [-]
  int inverted_quads = 0;
  int non_simple_outlines = 0;
  int unconverged = 0;
};

/// The patch's flattened outline, counter-clockwise [mm].
std::vector<Vec2> flat_outline(const Strips& strips, const Flattening& flat, int patch);

/// A flat quad with the four side lengths of the 3D quad \p p (corners in order), built from
/// two triangles on either side of a diagonal so it cannot cross itself: of the diagonal lengths
/// both triangles admit, the one whose quad is strictly convex with corner angles nearest the 3D
/// ones (largest difference smallest; the 3D diagonal itself is a candidate, so a planar convex
/// quad comes back congruent). Counter-clockwise. Used for a one-quad facet whose corners,
/// shared with facets at other angles, sit off any common plane and flatten crossed: its side
/// lengths are what its neighbours keep [mm]. Empty when no length gives a convex quad.
std::optional<std::array<Vec2, 4>> convex_quad(const std::array<Vec3, 4>& p);

/// Quads of \p quads (counter-clockwise corner order expected) that are inverted or not
/// strictly convex in the plane: some corner angle, measured counter-clockwise, outside (0, pi).
int count_inverted_quads(const std::vector<Vec2>& points,
                         const std::vector<std::array<int, 4>>& quads);

/// True when the closed polygon through \p outline (indices into \p points) does not touch or
/// cross itself.
bool is_simple_polygon(const std::vector<Vec2>& points, const std::vector<int>& outline);

/// Flattens every patch of \p strips. \throw InvalidInput options out of range.
Flattening flatten_patches(const Strips& strips, const FlattenOptions& options);

/// A facet (Patch::flat) is cut along its outline only: its inner quads are a frame the strips
/// stage built, not a shape to keep. Where they cannot lie flat together (a cap of quads tilted
/// up to 85 deg from the facet's plane over a horse's ear: the quads' own 3D angles fold it),
/// this flattens the outline alone: its edges take their 3D lengths and each corner the facet's
/// own angle there (the sum of its quads' corner angles at that vertex, the angle a neighbour's
/// border meets it at), in least squares (Eq. 2 on the outline, from the facet's best-fit
/// plane). Its inner vertices follow as the mean of their neighbours (Tutte). max_angle_error
/// is then over the outline's corners, the only angles cut; inverted_quads still counts every
/// quad. Empty for a patch that is no facet, whose outline is not one loop through distinct
/// vertices, or that comes out more than twice its quads' area (small errors at many corners
/// adding up along a long side).
std::optional<PatchFlattening> flatten_facet_by_outline(const Strips& strips, int patch,
                                                        const FlattenOptions& options);

/// Sets \p flat's totals and its border pieces and shared borders from its patches' flattenings
/// (one per patch of \p strips); what flatten_patches ends with, and what a caller that left
/// patches out does again.
void summarise_flattening(const Strips& strips, Flattening& flat);

/// The patches' 3D meshes as one triangle mesh (each patch with its own vertices), either as
/// built or, with \p deformed, as deformed to the flat metric (PatchFlattening::deformed_3d,
/// or computed here where the flattening ran without mimic_3d).
TriangleMesh patch_triangles(const Strips& strips, const Flattening& flat, bool deformed);

}  // namespace kerfab
