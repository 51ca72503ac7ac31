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

struct StripsOptions {
  int rulings_per_quad = 4;       ///< segments each bending edge is split into [-], >= 1
  double max_ruling_spacing = 5;  ///< a quad gets at least ceil(bending edge length / this)
                                  ///< segments [mm], > 0; the larger count wins
  Projection projection = Projection::kNormal;
  double split_angle = M_PI / 3;   ///< a strip is split between two quads where the sector
                                   ///< normals at either end of their shared ruling differ by
                                   ///< more than this [rad], in (0, pi]
  std::optional<double> features;  ///< set: vertices on refined-mesh edges sharper than this
                                   ///< dihedral angle go to target feature curves [rad], (0, pi)
};

/// One edge of a patch's outline, over the patch's own vertices 2 * ruling + rail.
struct OutlineEdge {
  std::array<int, 2> v{-1, -1};  ///< local vertices, in outline order
  int coarse_edge = -1;          ///< the coarse quad-mesh edge it lies on
  int face = -1;                 ///< the sub-quad it bounds (index into Patch::faces)
  int side = -1;                 ///< 0: rail 0, 1: rail 1, 2: first ruling, 3: last ruling
};

/// One patch: a chain of sub-quads between two rails.
struct Patch {
  std::vector<int> quads;                   ///< coarse quads, in chain order
  std::vector<std::array<int, 2>> rulings;  ///< ruling i joins vertex rulings[i][0] (rail 0) and
                                            ///< rulings[i][1] (rail 1); ids into Strips::vertices
  std::vector<int> faces;  ///< sub-quad i (between rulings i and i+1): id into Strips::faces
  std::vector<char> face_flipped;  ///< sub-quad i is oriented (r0_i, r1_i, r1_i+1, r0_i+1)
                                   ///< instead of (r0_i, r0_i+1, r1_i+1, r1_i)
  std::vector<std::array<int, 2>> rail_edges;  ///< sub-quad i: the coarse edges its rail-0 and
                                               ///< rail-1 sides lie on
  std::vector<int> ruling_edges;  ///< per ruling: the coarse edge it lies on, -1 for the rulings
                                  ///< added inside a quad
  std::array<int, 2> end_edges{-1, -1};  ///< coarse edges of the first and last ruling
  bool loop_cut = false;                 ///< the chain closed on itself and was cut open here
  int chain = -1;                        ///< index of the maximal chain the patch came from

  /// Local quads over the patch's own vertices 2*i + rail (i = ruling), oriented like the 3D
  /// faces (outward).
  std::vector<std::array<int, 4>> local_quads() const;

  /// The outline: rail 0 from the first ruling to the last, the last ruling, rail 1 back, the
  /// first ruling.
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
  std::vector<int> quad_patch;                  ///< per coarse quad: its patch
  std::vector<std::vector<int>> edge_vertices;  ///< per coarse edge: vertex ids along it from
                                                ///< the start of its halfedge 0 to its end
  std::vector<char> vertex_on_straight_edge;    ///< vertex kept on a straight coarse edge
                                                ///< (T-junction or stiff edge), not projected
  int chains = 0;                               ///< maximal chains of quads before splitting
  int closed_loops = 0;      ///< chains that closed on themselves (each cut once)
  int split_borders = 0;     ///< borders inserted at folds above split_angle
  int self_contacts = 0;     ///< vertices copied where a patch meets itself (loop cuts, strip
                             ///< ends against their own side)
  int t_junctions = 0;       ///< vertices on an edge that the neighbour does not subdivide
  int ray_fallbacks = 0;     ///< normal projections that fell back to the closest point
  int feature_vertices = 0;  ///< vertices moved onto target feature curves
  double max_fold = 0;       ///< largest sector-normal angle kept inside a patch [rad]
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

/// The sub-quads as triangles (two per sub-quad), for distance queries and output.
TriangleMesh triangulate(const Strips& strips);

}  // namespace kerfab
