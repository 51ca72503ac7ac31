// The assembly order: exact orders on hand-made contact graphs, and on every generated shape
// (run end to end) each step after the first adds a part that shares a border with the parts
// already placed, checked against the joints' borders, not the plan's own contact lists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "kerfab/assembly/assembly.h"
#include "kerfab/core/errors.h"
#include "kerfab/pipeline/pipeline.h"
#include "fixtures.h"
#include "test_util.h"

namespace kerfab {
namespace {

/// Joints with \p parts parts and one border per (p, q, length, toothed length).
Joints contact_graph(int parts, const std::vector<std::tuple<int, int, double, double>>& borders) {
  Joints j;
  j.parts.resize(parts);
  for (const auto& [p, q, length, toothed] : borders) {
    BorderJoint b;
    b.patches = {p, q};
    b.length = length;
    if (toothed > 0) b.intervals.push_back({.s0 = 0, .s1 = toothed, .owner = 0});
    if (toothed < length) b.intervals.push_back({.s0 = toothed, .s1 = length, .owner = -1});
    j.borders.push_back(b);
  }
  return j;
}

/// Part shapes from areas and perimeters [mm^2], [mm].
std::vector<PartShape> shapes_of(const std::vector<double>& area,
                                 const std::vector<double>& perimeter) {
  std::vector<PartShape> out;
  for (std::size_t p = 0; p < area.size(); ++p) out.push_back({area[p], perimeter[p]});
  return out;
}

std::vector<int> order_of(const AssemblyPlan& plan) {
  std::vector<int> out;
  for (const AssemblyStep& s : plan.steps) out.push_back(s.part);
  return out;
}

TEST(Assembly, LargestFirstThenBestHeld) {
  // A chain 0 - 1 - 2 - 3 and part 4 touching 1 with a long plain border. Part 2 is largest.
  // From 2: neighbours 1 (toothed 30) and 3 (toothed 10) -> 1 (hold 30 > 10); then 4 (hold
  // 0.5 * 50 = 25) beats 3 (10) and 0 (toothed 20 -> 20); then 0 (20), then 3 (10).
  const Joints j = contact_graph(
      5, {{0, 1, 20, 20}, {1, 2, 30, 30}, {2, 3, 10, 10}, {1, 4, 50, 0}});
  // Every part has a free border (perimeter 1000 mm): none fills a hole.
  const auto shapes = shapes_of({1, 2, 5, 1, 1}, std::vector<double>(5, 1000));
  const AssemblyPlan plan = plan_assembly(j, shapes, {});
  EXPECT_EQ(order_of(plan), (std::vector<int>{2, 1, 4, 0, 3}));
  EXPECT_EQ(plan.pieces, 1);
  EXPECT_TRUE(plan.steps[0].new_piece);
  ASSERT_EQ(plan.steps[2].joins.size(), 1u);
  EXPECT_EQ(plan.steps[2].joins[0].part, 1);
  EXPECT_DOUBLE_EQ(plan.steps[2].held, 50);
  EXPECT_DOUBLE_EQ(plan.steps[2].joins[0].toothed, 0);
  // Toothed and plain count alike with weight 1: 4 (50) before 0 (20) and 3 (10), as before;
  // with weight 0 a plain border holds nothing, so 0 (20) and 3 (10) go before 4.
  for (const AssemblyStep& s : plan.steps) EXPECT_FALSE(s.closing);
  EXPECT_EQ(order_of(plan_assembly(j, shapes, {.plain_weight = 0})),
            (std::vector<int>{2, 1, 0, 3, 4}));
}

TEST(Assembly, PartsThatFillAHoleWaitAndPiecesAreCounted) {
  // A ring 0-1-2-3-0 around a centre 4 that touches all four, their outlines all shared (a
  // closed shell: perimeter = shared border); 5-6 a separate pair with free borders.
  // Centre 4 is the largest and starts; then the ring grows around it (each ring part has an
  // unplaced neighbour until the last). Part 6 (larger than 5) starts the second piece.
  const Joints j = contact_graph(7, {{0, 1, 10, 10},
                                     {1, 2, 10, 10},
                                     {2, 3, 10, 10},
                                     {3, 0, 10, 10},
                                     {4, 0, 5, 5},
                                     {4, 1, 5, 5},
                                     {4, 2, 5, 5},
                                     {4, 3, 5, 5},
                                     {5, 6, 8, 8}});
  const std::vector<double> perimeter = {25, 25, 25, 25, 20, 100, 100};
  const AssemblyPlan plan = plan_assembly(j, shapes_of({1, 1, 1, 1, 9, 2, 3}, perimeter), {});
  EXPECT_EQ(plan.pieces, 2);
  const std::vector<int> order = order_of(plan);
  EXPECT_EQ(order, (std::vector<int>{4, 0, 1, 2, 3, 6, 5}));
  EXPECT_TRUE(plan.steps[4].closing);  // 3: all its neighbours (2, 0, 4) placed
  EXPECT_TRUE(plan.steps[5].new_piece);
  EXPECT_FALSE(plan.steps[6].closing);  // 5 has a free border: it fills no hole
  // Centre last when it is small: a part whose neighbours are all placed waits while others
  // can go on. Start 0 (largest): 1 and 3 (ties by area, then number: 1), ...
  const AssemblyPlan p2 = plan_assembly(j, shapes_of({9, 2, 2, 2, 1, 1, 1}, perimeter), {});
  const std::vector<int> o2 = order_of(p2);
  EXPECT_EQ(o2.front(), 0);
  // 4 touches 0 from the start; it is chosen only when its hold (5 per placed neighbour) beats
  // the ring's (10): never, so the ring closes first and 4 fills the hole.
  EXPECT_EQ(std::find(o2.begin(), o2.end(), 4) - o2.begin(), 4);
  EXPECT_TRUE(p2.steps[4].closing);
  EXPECT_THROW(plan_assembly(j, shapes_of({1, 2}, {1, 1}), {}), InvalidInput);
  EXPECT_THROW(plan_assembly(j, std::vector<PartShape>(7, {1, 1}), {.plain_weight = 1.5}),
               InvalidInput);
}

TEST(Assembly, EveryStepJoinsWhatIsBuiltOnGeneratedShapes) {
  PipelineOptions o;
  o.layout.sheet_width = 300;
  o.layout.sheet_height = 200;
  for (const auto& shape : test::end_to_end_shapes()) {
    SCOPED_TRACE(shape.name);
    const RunResult run = test::run_shape(shape, o, test::fresh_dir(shape.name));
    ASSERT_TRUE(run.assembly);
    const int n = static_cast<int>(run.joints->parts.size());
    if (shape.name == "plane") {  // a flat panel, cut as one plate: one step, nothing to join
      EXPECT_EQ(n, 1);
      EXPECT_EQ(run.assembly->steps.size(), 1u);
      continue;
    }
    ASSERT_GT(n, 1);
    const AssemblyPlan& plan = *run.assembly;
    ASSERT_EQ(static_cast<int>(plan.steps.size()), n);
    // A permutation of the parts.
    std::vector<int> order = order_of(plan);
    std::sort(order.begin(), order.end());
    for (int p = 0; p < n; ++p) EXPECT_EQ(order[p], p);
    // The borders as the joints stage made them: who touches whom, and how long.
    std::vector<std::set<int>> touches(n);
    for (const BorderJoint& b : run.joints->borders)
      if (b.patches[0] != b.patches[1] && b.length > 0) {
        touches[b.patches[0]].insert(b.patches[1]);
        touches[b.patches[1]].insert(b.patches[0]);
      }
    // The largest part starts.
    double largest = 0;
    for (const PartOutline& part : run.joints->parts)
      largest = std::max(largest, std::abs(polygon_area(part.designed)));
    EXPECT_NEAR(std::abs(polygon_area(run.joints->parts[plan.steps[0].part].designed)), largest,
                1e-9);
    // Every later step joins a placed part (each shape is one connected shell).
    EXPECT_EQ(plan.pieces, 1);
    std::set<int> placed = {plan.steps[0].part};
    for (std::size_t k = 1; k < plan.steps.size(); ++k) {
      const int p = plan.steps[k].part;
      bool joined = false;
      for (int q : touches[p]) joined = joined || placed.count(q) > 0;
      EXPECT_TRUE(joined) << "step " << k + 1 << " part " << p;
      EXPECT_FALSE(plan.steps[k].joins.empty());
      EXPECT_GT(plan.steps[k].held, 0);
      for (const PartContact& c : plan.steps[k].joins) EXPECT_TRUE(placed.count(c.part));
      placed.insert(p);
    }
  }
}

}  // namespace
}  // namespace kerfab
