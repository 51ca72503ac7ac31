// Connectivity steps of the quad mesher (src/kerfab/quads/bridges.h, cleanup.h) on flat grids
// of unit squares, where the right answer is known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "kerfab/quads/bridges.h"
#include "kerfab/quads/cleanup.h"
#include "shapes.h"

namespace kerfab::quads {
namespace {

struct Grid {
  std::vector<Vec3> points;
  std::vector<std::vector<int>> faces;
  int nx = 0, ny = 0;
  int at(int i, int j) const { return j * (nx + 1) + i; }
};

/// nx x ny unit squares in the plane z = 0, counter-clockwise seen from +z.
Grid grid(int nx, int ny) {
  Grid g;
  g.nx = nx;
  g.ny = ny;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) g.points.push_back(Vec3(i, j, 0));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      g.faces.push_back({g.at(i, j), g.at(i + 1, j), g.at(i + 1, j + 1), g.at(i, j + 1)});
  return g;
}

/// Cell (i, j) of \p g cut into two triangles on its diagonal.
void cut(Grid& g, int i, int j) {
  const auto q = g.faces[j * g.nx + i];
  g.faces[j * g.nx + i] = {q[0], q[1], q[2]};
  g.faces.push_back({q[0], q[2], q[3]});
}

/// Every edge in one face (border) or two faces that run it opposite ways.
void expect_conforming(const std::vector<std::vector<int>>& faces) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : faces)
    for (std::size_t i = 0; i < f.size(); ++i) ++directed[{f[i], f[(i + 1) % f.size()]}];
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1) << e.first << "-" << e.second << " twice the same way";
  }
}

double area_xy(const std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p) {
  double a = 0;
  for (const auto& f : faces)
    for (std::size_t i = 0; i < f.size(); ++i) {
      const Vec3 &u = p[f[i]], &w = p[f[(i + 1) % f.size()]];
      a += 0.5 * (u.x() * w.y() - w.x() * u.y());
    }
  return a;
}

std::map<int, int> valences(const std::vector<std::vector<int>>& faces) {
  std::map<int, std::set<int>> nb;
  for (const auto& f : faces)
    for (std::size_t i = 0; i < f.size(); ++i) {
      nb[f[i]].insert(f[(i + 1) % f.size()]);
      nb[f[(i + 1) % f.size()]].insert(f[i]);
    }
  std::map<int, int> out;
  for (const auto& [v, s] : nb) out[v] = static_cast<int>(s.size());
  return out;
}

constexpr double kOneDegree = 3.14159265358979323846 / 180;
const auto no_feature = [](int, int) { return false; };
const auto up = [](const Vec3&) { return Vec3(0, 0, 1); };

// Two cut cells on a 12 x 12 grid closed into a torus (connectivity only): each triangle
// pairs with one of the other cell's by a straight row, one of 3 quads (the gap between the
// cells), one of 7 (round the other way); rows ending on a border or turning would cost more.
// Every face is then a quad, the mesh conforms and keeps the torus' Euler characteristic, 0.
TEST(QuadBridges, TwoCutCellsAreJoinedByStraightRows) {
  const int n = 12;
  auto at = [&](int i, int j) { return ((j + n) % n) * n + (i + n) % n; };
  std::vector<std::vector<int>> faces;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::vector<int> q{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      if ((i == 2 || i == 6) && j == 2) {  // cut on the diagonal from corner 0 to corner 2
        faces.push_back({q[0], q[1], q[2]});
        faces.push_back({q[0], q[2], q[3]});
      } else {
        faces.push_back(q);
      }
    }
  const int before = static_cast<int>(faces.size());  // 146
  const BridgeResult b = bridge_triangles(faces, n * n, no_feature);
  ASSERT_TRUE(b.complete);
  EXPECT_EQ(b.rows, 2);
  EXPECT_EQ(b.turns, 0);
  EXPECT_EQ(static_cast<int>(b.faces.size()), before + 3 + 7);
  for (const auto& f : b.faces) EXPECT_EQ(f.size(), 4u);
  expect_conforming(b.faces);
  std::set<std::pair<int, int>> edges;
  std::set<int> vertices;
  for (const auto& f : b.faces)
    for (std::size_t i = 0; i < f.size(); ++i) {
      edges.insert(std::minmax(f[i], f[(i + 1) % f.size()]));
      vertices.insert(f[i]);
    }
  EXPECT_EQ(static_cast<int>(vertices.size()) - static_cast<int>(edges.size()) +
                static_cast<int>(b.faces.size()),
            0);
  // The new vertices: the middles of the crossed edges, 4 for the row of 3 quads, 8 for 7.
  EXPECT_EQ(b.added.size(), 4u + 8u);
  for (const auto& v : b.added) EXPECT_EQ(v.count, 2);
}

// A row never ends in a triangle through a feature edge (the middle would stay on the line as
// a flat corner): with the edge between the cut cells' neighbours marked, the row goes round.
TEST(QuadBridges, NoTriangleIsEnteredAcrossAFeature) {
  Grid g = grid(5, 1);
  cut(g, 0, 0);
  cut(g, 4, 0);
  // Feature: every vertical edge at x = 1 and x = 4 (the cut cells' inner sides).
  const auto feature = [&](int a, int b) {
    const Vec3 &p = g.points[a], &q = g.points[b];
    return p.x() == q.x() && (p.x() == 1 || p.x() == 4);
  };
  const BridgeResult b = bridge_triangles(g.faces, static_cast<int>(g.points.size()), feature);
  // The only way between the cells is through those edges: nothing is bridged, and it says so.
  EXPECT_FALSE(b.complete);
  for (const auto& v : b.added) EXPECT_FALSE(v.feature);
}

// A regular grid is left alone; an edge rotated the wrong way inside it (two vertices of
// valence 3, two of 5) is rotated back.
TEST(QuadCleanup, AWronglyRotatedEdgeIsRotatedBack) {
  Grid g = grid(6, 6);
  const std::vector<char> pinned(g.points.size(), 0);
  CleanupResult same = clean_up_valences(g.faces, g.points, pinned, no_feature, up);
  EXPECT_EQ(same.rotations + same.collapses, 0);
  EXPECT_EQ(same.faces.size(), g.faces.size());

  // Cells (2,2) and (3,2) share the edge x = 3; their hexagon's other diagonal joins (2,3)
  // and (4,2) -- rotated, they are two parallelograms.
  const int a = g.at(3, 2), b = g.at(3, 3), c = g.at(2, 3), d = g.at(2, 2), e = g.at(4, 2),
            f = g.at(4, 3);
  g.faces[2 * 6 + 2] = {d, a, e, c};
  g.faces[2 * 6 + 3] = {e, f, b, c};
  auto irregular_inside = [&](const std::vector<std::vector<int>>& faces) {
    int n = 0;
    for (auto [v, k] : valences(faces)) {
      const Vec3& p = g.points[v];
      const bool inside = p.x() > 0 && p.x() < 6 && p.y() > 0 && p.y() < 6;
      n += inside && k != 4 ? 1 : 0;
    }
    return n;
  };
  ASSERT_EQ(irregular_inside(g.faces), 4);
  // The parallelograms have corners of 45 degrees: that is what is undone, not required.
  const CleanupResult r = clean_up_valences(g.faces, g.points, pinned, no_feature, up);
  EXPECT_EQ(irregular_inside(r.faces), 0);
  EXPECT_EQ(r.faces.size(), g.faces.size());
  expect_conforming(r.faces);
  EXPECT_NEAR(area_xy(r.faces, r.points), 36.0, 1e-9);
}

// A quad with two opposite corners of valence 3 (and 5 at the other two) is collapsed along
// that diagonal: all four defects go, one face less. Built from a 4 x 4 grid by splitting its
// middle vertex m into a (below, keeping the lower cells) and c (above), with the thin quad
// (a, right, c, left) between them -- the reverse of the collapse.
TEST(QuadCleanup, ADiagonalOfTwoValenceThreeCornersIsCollapsed) {
  Grid g = grid(4, 4);
  const int a = g.at(2, 2), left = g.at(1, 2), right = g.at(3, 2);
  g.points[a] = Vec3(2, 1.8, 0);
  g.points.push_back(Vec3(2, 2.2, 0));
  const int c = static_cast<int>(g.points.size()) - 1;
  for (int j = 2; j <= 3; ++j)  // the two cells above the middle: i = 1, 2 in row j = 2
    for (int& v : g.faces[2 * 4 + (j - 1)]) v = v == a ? c : v;
  g.faces.push_back({a, right, c, left});
  expect_conforming(g.faces);
  ASSERT_NEAR(area_xy(g.faces, g.points), 16.0, 1e-9);
  auto v = valences(g.faces);
  ASSERT_EQ(v[a], 3);
  ASSERT_EQ(v[c], 3);
  ASSERT_EQ(v[left], 5);
  ASSERT_EQ(v[right], 5);
  const std::vector<char> pinned(g.points.size(), 0);
  const CleanupResult r = clean_up_valences(g.faces, g.points, pinned, no_feature, up);
  EXPECT_EQ(r.collapses, 1);
  EXPECT_EQ(r.faces.size(), 16u);
  expect_conforming(r.faces);
  EXPECT_NEAR(area_xy(r.faces, r.points), 16.0, 1e-9);
  EXPECT_NEAR((r.points[a] - Vec3(2, 2, 0)).norm(), 0.0, 1e-12);  // merged at the middle
  for (auto [w, k] : valences(r.faces)) {
    const Vec3& p = r.points[w];
    if (p.x() > 0.5 && p.x() < 3.5 && p.y() > 0.5 && p.y() < 3.5) {
      EXPECT_EQ(k, 4) << w;
    }
  }
}

/// The n x n grid of unit squares as a mesh (vertex (i, j) is number j (n + 1) + i, as in
/// Grid::at), and whether a face of it is a convex quad turning counter-clockwise seen from +z
/// with no corner under a degree (measured here, not by the mesher).
PolyMesh poly_grid(int n) {
  return test::grid_mesh(n, n, false, false,
                         [n](double u, double v) { return Vec3(n * u, n * v, 0); });
}
bool convex_up(const PolyMesh& m, OpenMesh::FaceHandle f) {
  std::vector<Vec3> p;
  for (auto v : m.fv_range(f)) p.push_back(to_eigen(m.point(v)));
  for (std::size_t c = 0; c < p.size(); ++c) {
    const Vec3 u = p[(c + 1) % p.size()] - p[c], w = p[(c + p.size() - 1) % p.size()] - p[c];
    if (!(u.cross(w).z() > std::sin(kOneDegree) * u.norm() * w.norm())) return false;
  }
  return true;
}
const auto onto_plane = [](const Vec3& p) { return Vec3(p.x(), p.y(), 0); };

// Sound quads are left exactly where they are; an inner corner pushed across its neighbours'
// diagonal (three quads round it reflex, one folded over) or onto the straight line of two
// neighbours (a corner of 180 degrees, as on the bunny's straight feature line) is moved back
// until all four quads round it are convex; the border does not move.
TEST(QuadUntangle, ACornerPushedAcrossItsNeighboursIsMovedBack) {
  const Grid g = grid(4, 4);
  PolyMesh clean = poly_grid(4);
  EXPECT_EQ(untangle(clean, convex_up, onto_plane), 0);
  for (auto v : clean.vertices()) EXPECT_EQ(to_eigen(clean.point(v)), g.points[v.idx()]);

  // Across the diagonal, lifted; onto the line from (3, 2) to (2, 3).
  for (const Vec3& pushed : {Vec3(3.3, 3.2, 0.4), Vec3(2.5, 2.5, 0)}) {
    SCOPED_TRACE(pushed.transpose());
    const int m = g.at(2, 2);
    PolyMesh q = poly_grid(4);
    q.set_point(OpenMesh::VertexHandle(m), to_openmesh(pushed));
    int unsound = 0;
    for (auto f : q.faces()) unsound += convex_up(q, f) ? 0 : 1;
    ASSERT_GT(unsound, 0);
    EXPECT_EQ(untangle(q, convex_up, onto_plane), 0);
    for (auto f : q.faces()) EXPECT_TRUE(convex_up(q, f)) << f.idx();
    for (auto v : q.vertices()) {
      const Vec3 p = to_eigen(q.point(v));
      if (v.idx() != m) {
        EXPECT_EQ(p, g.points[v.idx()]) << v.idx();
      } else {
        EXPECT_NEAR(p.z(), 0.0, 1e-12);
        EXPECT_LT((p - Vec3(2, 2, 0)).norm(), 1.0);  // inside its four cells again
      }
    }
  }
}

}  // namespace
}  // namespace kerfab::quads
