#pragma once
/// \file Coarsening of a given quad mesh where its strips would be too narrow to bend: whole
/// rows of quads (polychords, the chains of quads crossing opposite edges) are collapsed, each
/// merging its two sides into one, so that the rows beside it grow wider. A strip of kerfab is
/// a run of such a row, its rulings the row's cross edges, and a beam between two kerf cuts is
/// as long as the strip is wide: a row narrower than the bend needs (docs/kerf-cuts.md) makes
/// cuts closer than the laser can make, which the resolve stage can only cure by flat facets
/// (many small parts). Derivation and measurements: docs/quad-meshing.md, "Coarsening".
#include <optional>
#include <string>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/material.h"
#include "kerfab/core/mesh.h"

namespace kerfab {

struct CoarsenOptions {
  bool enabled = true;           ///< false: the quad mesh is used as given
  double min_cut_spacing = 0.9;  ///< the laser's closest cuts [mm], > 0
  /// A strip that bends needs room across it for at least one cut: the shortest cut, the
  /// bridge beside it, the kerf margin on both sides and the joints' slots on both borders
  /// (half a tooth width each), and a minimum cut spacing on each side [mm], >= 0.
  double min_cut_length = 2.0, bridge = 2.0, kerf_margin = 1.0, joint_depth = 1.5;
  double min_fold = M_PI / 180;  ///< a row bends where it folds more than this across a cross
                                 ///< edge [rad], >= 0
  double tolerance = 0.004;      ///< a widened row's straight rulings may miss the surface by
                                 ///< this fraction of the target's bbox diagonal [-], > 0
  double feature_angle = 1.05;   ///< quad-mesh edges folding more are sharp features, kept in
                                 ///< place [rad], (0, pi)
  double min_corner = 25 * M_PI / 180;   ///< quads the collapse changes keep corners within
  double max_corner = 170 * M_PI / 180;  ///< [min_corner, max_corner] [rad] (a sharper corner
                                         ///< makes a spike of a facet, hanging on a neck)
  double need_fraction = 0.25;  ///< a row is collapsed only where at least this fraction of its
                                ///< cross edges has a row beside it too narrow for its bend [-]
};

struct CoarsenResult {
  PolyMesh quads;        ///< the coarsened quad mesh, vertices on the target [mm]
  int quads_before = 0;  ///< faces given
  int quads_after = 0;   ///< faces kept
  /// Levels of Catmull-Clark subdivision taken back first (take_back_subdivision): the mesh
  /// given was that many levels finer than one whose strips bend where its own do not.
  int levels_taken_back = 0;
  int rows_collapsed = 0;    ///< polychords collapsed
  int rows_refused = 0;      ///< rows that needed widening but could not be collapsed (their
                             ///< neighbours would miss the target, fold, or the topology change)
  double narrow_before = 0;  ///< fraction of the cross edges with a row too narrow for its bend,
  double narrow_after = 0;   ///< before and after [-]
  /// True when the mesh kept is not the one given.
  bool changed() const { return levels_taken_back > 0 || rows_collapsed > 0; }
};

/// One level of Catmull-Clark subdivision taken back, where \p quads is one: its vertices fall
/// into the old ones (V), the edge points (E) and the face points (F), each quad V, E, F, E in
/// turn, every E joined to four quads (two on the border) and every F, never on the border,
/// to four; the quads around each F then make one coarser quad of their V corners, in the same
/// turning sense. Empty where the mesh is no such subdivision (or the coarser one would have
/// a face that is not a quad: a subdivided triangle). The coarser quads' corners are where the
/// V vertices are.
std::optional<PolyMesh> take_back_subdivision(const PolyMesh& quads);

/// Takes back levels of subdivision (take_back_subdivision) while that lowers the fraction of
/// cross edges with a row too narrow for its bend, every coarser quad stays convex with its
/// corners in range and its edges' and faces' middles stay within the tolerance of the target
/// (a straight ruling across the wider row misses the surface by no more); then collapses rows
/// of \p quads (all quads, on \p target) narrower than \p material needs for their bend,
/// narrowest first, while the rows beside them stay faithful to the target
/// (straight rulings within the tolerance), no sharp feature or border corner moves, and every
/// changed quad stays convex with its corners in range. Merged vertices go to the target's
/// closest point. The topology (Euler characteristic, borders) never changes. Paper (no
/// thickness) needs no kerf cuts: nothing is collapsed. \throw InvalidInput options out of
/// range or a mesh that is not all quads.
CoarsenResult coarsen_quads(const PolyMesh& quads, const TargetSurface& target,
                            const Material& material, const CoarsenOptions& options);

}  // namespace kerfab
