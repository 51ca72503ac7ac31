#pragma once
/// \file Weighted binary packing program  max sum w_i x_i  s.t.  x_a + x_b <= 1 for listed
/// conflict pairs, x_i in {0,1}, some x_i fixed. Solved by COIN-OR CBC behind this interface.
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace kerfab {

struct PackingProblem {
  std::vector<double> weights;                 ///< objective coefficient per variable (any sign)
  std::vector<std::pair<int, int>> conflicts;  ///< pairs that may not both be 1
  /// Further inequalities "at most limit of these variables are 1". \pre each is implied by the
  /// conflicts (e.g. an odd-cycle cut): they tighten the relaxation, never the feasible set.
  std::vector<std::pair<std::vector<int>, int>> set_limits;
  std::vector<std::optional<bool>> fixed;  ///< per variable: unset = free; empty = all free
  /// A known feasible selection (0/1 per variable) to start from; empty = none. Used when it
  /// respects the conflicts and fixings and beats the solver's own greedy start.
  std::vector<char> start;
};

struct PackingOptions {
  double time_limit_s = 60.0;  ///< wall-clock limit of the branch and bound [s], > 0
  double relative_gap = 0.0;   ///< stop when (bound - objective) / |objective| <= this [-], >= 0
  bool log = false;            ///< let CBC print its own log to stdout
  /// false: no branch and bound (no time is left for it): the better of problem.start and the
  /// greedy selection, status kTimeLimit, bound the sum of the positive weights.
  bool search = true;
};

enum class PackingStatus {
  kOptimal,    ///< proven optimal (within relative_gap, see gap)
  kTimeLimit,  ///< time limit reached; best feasible selection returned
  kStopped,    ///< solver stopped for another reason; best feasible selection returned
};

std::string to_string(PackingStatus status);

struct PackingResult {
  std::vector<char> x;   ///< 0/1 per variable, feasible
  double objective = 0;  ///< sum w_i x_i of x
  double bound = 0;      ///< proven upper bound on the optimum (>= objective)
  PackingStatus status = PackingStatus::kStopped;
  double seconds = 0;  ///< solve time [s]
};

struct PackingRelaxation {
  bool optimal = false;   ///< the simplex reached an optimum (else x and objective are unset)
  std::vector<double> x;  ///< optimal point of the linear relaxation, each in [0, 1]
  double objective = 0;   ///< w.x at that point: an upper bound on the integer optimum
  double seconds = 0;     ///< solve time [s]
};

/// The linear relaxation (0 <= x_i <= 1 and every inequality of the program), solved by CLP's
/// simplex, to which further "at most limit of these" rows can be added; each solve after an
/// addition starts from the previous basis (dual simplex), so a cutting-plane loop stays cheap.
class PackingRelaxationSolver {
 public:
  /// \throw InvalidInput as solve_packing.
  explicit PackingRelaxationSolver(const PackingProblem& problem);
  ~PackingRelaxationSolver();
  PackingRelaxationSolver(const PackingRelaxationSolver&) = delete;
  PackingRelaxationSolver& operator=(const PackingRelaxationSolver&) = delete;

  /// Adds the row sum_{i in vars} x_i <= limit. \pre indices in range.
  void add_limit(const std::vector<int>& vars, int limit);
  /// Solves the relaxation as it now stands, for at most \p max_seconds [s] (CLP's clock; a
  /// solve stopped there resumes from where it stopped on the next call); a simplex that fails
  /// or runs out of time says so in `optimal`.
  PackingRelaxation solve(double max_seconds = std::numeric_limits<double>::infinity());

 private:
  struct Model;
  std::unique_ptr<Model> model_;
  int n_;
};

/// Solves the packing program. The better of problem.start and a greedy selection is handed to
/// CBC as a start, so a feasible answer exists even when the time limit stops the search early.
/// \throw InvalidInput a conflict names a variable out of range, or two variables fixed to 1
///        conflict (the program is infeasible).
/// \throw SolverError CBC failed outright.
PackingResult solve_packing(const PackingProblem& problem, const PackingOptions& options);

}  // namespace kerfab
