#pragma once
/// \file Odd-cycle inequalities for a packing (stable set) program over a conflict graph.
///
/// If the variables x_1..x_k lie on an odd cycle of conflicts (x_i + x_{i+1} <= 1 around the
/// cycle, k odd), at most (k-1)/2 of them can be 1. The linear relaxation does not know this:
/// x = 1/2 everywhere satisfies every pair and sums to k/2. These inequalities are what the
/// relaxation of the bending program lacks (its conflict graph is the medial graph of the quad
/// mesh, whose odd cycles are the ones around an odd number of odd-valence vertices), so adding
/// the violated ones closes most of the gap between the relaxation and the integer optimum.
#include <utility>
#include <vector>

namespace kerfab {

struct OddCycleOptions {
  double min_violation = 1e-3;  ///< report a cycle only if sum x - (k-1)/2 exceeds this [-], > 0
  int max_cycles = 400;         ///< at most this many cycles per call [count], >= 1
};

/// Violated odd-cycle inequalities of the point \p x: each returned cycle C (variable indices in
/// cycle order, odd length >= 3, no repeats, consecutive ones in conflict, also last and first)
/// has sum_{i in C} x_i > (|C|-1)/2 + min_violation. Exact separation (shortest odd closed walk
/// in the bipartite double cover with arc cost 1 - x_i - x_j, then reduced to a simple odd
/// cycle), started from every fractional variable not already on a found cycle; deterministic.
/// \pre conflicts name distinct variables in [0, x.size()); 0 <= x_i <= 1 and the pair
/// inequalities hold up to round-off.
std::vector<std::vector<int>> violated_odd_cycles(const std::vector<std::pair<int, int>>& conflicts,
                                                  const std::vector<double>& x,
                                                  const OddCycleOptions& options);

}  // namespace kerfab
