#include "kerfab/adapters/matching_program.h"

#include <coin/Cbc_C_Interface.h>

#include <memory>
#include <string>

#include "kerfab/core/errors.h"
#include "kerfab/core/headroom.h"

namespace kerfab {
namespace {

struct CbcDeleter {
  void operator()(Cbc_Model* m) const { Cbc_deleteModel(m); }
};

}  // namespace

MatchingResult min_cost_perfect_matching(int nodes, const std::vector<MatchingPair>& pairs,
                                         double time_limit_s) {
  MatchingResult result;
  if (nodes == 0) {
    result.optimal = true;
    return result;
  }
  const int n = static_cast<int>(pairs.size());
  // Column-wise: pair k has a 1 in the rows of its two nodes; every row equals 1.
  std::vector<int> start(n + 1), index(2 * n);
  std::vector<double> value(2 * n, 1.0), lb(n, 0.0), ub(n, 1.0), cost(n);
  for (int k = 0; k < n; ++k) {
    const auto& p = pairs[k];
    if (p.a < 0 || p.b < 0 || p.a >= nodes || p.b >= nodes || p.a == p.b)
      throw InvalidInput("matching program: pair (" + std::to_string(p.a) + ", " +
                         std::to_string(p.b) + ") is not two distinct nodes in range");
    start[k] = 2 * k;
    index[2 * k] = p.a;
    index[2 * k + 1] = p.b;
    cost[k] = p.cost;
  }
  start[n] = 2 * n;
  std::vector<double> row_lb(nodes, 1.0), row_ub(nodes, 1.0);
  std::unique_ptr<Cbc_Model, CbcDeleter> model(Cbc_newModel());
  if (!model) throw SolverError("CBC: could not create a model");
  Cbc_loadProblem(model.get(), n, nodes, start.data(), n ? index.data() : nullptr,
                  n ? value.data() : nullptr, lb.data(), ub.data(), cost.data(), row_lb.data(),
                  row_ub.data());
  for (int k = 0; k < n; ++k) Cbc_setInteger(model.get(), k);
  Cbc_setObjSense(model.get(), 1.0);
  Cbc_setLogLevel(model.get(), 0);
  Cbc_setMaximumSeconds(model.get(), time_limit_s);
  Cbc_setParameter(model.get(), "threads", "0");  // no worker threads: deterministic, and nothing to fail to start
  ensure_headroom();  // CBC crashes where an allocation fails inside it
  Cbc_solve(model.get());
  const double* y = Cbc_bestSolution(model.get());
  if (y == nullptr) return result;
  result.mate.assign(nodes, -1);
  for (int k = 0; k < n; ++k)
    if (y[k] > 0.5) {
      result.mate[pairs[k].a] = pairs[k].b;
      result.mate[pairs[k].b] = pairs[k].a;
      result.cost += pairs[k].cost;
    }
  for (int m : result.mate)
    if (m < 0) {
      result.mate.clear();
      return result;
    }
  result.optimal = Cbc_isProvenOptimal(model.get()) != 0;
  return result;
}

}  // namespace kerfab
