#pragma once
/// \file Quad meshing of a triangle target (before bending): a cross field that follows the
/// principal curvature directions where the surface is clearly anisotropic and the sharp
/// features and borders everywhere, a position field on it (lattice of quad corners), the
/// lattice extracted from a remeshed triangle surface by edge collapses and triangle pairing,
/// and one split step that makes every face a quad. Derivation and measurements:
/// docs/quad-meshing.md.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/guidance.h"
#include "kerfab/core/material.h"
#include "kerfab/core/mesh.h"

namespace kerfab {

struct QuadMeshOptions {
  std::optional<int> quads;           ///< set: about this many quads [-], 20..20000
  std::optional<double> quad_size;    ///< set: quad edge length [mm], > 0 (wins over quads)
  /// Where quad_size comes from, as the size rule's reason and progress name it (an
  /// extrusion's cap is meshed at the size the rule chose for the whole model).
  std::string quad_size_from = "--quad-size";
  double feature_angle = 1.05;        ///< edges folding more are sharp features [rad], (0, pi)
                                      ///< (and shallower ones between wide planes)
  /// Where the lattice at the quad size leaves a triangle with no partner (one walled in by
  /// feature lines), whether make_quad_mesh may raise feature_angle, up to 90 deg, until it
  /// pairs them all; false where the user chose the angle.
  bool raise_feature_angle = true;
  double min_cut_spacing = 0.9;       ///< the laser's closest cuts [mm] (the size rule), > 0
  double tolerance = 0.002;           ///< wanted deviation of a straight ruling from the
                                      ///< surface, fraction of the bbox diagonal [-], > 0
  int min_quads = 400;                ///< the size rule never gives fewer quads [-]
  int max_quads = 6000;               ///< nor more [-]
  int smoothing_iterations = 200;     ///< Gauss-Seidel sweeps of the position field [-]
  /// A target that ends in a dome is swept where the sweep has at most this share of the
  /// lattice's irregular vertices, else meshed by the lattice (docs/quad-meshing.md, "Domes")
  /// [-], >= 0; infinity: always swept.
  double domed_sweep_share = 0.75;
};

/// How the quad size was chosen (docs/quad-meshing.md, "Size").
struct QuadSizeRule {
  double area = 0;            ///< target surface area [mm^2]
  double bend_curvature = 0;  ///< 80th percentile (by area) of the larger principal
                              ///< curvature magnitude [1/mm]
  double ruling_curvature = 0;  ///< 80th percentile of the smaller one [1/mm]
  /// Thickness under which the thinnest tubes make up 5 % of the surface: where the line into
  /// the solid along the normal meets the other side at about twice the radius the surface
  /// curves round with [mm] (infinite where there are none: open surfaces, plates) ...
  double tube_thickness = 0;
  /// ... and the largest quads that go 4 round them [mm]: the size where the size otherwise
  /// chosen would go round them fewer than 3.5 times
  double tube_size = 0;
  double kerf_size = 0;       ///< smallest strip width whose bend keeps beams twice the
                              ///< minimum cut spacing wide [mm] (0: nothing bends or paper)
  double fidelity_size = 0;   ///< largest strip width whose straight rulings stay within the
                              ///< tolerance [mm] (infinite where nothing curves that way)
  double size = 0;            ///< the quad edge length chosen [mm]
  std::string reason;         ///< which bound decided it
};

struct QuadMeshResult {
  PolyMesh quads;                      ///< all quads, vertices on the target [mm]
  QuadSizeRule size;
  int remeshed_vertices = 0;           ///< vertices of the remeshed triangle surface
  int feature_edges = 0;               ///< sharp or border edges kept (remeshed surface)
  double feature_length = 0;           ///< their length [mm]
  double feature_length_on_quads = 0;  ///< of it, lying along quad edges [mm]
  std::string method;                  ///< how it was made: "lattice" (the lattice paired into
                                       ///< quads), "lattice, faces split", or "triangles split
                                       ///< into quads (no lattice)" (the safe net)
  std::string problem;                 ///< empty (else why the last try failed)
  int lattice_quads = 0;               ///< quads of the extracted lattice (before the split)
  int lattice_triangles = 0;           ///< triangles left over there
  /// Rows of quads split to make the left-over triangles quads in pairs (pure lattice; a split
  /// lattice makes each triangle 3 quads instead).
  int triangle_rows = 0;
  /// Triangles the lattice at the quad size left with no partner, where the lattice with every
  /// face split was taken instead (0 where it paired them all).
  int unpaired_triangles = 0;
  double feature_angle = 0;  ///< the sharp features' angle the quads were made for [rad]
  /// The option's feature angle, where feature_angle was raised from it (else 0) [rad].
  double feature_angle_asked = 0;
  /// The target's folds over feature_angle, up to 90 deg, ascending [rad]: raising the feature
  /// angle changes the sharp features (and so the quads) only past one of them.
  std::vector<double> folds_over_feature_angle;
  /// Unit dislocations of the position field (dislocations.h) found, and left after the
  /// global integer step (which is kept only where it leaves none).
  int dislocations = 0, dislocations_left = 0;
  int irregular_vertices = 0;          ///< interior vertices of valence != 4, border != 3
  std::vector<std::pair<int, int>> valences;  ///< (valence, count) over interior vertices
  double max_distance = 0;             ///< farthest quad vertex from the target [mm]
  double min_corner_angle = 0;         ///< smallest quad corner angle [rad]
  double max_corner_angle = 0;         ///< largest quad corner angle [rad]
  double mean_corner_deviation = 0;    ///< mean |corner angle - 90 deg| over all corners [rad]
  double skewed_corners = 0;           ///< share of the corners outside 45-135 deg [-]
  std::vector<std::string> repairs;    ///< what was done to the input, one line each
  /// Edges of `quads` the bending program takes as given: an extrusion's wall bends only about
  /// its axis, so its edges between rows bend and those along the axis stay straight
  /// (quads/sweep.h).
  std::vector<EdgeGuidance> bending;
};

/// Makes an all-quad mesh on \p surface (the prepared, scaled target) for the material given.
/// \throw InvalidInput options out of range, or a target that is not a manifold surface.
/// \throw SolverError when no valid quad mesh came out (the message says what to pass instead).
/// \p progress, if set, hears one line per attempt (its lattice, quads and irregular vertices,
/// or why it failed): a fine mesh takes minutes.
QuadMeshResult make_quad_mesh(const TargetSurface& surface, const Material& material,
                              const QuadMeshOptions& options,
                              const std::function<void(const std::string&)>& progress = {});

}  // namespace kerfab
