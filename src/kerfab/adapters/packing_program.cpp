#include "kerfab/adapters/packing_program.h"

#include <coin/Cbc_C_Interface.h>
#include <coin/Clp_C_Interface.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include "kerfab/core/errors.h"
#include "kerfab/core/headroom.h"

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

// x respects every conflict, fixing and set limit.
bool is_feasible(const PackingProblem& p, const std::vector<char>& x) {
  for (const auto& [a, b] : p.conflicts)
    if (x[a] && x[b]) return false;
  for (std::size_t i = 0; i < p.fixed.size(); ++i)
    if (p.fixed[i] && static_cast<bool>(x[i]) != *p.fixed[i]) return false;
  for (const auto& [vars, limit] : p.set_limits) {
    int count = 0;
    for (int i : vars) count += x[i] ? 1 : 0;
    if (count > limit) return false;
  }
  return true;
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

namespace {

using CbcModelPtr = std::unique_ptr<Cbc_Model, CbcDeleter>;

// Checks the problem and returns each variable's conflict neighbours.
std::vector<std::vector<int>> conflict_adjacency(const PackingProblem& problem) {
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
  for (const auto& [vars, limit] : problem.set_limits)
    for (int i : vars)
      if (i < 0 || i >= n)
        throw InvalidInput("packing program: set limit names variable " + std::to_string(i) +
                           " out of range");
  return adj;
}

// The program in column-wise form, minimising -w.x (both solvers minimise).
struct ColumnMatrix {
  int n = 0, m = 0;
  std::vector<int> start, index;
  std::vector<double> value, col_lb, col_ub, cost, row_lb, row_ub;
};

ColumnMatrix column_matrix(const PackingProblem& problem) {
  ColumnMatrix c;
  c.n = static_cast<int>(problem.weights.size());
  // One row per conflict (two nonzeros), then one per set limit.
  const int m_pairs = static_cast<int>(problem.conflicts.size());
  c.m = m_pairs + static_cast<int>(problem.set_limits.size());
  std::vector<std::vector<int>> col_rows(c.n);
  for (int r = 0; r < m_pairs; ++r) {
    col_rows[problem.conflicts[r].first].push_back(r);
    col_rows[problem.conflicts[r].second].push_back(r);
  }
  c.row_ub.assign(c.m, 1.0);
  for (int k = 0; k < static_cast<int>(problem.set_limits.size()); ++k) {
    const auto& [vars, limit] = problem.set_limits[k];
    for (int i : vars) col_rows[i].push_back(m_pairs + k);
    c.row_ub[m_pairs + k] = limit;
  }
  c.row_lb.assign(c.m, -std::numeric_limits<double>::infinity());
  c.start.assign(c.n + 1, 0);
  for (int i = 0; i < c.n; ++i) {
    c.start[i + 1] = c.start[i] + static_cast<int>(col_rows[i].size());
    for (int r : col_rows[i]) {
      c.index.push_back(r);
      c.value.push_back(1.0);
    }
  }
  c.col_lb.assign(c.n, 0.0);
  c.col_ub.assign(c.n, 1.0);
  c.cost.resize(c.n);
  for (int i = 0; i < c.n; ++i) {
    if (fixed_to(problem, i, true)) c.col_lb[i] = 1.0;
    if (fixed_to(problem, i, false)) c.col_ub[i] = 0.0;
    c.cost[i] = -problem.weights[i];
  }
  return c;
}

template <class T>
const T* data_or_null(const std::vector<T>& v) {
  return v.empty() ? nullptr : v.data();
}

// The program as a CBC model with continuous columns (integers are set by the caller).
CbcModelPtr load_model(const PackingProblem& problem) {
  const ColumnMatrix c = column_matrix(problem);
  CbcModelPtr model(Cbc_newModel());
  if (!model) throw SolverError("CBC: could not create a model");
  Cbc_loadProblem(model.get(), c.n, c.m, c.start.data(), data_or_null(c.index),
                  data_or_null(c.value), c.col_lb.data(), c.col_ub.data(), c.cost.data(),
                  data_or_null(c.row_lb), data_or_null(c.row_ub));
  Cbc_setObjSense(model.get(), 1.0);
  return model;
}

struct ClpDeleter {
  void operator()(Clp_Simplex* m) const { Clp_deleteModel(m); }
};

}  // namespace

struct PackingRelaxationSolver::Model {
  std::unique_ptr<Clp_Simplex, ClpDeleter> clp;
  bool solved = false;
};

PackingRelaxationSolver::PackingRelaxationSolver(const PackingProblem& problem)
    : n_(static_cast<int>(problem.weights.size())) {
  conflict_adjacency(problem);
  const ColumnMatrix c = column_matrix(problem);
  model_ = std::make_unique<Model>();
  model_->clp.reset(Clp_newModel());
  Clp_Simplex* clp = model_->clp.get();
  if (!clp) throw SolverError("CLP: could not create a model");
  Clp_setLogLevel(clp, 0);
  Clp_loadProblem(clp, c.n, c.m, c.start.data(), data_or_null(c.index), data_or_null(c.value),
                  c.col_lb.data(), c.col_ub.data(), c.cost.data(), data_or_null(c.row_lb),
                  data_or_null(c.row_ub));
  Clp_setOptimizationDirection(clp, 1.0);
}

PackingRelaxationSolver::~PackingRelaxationSolver() = default;  // Model is complete here

void PackingRelaxationSolver::add_limit(const std::vector<int>& vars, int limit) {
  const std::vector<double> ones(vars.size(), 1.0);
  const double lower = -std::numeric_limits<double>::infinity();
  const double upper = limit;
  const CoinBigIndex starts[2] = {0, static_cast<CoinBigIndex>(vars.size())};
  Clp_addRows(model_->clp.get(), 1, &lower, &upper, starts, vars.data(), ones.data());
}

PackingRelaxation PackingRelaxationSolver::solve(double max_seconds) {
  const auto start = std::chrono::steady_clock::now();
  PackingRelaxation result;
  if (n_ == 0) {
    result.optimal = true;
    return result;
  }
  Clp_Simplex* clp = model_->clp.get();
  // CLP counts from this call; non-positive means no limit to it.
  Clp_setMaximumSeconds(clp, std::isfinite(max_seconds) ? std::max(max_seconds, 1e-3) : -1.0);
  // Dual simplex from the last basis: added rows keep it dual feasible.
  if (!model_->solved)
    Clp_initialSolve(clp);
  else
    Clp_dual(clp, 0);
  model_->solved = true;
  if (!Clp_isProvenOptimal(clp)) return result;
  result.optimal = true;
  const double* x = Clp_getColSolution(clp);
  result.x.assign(x, x + n_);
  for (double& v : result.x) v = std::clamp(v, 0.0, 1.0);
  result.objective = -Clp_getObjValue(clp);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

PackingResult solve_packing(const PackingProblem& problem, const PackingOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(problem.weights.size());
  const auto adj = conflict_adjacency(problem);

  PackingResult result;
  result.x = greedy_start(problem, adj);
  if (static_cast<int>(problem.start.size()) == n && is_feasible(problem, problem.start) &&
      objective_of(problem, problem.start) > objective_of(problem, result.x))
    result.x = problem.start;
  if (n == 0) {
    result.status = PackingStatus::kOptimal;
    return result;
  }
  if (!options.search) {
    result.objective = objective_of(problem, result.x);
    result.bound = 0;
    for (double w : problem.weights) result.bound += std::max(w, 0.0);
    result.status = PackingStatus::kTimeLimit;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
  const CbcModelPtr model = load_model(problem);
  for (int i = 0; i < n; ++i) Cbc_setInteger(model.get(), i);
  Cbc_setLogLevel(model.get(), options.log ? 1 : 0);
  Cbc_setMaximumSeconds(model.get(), options.time_limit_s);
  Cbc_setAllowableFractionGap(model.get(), options.relative_gap);
  Cbc_setParameter(model.get(), "threads", "0");  // no worker threads: deterministic, and nothing to fail to start
  Cbc_setParameter(model.get(), "preprocess", "off");
  {
    std::vector<int> idx(n);
    std::vector<double> val(n);
    for (int i = 0; i < n; ++i) {
      idx[i] = i;
      val[i] = result.x[i];
    }
    Cbc_setMIPStartI(model.get(), n, idx.data(), val.data());
  }

  ensure_headroom();  // CBC crashes where an allocation fails inside it
  Cbc_solve(model.get());
  const double* sol = Cbc_bestSolution(model.get());
  if (sol != nullptr) {
    std::vector<char> x(n);
    for (int i = 0; i < n; ++i) x[i] = sol[i] > 0.5 ? 1 : 0;
    // Keep CBC's answer only if it is feasible and at least as good as the start.
    if (is_feasible(problem, x) &&
        objective_of(problem, x) >= objective_of(problem, result.x) - 1e-12)
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
