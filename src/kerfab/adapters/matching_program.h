#pragma once
/// \file Minimum-cost perfect matching as an integer program, solved by COIN-OR CBC behind this
/// interface: min sum c_ab y_ab over the listed pairs, every node in exactly one chosen pair.
#include <vector>

namespace kerfab {

struct MatchingPair {
  int a = -1, b = -1;  ///< two distinct nodes
  double cost = 0;     ///< cost of pairing them
};

struct MatchingResult {
  std::vector<int> mate;  ///< per node its partner; empty if no perfect matching was found
  double cost = 0;        ///< total cost of the chosen pairs
  bool optimal = false;   ///< proven optimal
};

/// Solves the matching program over \p nodes nodes with the listed candidate pairs.
/// \throw InvalidInput a pair names a node out of range or a node twice.
/// \throw SolverError CBC failed outright.
MatchingResult min_cost_perfect_matching(int nodes, const std::vector<MatchingPair>& pairs,
                                         double time_limit_s);

}  // namespace kerfab
