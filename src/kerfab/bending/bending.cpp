#include "kerfab/bending/bending.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "kerfab/bending/odd_cycles.h"
#include "kerfab/bending/seams.h"
#include "kerfab/core/errors.h"

namespace kerfab {

std::string to_string(QuadKind kind) {
  switch (kind) {
    case QuadKind::kBending:
      return "bending";
    case QuadKind::kOneSided:
      return "one_sided";
    case QuadKind::kRigid:
      return "rigid";
  }
  return "unknown";
}

std::vector<double> edge_variances(const PolyMesh& quads, const TargetSurface& target,
                                   int samples) {
  std::vector<double> w(quads.n_edges(), 0.0);
  std::vector<double> d(samples);
  for (auto e : quads.edges()) {
    const auto h = quads.halfedge_handle(e, 0);
    const Vec3 a = to_eigen(quads.point(quads.from_vertex_handle(h)));
    const Vec3 b = to_eigen(quads.point(quads.to_vertex_handle(h)));
    double mean = 0;
    for (int i = 0; i < samples; ++i) {
      const double t = (i + 0.5) / samples;
      d[i] = target.signed_distance(a + t * (b - a));
      mean += d[i];
    }
    mean /= samples;
    double var = 0;
    for (double x : d) var += (x - mean) * (x - mean);
    w[e.idx()] = var / samples;
  }
  return w;
}

std::vector<QuadBending> classify_quads(const PolyMesh& quads, const std::vector<char>& bendable) {
  std::vector<QuadBending> out(quads.n_faces());
  for (auto f : quads.faces()) {
    const auto e = quad_edges(quads, f);
    for (int axis = 0; axis < 2; ++axis) {
      const int n = bendable[e[axis]] + bendable[e[axis + 2]];
      if (n == 2) out[f.idx()] = {QuadKind::kBending, axis};
      if (n == 1) out[f.idx()] = {QuadKind::kOneSided, axis};
    }
  }
  return out;
}

std::pair<int, int> count_aligned_edges(const PolyMesh& quads,
                                        const std::vector<QuadBending>& classes) {
  auto role = [&](OpenMesh::FaceHandle f, int edge) {
    const auto e = quad_edges(quads, f);
    const int k = static_cast<int>(std::find(e.begin(), e.end(), edge) - e.begin());
    return k % 2 == classes[f.idx()].axis;  // true: the edge is on the face's bending axis
  };
  int interior = 0, aligned = 0;
  for (auto e : quads.edges()) {
    if (quads.is_boundary(e)) continue;
    ++interior;
    const auto f0 = quads.face_handle(quads.halfedge_handle(e, 0));
    const auto f1 = quads.face_handle(quads.halfedge_handle(e, 1));
    if (classes[f0.idx()].kind == QuadKind::kRigid || classes[f1.idx()].kind == QuadKind::kRigid)
      continue;
    if (role(f0, e.idx()) == role(f1, e.idx())) ++aligned;
  }
  return {interior, aligned};
}

namespace {

// Rings around odd vertices up to this radius [edges], and moat growth up to this many steps:
// on spot_quadrangulated (96 odd vertices, seams 232 edges) the relaxation with these rings is
// within one edge of the optimum (radius 4: 1 edge, 10: exact but 10x slower to solve), and a
// few rounds of separation close the rest.
constexpr int kRingBallRadius = 4;
constexpr int kRingMoatSteps = 64;

// Cutting-plane rounds on \p relaxation: odd cycles violated by its optimum become set limits
// of the program. Stops when none is violated, when the relaxation proves the known selection
// of objective `known` optimal (all weights equal w: objectives are multiples of w, so a bound
// below known + w suffices), or after `budget_s` seconds in all (each simplex is stopped at what
// is left of them). Returns the time of the first relaxation solve, infinity if it did not
// finish in the budget, -1 if there was no budget; \p out_of_time: the rounds stopped because
// the budget ran out (not because they were done); \p last_x: the last relaxation optimum
// found (empty if none).
double separate_odd_cycles(PackingProblem& problem, PackingRelaxationSolver& relaxation,
                           BendingResult& r, double known, double budget_s, bool& out_of_time,
                           std::vector<double>& last_x) {
  out_of_time = false;
  const auto t0 = std::chrono::steady_clock::now();
  const auto [w_lo, w_hi] = std::minmax_element(problem.weights.begin(), problem.weights.end());
  const bool uniform = w_lo != problem.weights.end() && *w_hi - *w_lo <= 1e-12 * std::abs(*w_hi);
  const double proven_below = uniform ? known + *w_hi * (1 - 1e-6) : known + 1e-9 * std::abs(known);
  double first = -1;
  for (;;) {
    const double left =
        budget_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (left <= 0) {
      out_of_time = true;
      break;
    }
    const PackingRelaxation lp = relaxation.solve(left);
    if (first < 0) first = lp.optimal ? lp.seconds : std::numeric_limits<double>::infinity();
    if (!lp.optimal) {  // the cuts only help; CBC still solves the program
      out_of_time = true;
      break;
    }
    r.relaxation_bound = lp.objective;
    last_x = lp.x;
    if (lp.objective < proven_below) break;
    const auto cycles = violated_odd_cycles(problem.conflicts, lp.x, {});
    if (cycles.empty()) break;
    ++r.cut_rounds;
    for (const auto& c : cycles) {
      const int limit = (static_cast<int>(c.size()) - 1) / 2;
      relaxation.add_limit(c, limit);
      problem.set_limits.emplace_back(c, limit);
      ++r.separated_cuts;
    }
  }
  return first;
}

// A set limit whose sum at the relaxation optimum is this far below its limit is slack there.
constexpr double kSlack = 1e-6;

// Removes from \p problem the set limits from index \p first on (the odd cycles the rounds
// separated) that \p x (a relaxation optimum with all of them) leaves slack, and returns how
// many. Each is valid for every selection, so the program's optimum stays; and its
// relaxation's optimum stays too (\p x is still optimal without rows it does not meet). CBC
// solves the root relaxation afresh with every row it is given: on Amo's QuadriFlow mesh (1670
// edges) 10 rounds separate 3373 cycles, most of them slack at the last optimum, and CBC took
// 14 s to prove the start optimal with all of them, 2 s without the slack ones. The stars and
// rings stay: where no round separates anything the program is the same as before (leaving
// out slack rings too gave spot_quadrangulated at 200 mm another selection of the same
// objective, on which a part flattened inverted).
int drop_slack_cycles(PackingProblem& problem, std::size_t first, const std::vector<double>& x) {
  if (x.empty() || first >= problem.set_limits.size()) return 0;
  const auto slack = [&](const std::pair<std::vector<int>, int>& limit) {
    double sum = 0;
    for (int v : limit.first) sum += x[v];
    return sum < limit.second - kSlack;
  };
  const auto kept =
      std::remove_if(problem.set_limits.begin() + first, problem.set_limits.end(), slack);
  const int dropped = static_cast<int>(problem.set_limits.end() - kept);
  problem.set_limits.erase(kept, problem.set_limits.end());
  return dropped;
}

}  // namespace

BendingResult choose_bending_edges(const PolyMesh& quads, const TargetSurface& target,
                                   const BendingOptions& options) {
  if (!is_all_quads(quads)) throw InvalidInput("bending directions need an all-quad mesh");
  // Past 1000 the edges' own weights only break ties, and w0 ~ 1e25 and up aborts CLP (an
  // assertion on the objective's size; --alignment 1e300 crashed the run).
  if (!(options.alignment >= 0.0 && options.alignment <= kMaxAlignment))
    throw InvalidInput("--alignment must be in [0, " + std::to_string(int(kMaxAlignment)) + "]");
  if (options.edge_samples < 2) throw InvalidInput("--edge-samples must be >= 2");
  if (!(options.time_limit_s > 0.0)) throw InvalidInput("--ilp-time-limit must be > 0 s");
  if (!(options.relative_gap >= 0.0)) throw InvalidInput("--ilp-gap must be >= 0");

  const auto stage_start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_start).count();
  };
  BendingResult r;
  r.variance = edge_variances(quads, target, options.edge_samples);
  // Deviations below a micrometre-scale floor (1e-6 of the model's diagonal) are round-off of
  // the distance queries, not shape: count them as zero.
  const double floor = std::pow(1e-6 * bounding_box(quads).diagonal(), 2);
  for (double& w : r.variance)
    if (w < floor) w = 0.0;
  const double w_max =
      r.variance.empty() ? 0.0 : *std::max_element(r.variance.begin(), r.variance.end());
  // If no edge deviates from the target at all (a plane, or a quad mesh whose edges lie on the
  // target's triangles), all weights tie; any positive scale then gives the same program, and
  // the bias must stay positive so strips still form (paper Sec. 3.1).
  r.w0 = options.alignment * (w_max > 0.0 ? w_max : 1.0);

  PackingProblem problem;
  problem.weights.resize(quads.n_edges());
  for (std::size_t e = 0; e < r.variance.size(); ++e) problem.weights[e] = r.variance[e] + r.w0;
  for (auto f : quads.faces()) {
    const auto e = quad_edges(quads, f);
    for (int k = 0; k < 4; ++k) problem.conflicts.emplace_back(e[k], e[(k + 1) % 4]);
  }
  // Around an interior vertex of odd valence k its k edges form an odd cycle of conflicts
  // (consecutive ones share a quad corner), so at most (k-1)/2 of them can bend. These stars are
  // also odd_rings' rings of radius 0 below; the repeated rows are kept on purpose: the
  // relaxation is highly degenerate and which optimal vertex CLP returns steers the separation.
  // Without them spot_quadrangulated needs 6 rounds and is not proven within 60 s (13 s with).
  for (auto v : quads.vertices()) {
    if (quads.is_boundary(v) || quads.is_isolated(v)) continue;
    const int k = static_cast<int>(quads.valence(v));
    if (k % 2 == 0) continue;
    std::vector<int> around;
    for (auto e : quads.ve_range(v)) around.push_back(e.idx());
    problem.set_limits.emplace_back(std::move(around), (k - 1) / 2);
  }
  if (!options.guidance.empty()) {
    problem.fixed.assign(quads.n_edges(), std::nullopt);
    const int nv = static_cast<int>(quads.n_vertices());
    for (const auto& g : options.guidance) {
      std::string name = "(";  // built step by step: GCC 12 warns falsely on a + chain here
      name.append(std::to_string(g.v0)).append(", ").append(std::to_string(g.v1)).append(")");
      if (g.v0 < 0 || g.v1 < 0 || g.v0 >= nv || g.v1 >= nv)
        throw InvalidInput("guidance edge " + name + ": vertex index out of range 0.." +
                           std::to_string(nv - 1));
      const auto h = quads.find_halfedge(quads.vertex_handle(g.v0), quads.vertex_handle(g.v1));
      if (!h.is_valid())
        throw InvalidInput("guidance edge " + name + " is not an edge of the quad mesh");
      auto& slot = problem.fixed[quads.edge_handle(h).idx()];
      if (slot && *slot != g.bendable)
        throw InvalidInput("guidance edge " + name + " is forced both bendable and stiff");
      slot = g.bendable;
    }
    for (auto f : quads.faces()) {
      const auto e = quad_edges(quads, f);
      for (int k = 0; k < 4; ++k) {
        const auto& a = problem.fixed[e[k]];
        const auto& b = problem.fixed[e[(k + 1) % 4]];
        if (a && b && *a && *b)
          throw InvalidInput("guidance forces two consecutive edges of quad " +
                             std::to_string(f.idx()) +
                             " bendable; only opposite edges of a quad can bend together");
      }
    }
  }

  // Start and cuts from the seam structure (seams.h), then odd cycles separated from the
  // relaxation, before the branch and bound.
  const auto cuts_start = std::chrono::steady_clock::now();
  const SeamSelection seams = seam_selection(quads);
  problem.start = seams.bendable;
  r.odd_vertices = seams.odd_vertices;
  r.seam_edges = seams.seam_edges;
  r.seam_pairing_optimal = seams.pairing_optimal;
  for (std::size_t e = 0; e < seams.bendable.size(); ++e)
    r.start_objective += seams.bendable[e] ? problem.weights[e] : 0.0;
  for (auto& ring : odd_rings(quads, kRingBallRadius, kRingMoatSteps)) {
    const int limit = (static_cast<int>(ring.size()) - 1) / 2;
    problem.set_limits.emplace_back(std::move(ring), limit);
    ++r.ring_cuts;
  }
  // The time limit covers the whole stage: the weights and seams before, the cut rounds (at most
  // 30 % of it) and the branch and bound.
  PackingRelaxationSolver relaxation(problem);
  bool exhausted = false;
  std::vector<double> last_x;
  const std::size_t separated_from = problem.set_limits.size();
  const double first_lp =
      separate_odd_cycles(problem, relaxation, r, std::max(r.start_objective, 0.0),
                          0.3 * options.time_limit_s - elapsed(), exhausted, last_x);
  // Only where the separated cycles outnumber half the edges: CBC's root relaxation is then
  // mostly their rows (Amo 3373 for 1670 edges, fandisk's quads 1398 for 1528, each proven
  // with the same selection, sooner). With fewer, the time saved is small and the program is
  // left as it was, ties included: spot_quadrangulated at 250 mm (1200 cycles for 5856 edges)
  // took another selection of the same objective without its slack ones, and then held a
  // 3.7 mm border at a corner instead of jointing it.
  if (2 * (problem.set_limits.size() - separated_from) > problem.weights.size())
    r.slack_limits = drop_slack_cycles(problem, separated_from, last_x);
  r.cut_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - cuts_start).count();
  const double left = options.time_limit_s - elapsed();
  // CBC solves the root relaxation afresh before it first looks at its clock. Where that alone
  // would not fit in what is left (the relaxation here took first_lp, or did not finish in the
  // cut rounds' share), the branch and bound is not started: the start selection is kept, and
  // the relaxation, finished in what is left if need be, bounds it (spot with four Catmull-Clark
  // steps, 46,848 quads: one relaxation 28 s; CBC given 3 s took 33 s).
  // A large program whose cut rounds used their whole share has a root relaxation CBC solves
  // far more slowly than the first one here (it starts again with every cut added) and root
  // heuristics that do not look at the clock: Spot with four Catmull-Clark steps coarsened to
  // 7470 quads (14,940 edges): first relaxation 1.8 s, CBC's 25 s, then 60 s of heuristics —
  // the stage took 118 s of its 60. There the start selection is kept and the last relaxation
  // bounds it (CBC had found nothing better). Smaller programs go on to CBC as before: Amo
  // (1670 edges) and Spot with two steps (5856) also use the whole share and are then solved to
  // optimality within the limit.
  const bool large = problem.weights.size() > 10000;
  const bool search = (first_lp < 0 || left > 1.5 * first_lp) && !(large && exhausted);
  PackingResult solved =
      solve_packing(problem, {.time_limit_s = std::max(0.05 * options.time_limit_s, left),
                              .relative_gap = options.relative_gap,
                              .search = search});
  if (!search) {
    if (!std::isfinite(first_lp) && left > 0) {
      const PackingRelaxation lp = relaxation.solve(0.9 * left);
      if (lp.optimal) r.relaxation_bound = lp.objective;
    }
    if (r.relaxation_bound > 0) solved.bound = std::max(solved.objective, r.relaxation_bound);
  }
  r.bendable = solved.x;
  r.objective = solved.objective;
  r.bound = solved.bound;
  r.status = solved.status;
  r.solve_seconds = r.cut_seconds + solved.seconds;
  r.bendable_count = static_cast<int>(std::count(r.bendable.begin(), r.bendable.end(), 1));
  r.quads = classify_quads(quads, r.bendable);
  std::tie(r.interior_edges, r.aligned_edges) = count_aligned_edges(quads, r.quads);
  r.aligned_fraction =
      r.interior_edges ? static_cast<double>(r.aligned_edges) / r.interior_edges : 0.0;
  return r;
}

}  // namespace kerfab
