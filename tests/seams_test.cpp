// The combinatorial side of the bending program: seam starts, odd rings and odd-cycle
// separation (src/kerfab/bending/seams.h, odd_cycles.h), checked against exact answers.
#include "kerfab/bending/seams.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>

#include "kerfab/adapters/matching_program.h"
#include "kerfab/adapters/packing_program.h"
#include "kerfab/bending/bending.h"
#include "kerfab/bending/odd_cycles.h"
#include "kerfab/core/errors.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

std::vector<std::pair<int, int>> quad_conflicts(const PolyMesh& m) {
  std::vector<std::pair<int, int>> c;
  for (auto f : m.faces()) {
    const auto e = quad_edges(m, f);
    for (int k = 0; k < 4; ++k) c.emplace_back(e[k], e[(k + 1) % 4]);
  }
  return c;
}

bool in_conflict(const std::vector<std::pair<int, int>>& conflicts, int a, int b) {
  for (auto [p, q] : conflicts)
    if ((p == a && q == b) || (p == b && q == a)) return true;
  return false;
}

// Largest count of pairwise non-conflicting edges, by enumeration (small meshes only).
int max_bendable_count(const PolyMesh& m) {
  return static_cast<int>(
      test::exhaustive_packing_optimum(m, std::vector<double>(m.n_edges(), 1.0)));
}

void expect_feasible(const PolyMesh& m, const std::vector<char>& x) {
  for (auto [a, b] : quad_conflicts(m)) EXPECT_FALSE(x[a] && x[b]) << a << " " << b;
}

int count(const std::vector<char>& x) {
  return static_cast<int>(std::count(x.begin(), x.end(), 1));
}

// Cube (6 quads, 8 valence-3 corners): the seams pair the corners along 4 edges, so 6 - 4/2 = 4
// edges bend, which is the true maximum.
TEST(Seams, CubeSelectionIsTheExhaustiveMaximum) {
  const auto cube = test::sphere(50.0, 1).quads;
  const SeamSelection s = seam_selection(cube);
  expect_feasible(cube, s.bendable);
  EXPECT_EQ(s.odd_vertices, 8);
  EXPECT_EQ(s.seam_edges, 4);
  EXPECT_TRUE(s.pairing_optimal);
  EXPECT_EQ(count(s.bendable), 4);
  EXPECT_EQ(count(s.bendable), max_bendable_count(cube));
}

// On closed sphere-like meshes the count is exactly F - seam_edges / 2 (every seam edge is one
// disagreement, and nothing else is lost); on a torus grid (no odd vertex) every quad bends.
TEST(Seams, BendableCountIsFacesMinusHalfTheSeams) {
  for (int n : {2, 3, 5}) {
    const auto m = test::sphere(50.0, n).quads;
    const SeamSelection s = seam_selection(m);
    expect_feasible(m, s.bendable);
    EXPECT_EQ(s.odd_vertices, 8);
    EXPECT_EQ(count(s.bendable), static_cast<int>(m.n_faces()) - s.seam_edges / 2) << n;
    EXPECT_EQ(s.seam_edges % 2, 0);
    // The 8 cube corners pair along cube edges of n grid edges each.
    EXPECT_EQ(s.seam_edges, 4 * n);
  }
  const auto torus = test::torus(60.0, 20.0, 8, 6).quads;
  const SeamSelection t = seam_selection(torus);
  EXPECT_EQ(t.odd_vertices, 0);
  EXPECT_EQ(t.seam_edges, 0);
  EXPECT_EQ(count(t.bendable), static_cast<int>(torus.n_faces()));
}

// With a boundary, seams may end on it: an open cylinder has no odd vertex and needs none; every
// quad keeps its whole axis (at least F edges bend; which direction the field takes is left to
// the program).
TEST(Seams, OpenMeshesNeedNoSeams) {
  const auto cyl = test::open_cylinder(30.0, 60.0, 6, 3).quads;
  const SeamSelection s = seam_selection(cyl);
  expect_feasible(cyl, s.bendable);
  EXPECT_EQ(s.odd_vertices, 0);
  EXPECT_EQ(s.seam_edges, 0);
  EXPECT_GE(count(s.bendable), static_cast<int>(cyl.n_faces()));
}

TEST(Seams, MatchingProgramFindsTheMinimumAndRejectsBadPairs) {
  // Four points on a line at 0, 1, 10, 11: pairs (0,1) + (10,11) cost 2; crossing pairs cost more.
  const double x[4] = {0, 1, 10, 11};
  std::vector<MatchingPair> pairs;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) pairs.push_back({a, b, std::abs(x[a] - x[b])});
  const MatchingResult r = min_cost_perfect_matching(4, pairs, 10.0);
  ASSERT_EQ(r.mate.size(), 4u);
  EXPECT_TRUE(r.optimal);
  EXPECT_DOUBLE_EQ(r.cost, 2.0);
  EXPECT_EQ(r.mate[0], 1);
  EXPECT_EQ(r.mate[2], 3);
  EXPECT_THROW(min_cost_perfect_matching(4, {{0, 4, 1.0}}, 1.0), InvalidInput);
  EXPECT_THROW(min_cost_perfect_matching(4, {{2, 2, 1.0}}, 1.0), InvalidInput);
  // Odd node count: no perfect matching.
  EXPECT_TRUE(min_cost_perfect_matching(3, {{0, 1, 1.0}, {1, 2, 1.0}}, 1.0).mate.empty());
}

// Every ring is a simple odd cycle of conflicts, hence a valid cut: checked structurally and,
// on the cube, against every feasible selection.
TEST(Seams, OddRingsAreOddSimpleConflictCycles) {
  for (int n : {1, 3, 4}) {
    const auto m = test::sphere(50.0, n).quads;
    const auto conflicts = quad_conflicts(m);
    const auto rings = odd_rings(m, 4, 64);
    EXPECT_GE(rings.size(), 8u) << n;  // at least the 8 corner stars
    for (const auto& ring : rings) {
      ASSERT_EQ(ring.size() % 2, 1u);
      ASSERT_GE(ring.size(), 3u);
      EXPECT_EQ(std::set<int>(ring.begin(), ring.end()).size(), ring.size());
      for (int e : ring) {  // each edge conflicts with exactly two others of the ring
        int partners = 0;
        for (int g : ring) partners += g != e && in_conflict(conflicts, e, g);
        EXPECT_EQ(partners, 2);
      }
    }
  }
}

TEST(OddCycles, FindsTheViolatedOddCycleAndNothingOnEvenOnes) {
  // A 5-cycle and a disjoint 6-cycle at x = 1/2: only the 5-cycle is violated (2.5 > 2).
  std::vector<std::pair<int, int>> c;
  for (int i = 0; i < 5; ++i) c.emplace_back(i, (i + 1) % 5);
  for (int i = 0; i < 6; ++i) c.emplace_back(5 + i, 5 + (i + 1) % 6);
  const std::vector<double> half(11, 0.5);
  const auto cycles = violated_odd_cycles(c, half, {});
  ASSERT_EQ(cycles.size(), 1u);
  std::vector<int> got = cycles[0];
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, (std::vector<int>{0, 1, 2, 3, 4}));
  // Satisfied point (one variable lowered to 0): nothing violated.
  std::vector<double> x = half;
  x[0] = 0.0;
  EXPECT_TRUE(violated_odd_cycles(c, x, {}).empty());
  // An integral feasible point violates nothing.
  std::vector<double> y(11, 0.0);
  y[0] = y[2] = y[5] = y[7] = y[9] = 1.0;
  EXPECT_TRUE(violated_odd_cycles(c, y, {}).empty());
}

// Separation against brute force on random points of the relaxation of a cube sphere's
// program: every returned cycle is a simple odd conflict cycle and truly violated.
TEST(OddCycles, ReturnedCyclesAreValidAndViolated) {
  const auto m = test::sphere(50.0, 2).quads;
  const auto conflicts = quad_conflicts(m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.3, 0.5);
  int found = 0;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> x(m.n_edges());
    for (double& v : x) v = u(rng);  // pairs sum to <= 1
    for (const auto& cyc : violated_odd_cycles(conflicts, x, {.min_violation = 1e-3})) {
      ++found;
      ASSERT_EQ(cyc.size() % 2, 1u);
      EXPECT_EQ(std::set<int>(cyc.begin(), cyc.end()).size(), cyc.size());
      for (std::size_t i = 0; i < cyc.size(); ++i)
        EXPECT_TRUE(in_conflict(conflicts, cyc[i], cyc[(i + 1) % cyc.size()]));
      double sum = 0;
      for (int e : cyc) sum += x[e];
      EXPECT_GT(sum, (static_cast<double>(cyc.size()) - 1) / 2 + 1e-3);
    }
  }
  EXPECT_GT(found, 0);
}

// The real case of issue 3: spot_quadrangulated on spot_triangulated, every edge on the target,
// so all weights are equal and the program is pure cardinality. CBC proves the seam start
// optimal: 2928 - 232 / 2 = 2812 bendable edges.
TEST(Bending, SpotQuadrangulatedProvenOptimal) {
  InputOptions in_opt;
  in_opt.size = 250.0;
  const PreparedInput in =
      prepare_input(read_mesh(test::real_mesh("spot_triangulated.obj")),
                    read_mesh(test::real_mesh("spot_quadrangulated.obj")), in_opt);
  ASSERT_EQ(in.quads.n_faces(), 2928u);
  const BendingResult r = choose_bending_edges(in.quads, in.surface, {});
  EXPECT_EQ(r.status, PackingStatus::kOptimal);
  EXPECT_EQ(r.odd_vertices, 96);
  EXPECT_EQ(r.seam_edges, 232);
  EXPECT_TRUE(r.seam_pairing_optimal);
  EXPECT_EQ(r.bendable_count, 2928 - 232 / 2);
  EXPECT_NEAR(r.objective, r.w0 * 2812, 1e-6);
  EXPECT_LT(r.bound - r.objective, r.w0);  // the bound admits no better multiple of w0
}

}  // namespace
}  // namespace kerfab
