#include "kerfab/adapters/packing_program.h"

#include <coin/Cbc_C_Interface.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

struct CbcDeleter {
  void operator()(Cbc_Model* m) const { Cbc_deleteModel(m); }
};

bool fixed_to(const PackingProblem& p, int i, bool value) {
  return !p.fixed.empty() && p.fixed[i].has_value() && *p.fixed[i] == value;
}

// Greedy feasible start: fixed ones first, then by decreasing weight.
std::vector<char> greedy_start(const PackingProblem& p, const std::vector<std::vector<int>>& adj) {
  const int n = static_cast<int>(p.weights.size());
  std::vector<char> x(n, 0), blocked(n, 0);
  auto take = [&](int i) {
    x[i] = 1;
    for (int j : adj[i]) blocked[j] = 1;
  };
  for (int i = 0; i < n; ++i)
    if (fixed_to(p, i, true)) take(i);
  for (int i = 0; i < n; ++i)
    if (fixed_to(p, i, false)) blocked[i] = 1;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return p.weights[a] > p.weights[b]; });
  for (int i : order)
    if (!x[i] && !blocked[i] && p.weights[i] > 0) take(i);
  return x;
}

double objective_of(const PackingProblem& p, const std::vector<char>& x) {
  double f = 0;
  for (std::size_t i = 0; i < x.size(); ++i) f += x[i] ? p.weights[i] : 0.0;
  return f;
}

}  // namespace

std::string to_string(PackingStatus status) {
  switch (status) {
    case PackingStatus::kOptimal:
      return "optimal";
    case PackingStatus::kTimeLimit:
      return "time_limit";
    case PackingStatus::kStopped:
      return "stopped";
  }
  return "unknown";
}

PackingResult solve_packing(const PackingProblem& problem, const PackingOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(problem.weights.size());
  if (!problem.fixed.empty() && static_cast<int>(problem.fixed.size()) != n)
    throw InvalidInput("packing program: 'fixed' has " + std::to_string(problem.fixed.size()) +
                       " entries for " + std::to_string(n) + " variables");
  std::vector<std::vector<int>> adj(n);
  for (const auto& [a, b] : problem.conflicts) {
    if (a < 0 || b < 0 || a >= n || b >= n || a == b)
      throw InvalidInput("packing program: conflict (" + std::to_string(a) + ", " +
                         std::to_string(b) + ") is not a pair of distinct variables");
    if (fixed_to(problem, a, true) && fixed_to(problem, b, true))
      throw InvalidInput("packing program: variables " + std::to_string(a) + " and " +
                         std::to_string(b) + " are both forced to 1 but conflict");
    adj[a].push_back(b);
    adj[b].push_back(a);
  }

  PackingResult result;
  result.x = greedy_start(problem, adj);
  if (n == 0) {
    result.status = PackingStatus::kOptimal;
    return result;
  }

  // Column-wise matrix: one row per conflict (two nonzeros), then one per set limit.
  const int m_pairs = static_cast<int>(problem.conflicts.size());
  const int m = m_pairs + static_cast<int>(problem.set_limits.size());
  std::vector<std::vector<int>> col_rows(n);
  for (int r = 0; r < m_pairs; ++r) {
    col_rows[problem.conflicts[r].first].push_back(r);
    col_rows[problem.conflicts[r].second].push_back(r);
  }
  std::vector<double> row_ub(m, 1.0);
  for (int k = 0; k < static_cast<int>(problem.set_limits.size()); ++k) {
    const auto& [vars, limit] = problem.set_limits[k];
    for (int i : vars) {
      if (i < 0 || i >= n)
        throw InvalidInput("packing program: set limit names variable " + std::to_string(i) +
                           " out of range");
      col_rows[i].push_back(m_pairs + k);
    }
    row_ub[m_pairs + k] = limit;
  }
  std::vector<int> start_idx(n + 1, 0), index;
  std::vector<double> value;
  for (int i = 0; i < n; ++i) {
    start_idx[i + 1] = start_idx[i] + static_cast<int>(col_rows[i].size());
    for (int r : col_rows[i]) {
      index.push_back(r);
      value.push_back(1.0);
    }
  }
  std::vector<double> col_lb(n, 0.0), col_ub(n, 1.0),
      row_lb(m, -std::numeric_limits<double>::infinity());
  for (int i = 0; i < n; ++i) {
    if (fixed_to(problem, i, true)) col_lb[i] = 1.0;
    if (fixed_to(problem, i, false)) col_ub[i] = 0.0;
  }
  // CBC minimises: use -w.
  std::vector<double> cost(n);
  for (int i = 0; i < n; ++i) cost[i] = -problem.weights[i];

  std::unique_ptr<Cbc_Model, CbcDeleter> model(Cbc_newModel());
  if (!model) throw SolverError("CBC: could not create a model");
  Cbc_loadProblem(model.get(), n, m, start_idx.data(), index.empty() ? nullptr : index.data(),
                  value.empty() ? nullptr : value.data(), col_lb.data(), col_ub.data(), cost.data(),
                  m ? row_lb.data() : nullptr, m ? row_ub.data() : nullptr);
  for (int i = 0; i < n; ++i) Cbc_setInteger(model.get(), i);
  Cbc_setObjSense(model.get(), 1.0);
  Cbc_setLogLevel(model.get(), options.log ? 1 : 0);
  Cbc_setMaximumSeconds(model.get(), options.time_limit_s);
  Cbc_setAllowableFractionGap(model.get(), options.relative_gap);
  Cbc_setParameter(model.get(), "threads", "1");  // deterministic
  {
    std::vector<int> idx(n);
    std::vector<double> val(n);
    for (int i = 0; i < n; ++i) {
      idx[i] = i;
      val[i] = result.x[i];
    }
    Cbc_setMIPStartI(model.get(), n, idx.data(), val.data());
  }

  Cbc_solve(model.get());
  const double* sol = Cbc_bestSolution(model.get());
  if (sol != nullptr) {
    std::vector<char> x(n);
    for (int i = 0; i < n; ++i) x[i] = sol[i] > 0.5 ? 1 : 0;
    // Keep CBC's answer only if it is feasible and at least as good as the start.
    bool feasible = true;
    for (const auto& [a, b] : problem.conflicts) feasible &= !(x[a] && x[b]);
    if (feasible && objective_of(problem, x) >= objective_of(problem, result.x) - 1e-12)
      result.x = std::move(x);
  } else if (Cbc_isProvenInfeasible(model.get())) {
    throw SolverError("CBC: the bending program is infeasible");
  }
  result.objective = objective_of(problem, result.x);
  const double bound = -Cbc_getBestPossibleObjValue(model.get());
  const bool proven = Cbc_isProvenOptimal(model.get()) != 0;
  result.bound = std::max(result.objective, bound);
  if (proven)
    result.status = PackingStatus::kOptimal;
  else if (Cbc_isSecondsLimitReached(model.get()))
    result.status = PackingStatus::kTimeLimit;
  else
    result.status = PackingStatus::kStopped;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace kerfab
