#include "kerfab/bending/odd_cycles.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <set>

namespace kerfab {
namespace {

// Among closed walks of equal LP cost the search prefers fewer arcs: shorter cycles make
// stronger, sparser inequalities.
constexpr double kArcTieBreak = 1e-7;

// Reduces an odd closed walk (w[0..k-1], w[k] = w[0] implied) to a simple odd cycle whose nodes
// are a subset of the walk's. A repeated node splits the walk into two closed walks whose
// lengths sum to the odd total, so one of them is odd; keep that one and repeat.
std::vector<int> simple_odd_cycle(std::vector<int> walk) {
  for (;;) {
    assert(walk.size() % 2 == 1 && "walk must be odd");
    int a = -1, b = -1;
    {
      std::vector<std::pair<int, int>> order;  // (node, position), to find a repeat
      order.reserve(walk.size());
      for (int i = 0; i < static_cast<int>(walk.size()); ++i) order.emplace_back(walk[i], i);
      std::sort(order.begin(), order.end());
      for (std::size_t i = 1; i < order.size(); ++i)
        if (order[i].first == order[i - 1].first) {
          a = order[i - 1].second;
          b = order[i].second;
          break;
        }
    }
    if (a < 0) return walk;
    std::vector<int> inner(walk.begin() + a, walk.begin() + b);  // closed walk of length b - a
    if ((b - a) % 2 == 1) {
      walk = std::move(inner);
    } else {
      std::vector<int> outer(walk.begin(), walk.begin() + a);
      outer.insert(outer.end(), walk.begin() + b, walk.end());
      walk = std::move(outer);
    }
  }
}

}  // namespace

std::vector<std::vector<int>> violated_odd_cycles(const std::vector<std::pair<int, int>>& conflicts,
                                                  const std::vector<double>& x,
                                                  const OddCycleOptions& options) {
  const int n = static_cast<int>(x.size());
  std::vector<std::vector<std::pair<int, double>>> adj(n);
  {
    std::vector<std::pair<int, int>> pairs;
    pairs.reserve(conflicts.size());
    for (auto [a, b] : conflicts) pairs.emplace_back(std::min(a, b), std::max(a, b));
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (auto [a, b] : pairs) {
      const double cost = std::max(0.0, 1.0 - x[a] - x[b]) + kArcTieBreak;
      adj[a].emplace_back(b, cost);
      adj[b].emplace_back(a, cost);
    }
  }
  // A violated cycle has sum of (1 - x_i - x_j) over its arcs = |C| - 2 sum x < 1 - 2
  // min_violation.
  const double cutoff = 1.0 - 2.0 * options.min_violation;

  // Start from the most fractional variables first; integral ones lie on no violated cycle
  // (a violated cycle needs a fractional variable).
  std::vector<int> starts;
  for (int i = 0; i < n; ++i)
    if (x[i] > 1e-6 && x[i] < 1.0 - 1e-6 && !adj[i].empty()) starts.push_back(i);
  std::stable_sort(starts.begin(), starts.end(),
                   [&](int a, int b) { return std::abs(x[a] - 0.5) < std::abs(x[b] - 0.5); });

  std::vector<std::vector<int>> cycles;
  std::set<std::vector<int>> found;  // sorted node sets, to drop duplicates
  std::vector<char> covered(n, 0);
  // Double cover: node 2i + p is variable i reached by a walk of parity p.
  std::vector<double> dist(2 * n, std::numeric_limits<double>::infinity());
  std::vector<int> pred(2 * n, -1);
  std::vector<int> touched;
  using Item = std::pair<double, int>;
  for (int s : starts) {
    if (static_cast<int>(cycles.size()) >= options.max_cycles) break;
    if (covered[s]) continue;
    for (int v : touched) {
      dist[v] = std::numeric_limits<double>::infinity();
      pred[v] = -1;
    }
    touched.clear();
    std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
    dist[2 * s] = 0;
    touched.push_back(2 * s);
    heap.emplace(0.0, 2 * s);
    const int target = 2 * s + 1;
    while (!heap.empty()) {
      const auto [d, u] = heap.top();
      heap.pop();
      if (d > dist[u]) continue;
      if (d >= cutoff) break;
      if (u == target) break;
      const int i = u / 2, p = u % 2;
      for (const auto& [j, c] : adj[i]) {
        const int v = 2 * j + (1 - p);
        const double nd = d + c;
        if (nd < dist[v]) {
          if (!std::isfinite(dist[v])) touched.push_back(v);
          dist[v] = nd;
          pred[v] = u;
          heap.emplace(nd, v);
        }
      }
    }
    if (!(dist[target] < cutoff)) continue;
    std::vector<int> walk;  // s ... back to s (exclusive), odd number of arcs
    for (int v = target; v != 2 * s; v = pred[v]) walk.push_back(v / 2);
    std::reverse(walk.begin(), walk.end());  // ends with s
    std::vector<int> cycle = simple_odd_cycle(std::move(walk));
    if (cycle.size() < 3) continue;
    double sum = 0;
    for (int i : cycle) sum += x[i];
    if (sum <= (static_cast<double>(cycle.size()) - 1) / 2 + options.min_violation) continue;
    std::vector<int> key = cycle;
    std::sort(key.begin(), key.end());
    if (!found.insert(key).second) continue;
    for (int i : cycle) covered[i] = 1;
    cycles.push_back(std::move(cycle));
  }
  return cycles;
}

}  // namespace kerfab
