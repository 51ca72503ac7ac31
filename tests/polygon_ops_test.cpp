// The polygon Booleans' promise (adapters/polygon_ops.h): results are strictly simple — no ring
// passes through a point twice or touches one of its own edges — with holes as clockwise rings,
// and they cover exactly the right area. Checked on shapes whose answers are known by hand and on
// random unions of grid cells, where touching corners are everywhere.
#include "kerfab/adapters/polygon_ops.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "kerfab/core/geometry2d.h"

namespace kerfab {
namespace {

Polygon2 rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

double signed_total(const std::vector<Polygon2>& rings) {
  double a = 0;
  for (const auto& r : rings) a += polygon_area(r);
  return a;
}

/// Fails when a ring repeats a vertex or has a vertex on the inside of one of its own edges.
void expect_strictly_simple(const std::vector<Polygon2>& rings) {
  for (const auto& r : rings) {
    std::set<std::pair<double, double>> seen;
    for (const Vec2& v : r) EXPECT_TRUE(seen.emplace(v.x(), v.y()).second) << "repeated vertex";
    const std::size_t n = r.size();
    for (std::size_t e = 0; e < n; ++e) {
      const Vec2 &a = r[e], &b = r[(e + 1) % n];
      for (std::size_t k = 0; k < n; ++k) {
        if (k == e || k == (e + 1) % n) continue;
        const Vec2& p = r[k];
        const double cross = (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
        const double t = (p - a).dot(b - a) / (b - a).squaredNorm();
        EXPECT_FALSE(std::abs(cross) < 1e-9 && t > 1e-9 && t < 1 - 1e-9)
            << "vertex (" << p.x() << ", " << p.y() << ") on an edge of its own ring";
      }
    }
  }
}

/// Fails unless \p rings are one counter-clockwise outer ring and one clockwise hole of these
/// signed areas, both strictly simple.
void expect_outer_and_hole(const std::vector<Polygon2>& rings, double outer, double hole) {
  ASSERT_EQ(rings.size(), 2u);
  std::vector<double> areas{polygon_area(rings[0]), polygon_area(rings[1])};
  std::sort(areas.begin(), areas.end());
  EXPECT_NEAR(areas[0], hole, 1e-9);
  EXPECT_NEAR(areas[1], outer, 1e-9);
  expect_strictly_simple(rings);
}

// Round offsets are the morphological ones: a square of side a grown by d covers
// a^2 + 4ad + pi d^2 (the mitred offset the whole (a + 2d)^2), and shrunk by d it is the square
// of side a - 2d. Two squares joined by a bridge narrower than 2d fall in two when shrunk, and
// each grows back to its square within the arcs' tolerance.
TEST(PolygonOps, RoundOffsetsGrowAndShrinkAsMorphologyDoes) {
  const double a = 10, d = 1, tolerance = 0.01;
  auto area = [](const std::vector<Polygon2>& ps) {
    double sum = 0;
    for (const auto& p : ps) sum += polygon_area(p);
    return sum;
  };
  const Polygon2 square = rect(0, 0, a, a);
  const auto grown = polygon_offset_round({square}, d, tolerance);
  ASSERT_EQ(grown.size(), 1u);
  const double exact = a * a + 4 * a * d + std::numbers::pi * d * d;
  // The arcs are inscribed chords within the tolerance: less, by at most perimeter x tolerance.
  EXPECT_LE(area(grown), exact + 1e-6);
  EXPECT_GE(area(grown), exact - 2 * std::numbers::pi * d * tolerance - 1e-6);
  EXPECT_NEAR(area(polygon_offset({square}, d)), (a + 2 * d) * (a + 2 * d), 1e-6);
  EXPECT_NEAR(area(polygon_offset_round({square}, -d, tolerance)), (a - 2 * d) * (a - 2 * d), 1e-6);
  // Two 4 x 4 squares 1 mm apart, joined by a bridge 0.08 mm wide, shrunk by 0.49 mm.
  const Polygon2 pair = {{0, 0}, {4, 0}, {4, 1.96}, {5, 1.96}, {5, 0}, {9, 0},
                         {9, 4}, {5, 4}, {5, 2.04}, {4, 2.04}, {4, 4}, {0, 4}};
  const auto cores = polygon_offset_round({pair}, -0.49, tolerance);
  ASSERT_EQ(cores.size(), 2u);
  for (const auto& core : cores) {
    const auto back = polygon_offset_round({core}, 0.49, tolerance);
    ASSERT_EQ(back.size(), 1u);
    EXPECT_NEAR(area(back), 16 - (4 - std::numbers::pi) * 0.49 * 0.49, 0.04);
  }
}

TEST(PolygonOps, TwoTrianglesMeetingAtAPointComeOutAsTwoRings) {
  // A 2 x 2 square without its top and bottom quarters: two triangles touching at (1, 1).
  const auto left = polygon_difference(
      {rect(0, 0, 2, 2)}, {Polygon2{{0, 2}, {1, 1}, {2, 2}}, Polygon2{{0, 0}, {2, 0}, {1, 1}}});
  ASSERT_EQ(left.size(), 2u);
  for (const auto& r : left) EXPECT_NEAR(polygon_area(r), 1.0, 1e-9);
  expect_strictly_simple(left);
}

TEST(PolygonOps, AHoleTouchingTheOuterBorderComesOutAsAHole) {
  // A triangle cut from a 4 x 4 square, one corner on the square's left edge (inside the edge,
  // not at a vertex): the outer ring and a clockwise hole of area 2.
  const auto left =
      polygon_difference({rect(0, 0, 4, 4)}, {Polygon2{{0, 2}, {2, 1}, {2, 3}}});
  expect_outer_and_hole(left, 16.0, -2.0);
}

TEST(PolygonOps, ACavityOpenOnlyThroughAPointIsAHole) {
  // A 4 x 4 square minus the rectangle [1, 4] x [1, 3] except a triangle hanging from the top
  // with its tip (3, 1) on the bottom bar: the cut comes as two pieces meeting at (3, 1), the
  // right one open to the outside, the left one closed but for that point. Strictly simple: an
  // outer ring with a notch (16 - 1) and a clockwise hole of area 3.
  const auto left = polygon_difference(
      {rect(0, 0, 4, 4)},
      {Polygon2{{1, 1}, {3, 1}, {2, 3}, {1, 3}}, Polygon2{{3, 1}, {4, 1}, {4, 3}}});
  expect_outer_and_hole(left, 15.0, -3.0);
}

TEST(PolygonOps, AWedgeBetweenTwoCutsGoesWithThemNotAsASpikeAndAHole) {
  // The demo's part where a slot's cut-back turns a concave corner of 5 deg (coordinates as
  // drawn, mm): a 0.06 mm cut-back on the edge before the corner, the slot's cut-back after it,
  // and the wedge between them, its tip on the corner. All three are open to the outside, so the
  // result is one ring with a notch. Clipper alone returned the outer ring with the wedge as a
  // spike of material plus a hole of exactly the wedge: an outline taken alone kept a 0.15 mm
  // wide, 1.6 mm long hair there.
  Polygon2 part = {{82.18278, -103.3318},
                   {80.2716, -101.05843},
                   {79.12343, -102.02368},
                   {79.08564, -101.97872},
                   {77.43328, -99.58182},
                   {72, -100},
                   {76, -110},
                   {84, -106}};
  std::vector<Polygon2> cuts = {{{79.12419614535976, -102.02303053620858},
                                 {79.0864032938073, -101.9780754521463},
                                 {77.84538323919125, -103.02137650865764},
                                 {77.88317609074372, -103.06633159271992}},
                                {{79.08646116575278, -101.97815137245153},
                                 {77.4340975192544, -99.58125280262594},
                                 {76.09924978328846, -100.50146440452167},
                                 {77.75161342978684, -102.89836297434726}},
                                {{79.08563784544587, -101.9787189494703},
                                 {77.75161342978684, -102.89836297434726},
                                 {77.84538323919125, -103.02137650865764}}};
  make_counter_clockwise(part);
  for (auto& c : cuts) make_counter_clockwise(c);
  const auto left = polygon_difference({part}, cuts);
  ASSERT_EQ(left.size(), 1u);
  expect_strictly_simple(left);
  const double wedge = std::abs(polygon_area(cuts[2]));
  EXPECT_GT(wedge, 0.1);
  EXPECT_NEAR(polygon_area(left[0]),
              polygon_area(part) - signed_total(polygon_union(cuts)) +
                  signed_total(polygon_difference(cuts, {part})),
              1e-4);  // the grid's rounding (10 nm) along 20 mm of cuts
  Vec2 centroid(0, 0);
  for (const Vec2& v : cuts[2]) centroid += v / 3.0;
  EXPECT_FALSE(inside(centroid, left[0])) << "the wedge stayed as material";
}

TEST(PolygonOps, ANeedleLeftByTheBooleansGoesButASharpCornerOrANarrowSlotStays) {
  // The capped cylinder's part 24 as the Booleans returned it (mm, as flattened): a slot 1.59 mm
  // deep across a vertex of the border line, with a needle of material from the slot's bottom
  // up to that vertex, 0.4 um at its base. Grown by half the 0.15 mm kerf, it stood in the slot
  // as a hair of material as wide as the beam.
  const Polygon2 part = {{42.664, -48.399},   {44.7179, -48.9743}, {45.1466, -47.4439},
                         {47.6387, -48.1423}, {47.2101, -49.6724},  // the needle's tip
                         {47.6391, -48.1424}, {48.0808, -48.2660}, {47.6520, -49.7962},
                         {51.758, -50.947},   {51.758, -40},       {42.664, -40}};
  const Polygon2 slot = {
      {44.7179, -48.9743}, {47.6520, -49.7962}, {48.0808, -48.2660}, {45.1466, -47.4439}};
  ASSERT_GT(polygon_area(part), 0);
  const auto slot_inside = polygon_offset({slot}, -0.08);  // less a hair for the grid
  ASSERT_EQ(slot_inside.size(), 1u);
  auto in_slot = [&](const Polygon2& outline) {
    double a = 0;
    for (const auto& g : polygon_offset({outline}, 0.075))
      a += signed_total(polygon_intersection(g, slot_inside[0]));
    return a;
  };
  EXPECT_GT(in_slot(part), 0.1) << "the needle, grown by the kerf, stands in the slot";
  const Polygon2 clean = without_needles(part, 0.01);
  EXPECT_EQ(clean.size(), part.size() - 1);  // the tip
  EXPECT_LT(in_slot(clean), 1e-6) << "a hair of material stands in the slot";
  const double needle = std::abs(polygon_area({part[3], part[4], part[5]}));
  EXPECT_NEAR(polygon_area(clean), polygon_area(part) - needle, 1e-9);
  // A strip's tip of 2 degrees, 20 mm long, stays: its sides part 0.7 mm.
  const double tip = 2 * std::numbers::pi / 180;
  const Polygon2 strip = {{0, 0}, {20, 0}, {0, 20 * std::tan(tip)}};
  EXPECT_EQ(without_needles(strip, 0.01).size(), 3u);
  // So does a slit 0.02 mm wide (the widening of slits is the joints' business).
  const Polygon2 slit = {{0, 0},    {10, 0},   {10, 10},   {5.01, 10},
                         {5.01, 2}, {4.99, 2}, {4.99, 10}, {0, 10}};
  EXPECT_EQ(without_needles(slit, 0.01).size(), slit.size());
  // And one narrower than the width closes.
  const Polygon2 crack = {{0, 0}, {10, 0}, {10, 10}, {5.001, 10}, {5, 2}, {4.999, 10}, {0, 10}};
  EXPECT_NEAR(polygon_area(without_needles(crack, 0.01)), 100, 1e-9);
}

TEST(PolygonOps, GridCellsGiveTheExactAreaAndStrictlySimpleRings) {
  // A 12 x 12 square minus random unit cells: corners of removed cells touch everywhere, which
  // is where a ring could pass through a point twice. The area is the count of cells kept.
  std::mt19937 rng(7);
  for (int round = 0; round < 40; ++round) {
    std::vector<std::vector<bool>> gone(12, std::vector<bool>(12, false));
    std::vector<Polygon2> cells;
    std::bernoulli_distribution pick(0.45);
    int kept = 144;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j)
        if (pick(rng)) {
          gone[i][j] = true;
          cells.push_back(rect(i, j, i + 1, j + 1));
          --kept;
        }
    const auto left = polygon_difference({rect(0, 0, 12, 12)}, cells);
    EXPECT_NEAR(signed_total(left), kept, 1e-9) << "round " << round;
    expect_strictly_simple(left);
    // The union of the removed cells, alike.
    const auto removed = polygon_union(cells);
    EXPECT_NEAR(signed_total(removed), 144 - kept, 1e-9) << "round " << round;
    expect_strictly_simple(removed);
  }
}

// holds_point_deeper_than (core/geometry2d.h) spares the resolve stage an inward offset of
// every part to see that it is wide enough: where it finds a point farther than d from every
// edge, the offset by d / 2 is not empty. Exact cases: a 12 x 100 mm strip holds points 5.9 mm
// deep and none 6 mm deep; half an annulus 12 mm wide (radius 100 to 112, its centroid off the
// part) holds one 5 mm deep. Then the promise itself against Clipper's offset, on random toothed
// strips of 2 to 16 mm (seeded), offsets of up to 5 mm: never true where the offset is empty,
// always true where the strip is wider than three times the depth beyond its slots.
TEST(PolygonOps, APointDeeperThanTwiceTheOffsetMeansTheOffsetIsNotEmpty) {
  EXPECT_TRUE(holds_point_deeper_than(rect(0, 0, 100, 12), 5.9));
  EXPECT_FALSE(holds_point_deeper_than(rect(0, 0, 100, 12), 6.0));
  Polygon2 arc;
  for (int k = 0; k <= 60; ++k) {
    const double a = std::numbers::pi * k / 60;
    arc.emplace_back(112 * std::cos(a), 112 * std::sin(a));
  }
  for (int k = 60; k >= 0; --k) {
    const double a = std::numbers::pi * k / 60;
    arc.emplace_back(100 * std::cos(a), 100 * std::sin(a));
  }
  Vec2 centroid = Vec2::Zero();
  for (const Vec2& v : arc) centroid += v / static_cast<double>(arc.size());
  EXPECT_FALSE(inside(centroid, arc));
  EXPECT_TRUE(holds_point_deeper_than(arc, 5.0));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> width(2, 16), tooth(-1.5, 1.5), d(0.5, 10);
  int empty = 0, wide = 0;
  for (int trial = 0; trial < 400; ++trial) {
    // A strip 60 mm long with teeth and slots along both long sides.
    const double w = width(rng);
    Polygon2 strip;
    for (int k = 0; k <= 20; ++k) {
      const double e = k % 2 ? tooth(rng) : 0.0;
      strip.emplace_back(3.0 * k, -e);
      strip.emplace_back(3.0 * k + 3.0, -e);
    }
    for (int k = 20; k >= 0; --k) {
      const double e = k % 2 ? tooth(rng) : 0.0;
      strip.emplace_back(3.0 * k + 3.0, w + e);
      strip.emplace_back(3.0 * k, w + e);
    }
    const double depth = d(rng);
    const bool offset = !polygon_offset({strip}, -0.5 * depth).empty();
    const bool found = holds_point_deeper_than(strip, depth + 0.01);
    if (!offset) ++empty;
    if (found) {
      EXPECT_TRUE(offset) << "width " << w << ", depth " << depth;
    }
    // Wider than three times the depth beyond its slots: its middle line is found.
    if (w - 3 > 3 * depth) {
      ++wide;
      EXPECT_TRUE(found) << "width " << w << ", depth " << depth;
    }
  }
  EXPECT_GT(empty, 20);  // the test can fail on both sides
  EXPECT_GT(wide, 50);
}

}  // namespace
}  // namespace kerfab
