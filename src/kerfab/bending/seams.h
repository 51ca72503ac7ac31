#pragma once
/// \file A bendable-edge selection from short seams: the combinatorial structure of the bending
/// program when all edge weights are equal.
///
/// Give every quad a bending axis (one of its two opposite edge pairs). An edge can bend only if
/// it is on the axis of both its quads; where the two quads disagree about it, it cannot. Walking
/// once around an interior vertex of valence k crosses k edges and k quad corners, and every
/// corner swaps axis and ruling, so the number of disagreeing edges around the vertex has the
/// parity of k: the disagreeing edges form a T-join of the interior odd-valence vertices (each
/// such vertex is the end of a seam; boundary vertices are free). With all weights equal the
/// program maximises the bendable count F - |D|/2 over closed meshes, so the best selections are
/// the shortest seams pairing the odd vertices (with each other or with the boundary). On a
/// sphere-like mesh every T-join is the disagreement set of some axis field.
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab {

struct SeamSelection {
  std::vector<char> bendable;    ///< per edge: 1 = on the axis of every quad it borders
  std::vector<char> seam;        ///< per edge: 1 = on a seam (the two quads' axes disagree)
  int odd_vertices = 0;          ///< interior vertices of odd valence (seam ends)
  int seam_edges = 0;            ///< edges on seams
  bool pairing_optimal = false;  ///< the pairing is a proven minimum (matching program)
};

/// Axis field whose seams join the odd-valence vertices in pairs (or to the boundary) along
/// shortest edge paths, the pairing chosen greedily by distance and improved by exchanging
/// partners between two pairs until no exchange shortens the total (2-opt); then every edge on
/// the axis of all its quads is bendable. Always a feasible selection for the bending program
/// (no two consecutive edges of a quad). The pairing is made exact by a matching program up to
/// 400 nodes (odd vertices, twice that with a boundary); with more than 1000 odd vertices
/// or odd vertices x vertices above 2e7 no seams are planned (the field alone, still feasible).
/// \pre quads is all quads.
SeamSelection seam_selection(const PolyMesh& quads);

/// Odd rings around the odd-valence vertices: valid cuts for the bending program that tell its
/// relaxation that seams must run from each odd vertex to a partner. A ring is the set of edges
/// leaving a group of vertices (each joins a vertex inside to one outside) when those edges form
/// one simple cycle of conflicts (each consecutive, in one of its quads, to exactly two others;
/// so the ring misses the boundary) of odd length; then at most (length - 1) / 2 of them can
/// bend. Groups: the balls of radius 0..ball_radius (in edges) around every interior odd-valence
/// vertex, and the moats of the primal-dual T-join growth after each of up to moat_steps steps
/// (every group holding an odd number of odd vertices grows by one edge layer, touching groups
/// merge, even groups and groups on the boundary stop). Sorted edge indices, no duplicates.
/// \pre quads is all quads.
std::vector<std::vector<int>> odd_rings(const PolyMesh& quads, int ball_radius, int moat_steps);

}  // namespace kerfab
