#pragma once
/// \file Strips (paper Sec. 3.1, second half): every quad is subdivided along its bending
/// direction, the new vertices are projected onto the target, and quads that bend the same way
/// are chained into strips, which are split at sharp folds and cut open where they close into
/// loops. Each resulting patch is a "ladder": two rails joined by a sequence of rulings.
#include <array>
#include <optional>
#include <vector>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/bending/bending.h"
#include "kerfab/core/mesh.h"

namespace kerfab {

/// How new vertices reach the target.
enum class Projection {
  kNormal,   ///< along the quad mesh's interpolated vertex normal (ray cast); closest point when
             ///< the line misses the target or meets it far away
  kClosest,  ///< the closest point on the target
};

/// The most sub-quads a run may make (every later stage's work and memory grow with them; the
/// demo has about 3000, a 20 000-quad mesh at 4 rulings 80 000; 750 000 ran past 120 s and 8 GB).
inline constexpr int kMaxSubQuads = 250'000;
/// Memory a run needs per sub-quad, all stages together, and besides them [KB], [MB]: twice
/// what was measured (Spot 500 mm, 1 and 3 Catmull-Clark steps: 13 896 sub-quads 92 MB peak,
/// 46 848 161 MB, so 2.1 KB each and about 60 MB besides).
inline constexpr double kMemoryPerSubQuadKb = 4.0;
inline constexpr double kMemoryBesidesSubQuadsMb = 64.0;
/// The memory a run with this many sub-quads needs [MB].
inline double sub_quads_memory_mb(double sub_quads) {
  return kMemoryBesidesSubQuadsMb + sub_quads * kMemoryPerSubQuadKb / 1024;
}
/// The most sub-quads that fit a memory budget [MB] (0 if none do), never above kMaxSubQuads.
inline int sub_quads_within(double memory_mb) {
  const double n = (memory_mb - kMemoryBesidesSubQuadsMb) * 1024 / kMemoryPerSubQuadKb;
  return n <= 0 ? 0 : n >= kMaxSubQuads ? kMaxSubQuads : static_cast<int>(n);
}

/// A strip of stiff sheet is split where it folds more than this (StripsOptions::split_angle's
/// default, the CLI's --split-angle 60) [rad].
inline constexpr double kStiffSplitAngle = M_PI / 3;

/// Paper's strips are split only where they fold more than this (the CLI's default for
/// --material paper): paper creases where a stiff sheet must be cut in two, and the rulings
/// folding more than kCreaseFold (joints/glue_tabs.h) are scored. Of 60 to 179 degrees on the
/// shared meshes in paper, the largest that left no border without a tab and no part unresolved
/// that 60 did not (120 and up: two bare borders on fandisk); docs/joints.md, "Paper" [rad].
inline constexpr double kPaperSplitAngle = 100 * M_PI / 180;

struct StripsOptions {
  double max_memory_mb = 0;  ///< > 0: more sub-quads than sub_quads_within() this are refused
                             ///< [MB] (the run's memory budget); kMaxSubQuads holds always
  int rulings_per_quad = 4;       ///< segments each bending edge is split into [-], >= 1
  double max_ruling_spacing = 5;  ///< a quad gets at least ceil(bending edge length / this)
                                  ///< segments [mm], > 0; the larger count wins
  Projection projection = Projection::kNormal;
  /// A strip is split between two quads where the sector normals at either end of their shared
  /// ruling differ by more than this [rad], in (0, pi]; kPaperSplitAngle for paper.
  double split_angle = kStiffSplitAngle;
  std::optional<double> features;  ///< set: vertices on refined-mesh edges sharper than this
                                   ///< dihedral angle go to target feature curves [rad], (0, pi)
  /// Quad-mesh edges (vertex index pairs) where a strip border is inserted: each must be a
  /// ruling between two quads of one strip, or already a border.
  std::vector<std::array<int, 2>> split_edges;
  /// Quad-mesh edges (vertex index pairs) across which the strips on both sides are merged
  /// sideways into one patch (paper Sec. 3.5): each must be a rail edge of both quads, so that
  /// their rulings continue; consecutive merge edges along a rail join one merged run.
  std::vector<std::array<int, 2>> merge_edges;
  /// Merge edges that are wishes rather than orders (the resolve stage's): one that no longer
  /// applies once other changes are made (a border of the mesh or a facet beside it, a ruling
  /// rather than a rail, or one strip on both sides) is skipped instead of refused.
  std::vector<std::array<int, 2>> soft_merge_edges;
  /// Groups of quads (face indices of the quad mesh) each cut as one flat plate: a planar facet
  /// with no rulings and no kerf cuts (the fallback where nothing can bend the material enough).
  /// Every group must be edge-connected and form a disk; its quads are not subdivided.
  std::vector<std::vector<int>> facets;
};

/// One edge of a patch's outline, over the patch's own vertices (Patch::local_vertices).
struct OutlineEdge {
  std::array<int, 2> v{-1, -1};  ///< local vertices, in outline order
  int coarse_edge = -1;          ///< the coarse quad-mesh edge it lies on
  int face = -1;                 ///< the interval (between rulings face and face + 1) it bounds
  int side = -1;                 ///< 0: rail 0, 1: the last rail, 2: first ruling, 3: last ruling
  int sub_quad = -1;             ///< the sub-quad it bounds (index into Strips::faces)
};

/// A row of a patch merged sideways: one chain of quads between two neighbouring rails.
struct PatchRow {
  std::vector<int> quads;                ///< coarse quads, in chain order (aligned with row 0's)
  std::vector<int> faces;                ///< sub-quad of each interval (id into Strips::faces)
  std::vector<char> face_flipped;        ///< as Patch::face_flipped, against this row's two rails
  std::vector<int> ruling_edges;         ///< per ruling: the coarse edge this row's piece lies on
  std::array<int, 2> end_edges{-1, -1};  ///< coarse edges of its first and last ruling piece
  std::vector<int> rail;  ///< per ruling: the vertex of the rail it shares with the row before
};

/// One patch: a chain of sub-quads between two rails. A patch merged sideways (paper Sec. 3.5)
/// has several rows side by side; its rulings run straight from rail 0 across every row to the
/// last rail, and the inner rails' vertices lie on them.
struct Patch {
  std::vector<int> quads;                   ///< row 0's coarse quads, in chain order
  std::vector<std::array<int, 2>> rulings;  ///< ruling i joins vertex rulings[i][0] (rail 0) and
                                            ///< rulings[i][1] (the last rail); ids into
                                            ///< Strips::vertices
  std::vector<int> faces;          ///< row 0's sub-quad i (between rulings i and i+1): id into
                                   ///< Strips::faces
  std::vector<char> face_flipped;  ///< row 0's sub-quad i is oriented (r0_i, r1_i, r1_i+1, r0_i+1)
                                   ///< instead of (r0_i, r0_i+1, r1_i+1, r1_i), r1 the rail on
                                   ///< its other side
  std::vector<std::array<int, 2>> rail_edges;  ///< interval i: the coarse edges its rail-0 side
                                               ///< (row 0) and last-rail side (last row) lie on
  std::vector<int> ruling_edges;  ///< per ruling: the coarse edge row 0's piece of it lies on, -1
                                  ///< for the rulings added inside a quad
  std::array<int, 2> end_edges{-1, -1};  ///< coarse edges of row 0's first and last ruling piece
  bool loop_cut = false;                 ///< the chain closed on itself and was cut open here
  int chain = -1;                        ///< index of the maximal chain the patch came from
  std::vector<PatchRow> more_rows;       ///< rows 1, 2, ... of a merged patch, from rail 0 on
  /// A flat facet (StripsOptions::facets): quads holds its coarse quads, faces their sub-quads
  /// (one each); it has no rulings, rails or rows, and its own vertices, quads and outline.
  bool flat = false;
  std::vector<int> flat_vertices;              ///< local vertex -> Strips::vertices id
  std::vector<std::array<int, 4>> flat_quads;  ///< over the local vertices
  std::vector<OutlineEdge> flat_outline;       ///< counter-clockwise around the facet

  /// Rows side by side (1 unless merged).
  int rows() const { return 1 + static_cast<int>(more_rows.size()); }
  /// Every coarse quad of the patch, row by row.
  std::vector<int> all_quads() const;
  /// Every sub-quad of the patch, row by row.
  std::vector<int> all_faces() const;
  /// Sub-quad of interval \p i in row \p row (of a facet: its i-th sub-quad).
  int face(int i, int row) const { return row == 0 ? faces[i] : more_rows[row - 1].faces[i]; }

  /// The patch's own vertices: local 2 * i + r is ruling i on rail 0 (r = 0) or the last rail
  /// (r = 1); inner rails follow, local 2 * (n + 1) + (k - 1) * (n + 1) + i for rail k at ruling i
  /// (n + 1 rulings). Global ids into Strips::vertices.
  std::vector<int> local_vertices() const;
  /// Local index of rail \p k (0 .. rows()) at ruling \p i.
  int local(int k, int i) const;

  /// Local quads over the patch's own vertices, oriented like the 3D faces (outward), row by row.
  std::vector<std::array<int, 4>> local_quads() const;

  /// The outline: rail 0 from the first ruling to the last, the last ruling (one edge per row),
  /// the last rail back, the first ruling (one edge per row).
  std::vector<OutlineEdge> outline() const;
};

struct Strips {
  std::vector<Vec3> vertices;             ///< refined, projected vertices [mm]
  std::vector<std::array<int, 4>> faces;  ///< sub-quads, oriented like their coarse quad
  std::vector<int> face_quad;             ///< coarse quad of each sub-quad
  std::vector<int> face_patch;            ///< patch of each sub-quad
  std::vector<Patch> patches;
  std::vector<QuadBending> quads;               ///< per coarse quad: classification as used, rigid
                                                ///< quads given the axis that continues a strip
  std::vector<int> quad_segments;               ///< per coarse quad: sub-quads along the strip
  std::vector<int> quad_patch;                  ///< per coarse quad: its patch (-1: left out)
  std::vector<std::vector<int>> edge_vertices;  ///< per coarse edge: vertex ids along it from
                                                ///< the start of its halfedge 0 to its end
  std::vector<char> vertex_on_straight_edge;    ///< vertex kept on a straight coarse edge
                                                ///< (T-junction or stiff edge), not projected
  int chains = 0;                               ///< maximal chains of quads before splitting
  int closed_loops = 0;          ///< chains that closed on themselves (each cut once)
  int split_borders = 0;         ///< borders inserted at folds above split_angle
  int self_contacts = 0;         ///< vertices copied where a patch meets itself (loop cuts, strip
                                 ///< ends against their own side)
  int t_junctions = 0;           ///< vertices on an edge that the neighbour does not subdivide
  int ray_fallbacks = 0;         ///< normal projections that fell back to the closest point
  int feature_vertices = 0;      ///< vertices moved onto target feature curves
  double max_fold = 0;           ///< largest sector-normal angle kept inside a patch [rad]
  double target_facet_size = 0;  ///< the facet size of the target the strips lie on [mm]: the
                                 ///< median over its triangles of sqrt(2 area)
};

/// Subdivides, projects and chains the quads. \pre quads is all quads and \p bending was computed
/// on it. \throw InvalidInput options out of range.
Strips build_strips(const PolyMesh& quads, const BendingResult& bending,
                    const TargetSurface& target, const StripsOptions& options);

/// Splits patch \p patch at the ruling between its coarse quads \p at - 1 and \p at: the first
/// part keeps the id, the second becomes the last patch. Nothing else changes.
/// \throw InvalidInput no such patch, or \p at not in 1 .. quads - 1.
Strips split_patch(const Strips& strips, int patch, int at);

/// Ruling index where each column (coarse quad) of patch \p p of \p s starts, and one past the
/// last: column c spans rulings starts[c] .. starts[c + 1].
std::vector<int> column_starts(const Strips& s, const Patch& p);

/// Number of dual chords (rows of quads joined across opposite edges, open or closed) of the
/// quad mesh; a layout with one strip per row of one family needs about half of these.
int quad_rows(const PolyMesh& quads);

/// Bending directions of the naive layout that ignores the target: repeatedly the quad row
/// with the most quads not yet assigned makes them bend across it. Edges are bendable where all
/// their quads agree. The baseline for the strip count (build_strips on it).
BendingResult naive_row_bending(const PolyMesh& quads);

/// The naive layout, for comparison: the quad mesh's rows, and the strips that
/// naive_row_bending() gives with the same options.
struct RowBaseline {
  int quad_rows = 0;  ///< quad_rows()
  int strips = 0;     ///< patches of build_strips() on naive_row_bending()
};
RowBaseline row_baseline(const PolyMesh& quads, const TargetSurface& target,
                         const StripsOptions& options);

/// The sub-quads as triangles (two per sub-quad, in their order: sub-quad f gives triangles 2f
/// and 2f + 1), for distance queries and output.
TriangleMesh triangulate(const Strips& strips);

}  // namespace kerfab
