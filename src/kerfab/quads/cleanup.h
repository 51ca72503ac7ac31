#pragma once
/// \file Fewer irregular vertices in an all-quad mesh by local changes of its connectivity
/// (internal to src/kerfab/quads), as in quad-mesh simplification (Tarini et al. 2010,
/// "Practical quad mesh simplification"): an edge between two quads is rotated to another
/// diagonal of their hexagon, a quad with two opposite corners of valence 3 is collapsed along
/// that diagonal, an inner vertex of two quads is removed. Each change is made only where it
/// lowers the sum over the vertices it touches of 1 per irregular vertex plus a quarter of its
/// squared valence defect (4 inside, 3 on the border), makes no valence over 6 and leaves every
/// quad it makes convex (corners of at least 20 degrees after a rotation, 10 around a merged
/// vertex); feature and border edges stay edges and pinned vertices stay where they are.
#include <functional>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab::quads {

struct CleanupResult {
  std::vector<std::vector<int>> faces;  ///< all quads
  std::vector<Vec3> points;             ///< per vertex (a collapse moves the merged vertex)
  int rotations = 0;
  int collapses = 0;
};

/// \p faces: all quads, consistently oriented, a manifold on \p points; \p pinned per vertex;
/// \p is_feature(a, b): the edge a-b must stay. \p normal_at: the surface's unit normal near a
/// point (quads are judged in its tangent plane).
CleanupResult clean_up_valences(std::vector<std::vector<int>> faces, std::vector<Vec3> points,
                                const std::vector<char>& pinned,
                                const std::function<bool(int, int)>& is_feature,
                                const std::function<Vec3(const Vec3&)>& normal_at);

/// The last untangling, after the lattice's own (lattice.cpp, which keeps corners on feature
/// lines where they are): the quads of \p q that are not \p sound get one of their inner
/// corners, on a feature line or not, moved towards the mean of its neighbours (a quarter, half
/// or all the way), then \p onto the surface, where every quad round it is then sound; border
/// corners stay. One bad quad among thousands fails a whole lattice, and the next attempt is a
/// finer one (the bunny asked for 5000 quads: one quad with three corners on a straight feature
/// line made it 10,792 quads in 340 s). Sound quads are left as they are. Returns the quads
/// still not sound.
int untangle(PolyMesh& q, const std::function<bool(const PolyMesh&, OpenMesh::FaceHandle)>& sound,
             const std::function<Vec3(const Vec3&)>& onto);

}  // namespace kerfab::quads
