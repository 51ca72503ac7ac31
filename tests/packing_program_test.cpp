#include "kerfab/adapters/packing_program.h"

#include <gtest/gtest.h>

#include <random>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

double brute_force_optimum(const PackingProblem& p) {
  const int n = static_cast<int>(p.weights.size());
  double best = 0;
  for (unsigned mask = 0; mask < (1u << n); ++mask) {
    bool ok = true;
    for (auto [a, b] : p.conflicts) ok &= !((mask >> a & 1) && (mask >> b & 1));
    for (int i = 0; i < n && ok && !p.fixed.empty(); ++i)
      if (p.fixed[i]) ok &= ((mask >> i & 1) == static_cast<unsigned>(*p.fixed[i]));
    if (!ok) continue;
    double f = 0;
    for (int i = 0; i < n; ++i) f += (mask >> i & 1) ? p.weights[i] : 0.0;
    best = std::max(best, f);
  }
  return best;
}

/// n random weights in [0, 5) and each pair in conflict with probability 1 / odds.
PackingProblem random_program(std::mt19937& rng, int n, int odds) {
  std::uniform_real_distribution<double> w(0.0, 5.0);
  std::uniform_int_distribution<int> coin(0, odds - 1);
  PackingProblem p;
  for (int i = 0; i < n; ++i) p.weights.push_back(w(rng));
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (coin(rng) == 0) p.conflicts.emplace_back(a, b);
  return p;
}

TEST(PackingProgram, MatchesExhaustiveSearchOnRandomSmallPrograms) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 6 + trial % 10;
    PackingProblem p = random_program(rng, n, 6);
    if (trial % 3 == 0) {
      p.fixed.assign(n, std::nullopt);
      p.fixed[0] = false;
      p.fixed[n - 1] = true;
      for (auto [a, b] : p.conflicts)  // keep the program feasible
        if (a == n - 1 || b == n - 1) p.fixed[a == n - 1 ? b : a] = false;
    }
    const PackingResult r = solve_packing(p, {});
    EXPECT_EQ(r.status, PackingStatus::kOptimal);
    EXPECT_NEAR(r.objective, brute_force_optimum(p), 1e-7) << "trial " << trial;
    EXPECT_GE(r.bound, r.objective - 1e-9);
    for (auto [a, b] : p.conflicts) EXPECT_FALSE(r.x[a] && r.x[b]);
  }
}

// An odd cycle of 5 with unit weights: the relaxation allows 2.5, integers 2; the odd-cycle
// set limit makes the bound exact.
TEST(PackingProgram, WithoutSearchKeepsAFeasibleStartAndAValidBound) {
  // search = false (no time left for the branch and bound): a feasible selection at least as
  // good as the given start, status time limit, and a bound no lower than the true optimum.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 8 + trial % 6;
    PackingProblem p = random_program(rng, n, 4);
    p.start.assign(n, 0);
    p.start[trial % n] = 1;  // one variable alone is always feasible
    const PackingResult r = solve_packing(p, {.time_limit_s = 10, .search = false});
    ASSERT_EQ(r.x.size(), static_cast<std::size_t>(n));
    for (auto [a, b] : p.conflicts) EXPECT_FALSE(r.x[a] && r.x[b]) << "trial " << trial;
    double f = 0;
    for (int i = 0; i < n; ++i) f += r.x[i] ? p.weights[i] : 0.0;
    EXPECT_NEAR(f, r.objective, 1e-9);
    EXPECT_GE(r.objective, p.weights[trial % n] - 1e-12);
    EXPECT_GE(r.bound, brute_force_optimum(p) - 1e-9);
    EXPECT_EQ(r.status, PackingStatus::kTimeLimit);
  }
}

TEST(PackingProgram, OddCycleSetLimitGivesExactBound) {
  PackingProblem p;
  p.weights.assign(5, 1.0);
  for (int i = 0; i < 5; ++i) p.conflicts.emplace_back(i, (i + 1) % 5);
  p.set_limits.push_back({{0, 1, 2, 3, 4}, 2});
  const PackingResult r = solve_packing(p, {});
  EXPECT_EQ(r.status, PackingStatus::kOptimal);
  EXPECT_DOUBLE_EQ(r.objective, 2.0);
  EXPECT_NEAR(r.bound, 2.0, 1e-9);
}

TEST(PackingProgram, RejectsBadConflictsAndContradictoryFixings) {
  PackingProblem p;
  p.weights = {1, 1};
  p.conflicts = {{0, 2}};
  EXPECT_THROW(solve_packing(p, {}), InvalidInput);
  p.conflicts = {{0, 1}};
  p.fixed = {true, true};
  EXPECT_THROW(solve_packing(p, {}), InvalidInput);
  p.fixed = {true};
  EXPECT_THROW(solve_packing(p, {}), InvalidInput);
}

TEST(PackingProgram, Deterministic) {
  PackingProblem p;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> w(0.0, 1.0);
  for (int i = 0; i < 200; ++i) p.weights.push_back(w(rng));
  // 7i + 3 = i (mod 200) has no solution (6i + 3 is odd), so every pair is of distinct variables.
  for (int i = 0; i < 200; ++i) p.conflicts.emplace_back(i, (i * 7 + 3) % 200);
  const auto a = solve_packing(p, {}), b = solve_packing(p, {});
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.objective, b.objective);
}

}  // namespace
}  // namespace kerfab

namespace kerfab {
namespace {

// The relaxation of a 5-cycle of conflicts is worth 5/2 at x = 1/2; the odd-cycle row brings it
// to the integer optimum 2, solved again from the previous basis; the start is used when better.
TEST(PackingRelaxation, OddCycleRowTightensTheBound) {
  PackingProblem p;
  p.weights.assign(5, 1.0);
  for (int i = 0; i < 5; ++i) p.conflicts.emplace_back(i, (i + 1) % 5);
  PackingRelaxationSolver relaxation(p);
  const PackingRelaxation first = relaxation.solve();
  EXPECT_TRUE(first.optimal);
  EXPECT_NEAR(first.objective, 2.5, 1e-9);
  for (double v : first.x) EXPECT_NEAR(v, 0.5, 1e-9);
  relaxation.add_limit({0, 1, 2, 3, 4}, 2);
  EXPECT_NEAR(relaxation.solve().objective, 2.0, 1e-9);

  p.start = {1, 0, 1, 0, 0};
  const PackingResult r = solve_packing(p, {});
  EXPECT_EQ(r.status, PackingStatus::kOptimal);
  EXPECT_DOUBLE_EQ(r.objective, 2.0);
  // An infeasible start is ignored, not used.
  p.start = {1, 1, 0, 0, 0};
  EXPECT_DOUBLE_EQ(solve_packing(p, {}).objective, 2.0);
  EXPECT_THROW(PackingRelaxationSolver({.weights = {1.0}, .conflicts = {{0, 1}}}), InvalidInput);
}

}  // namespace
}  // namespace kerfab
