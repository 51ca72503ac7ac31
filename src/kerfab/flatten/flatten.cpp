#include "kerfab/flatten/flatten.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include "kerfab/core/errors.h"
#include "kerfab/core/parallel.h"

namespace kerfab {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

/// Corner angle at \p p between the directions to \p next and \p prev, counter-clockwise from
/// next to prev: in (0, pi) at a convex corner of a counter-clockwise polygon.
double corner_angle(const Vec2& p, const Vec2& next, const Vec2& prev) {
  const Vec2 u = next - p, v = prev - p;
  return std::atan2(cross2(u, v), u.dot(v));
}

double corner_angle_3d(const Vec3& p, const Vec3& next, const Vec3& prev) {
  const Vec3 u = next - p, v = prev - p;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

/// One patch as a small mesh over its own vertices.
struct LocalPatch {
  std::vector<Vec3> p3;
  std::vector<std::array<int, 4>> quads;
  std::vector<std::array<int, 2>> border;  // outline edges, in order around the patch
};

LocalPatch local_patch(const Strips& strips, const Patch& patch) {
  LocalPatch lp;
  for (int v : patch.local_vertices()) lp.p3.push_back(strips.vertices[v]);
  lp.quads = patch.local_quads();
  for (const OutlineEdge& e : patch.outline()) lp.border.push_back(e.v);
  return lp;
}

std::vector<Vec2> plane_coordinates(const std::vector<Vec3>& p3);

/// \p lp's vertices on its best-fit plane, turned and moved so that vertex 0 is at (0, 0) and
/// vertex 1 on the positive x axis, its quads counter-clockwise in total.
std::vector<Vec2> plane_guess(const LocalPatch& lp) {
  std::vector<Vec2> x = plane_coordinates(lp.p3);
  double area = 0;
  for (const auto& q : lp.quads)
    for (int c = 0; c < 4; ++c) area += 0.5 * cross2(x[q[c]], x[q[(c + 1) % 4]]);
  if (area < 0)
    for (Vec2& p : x) p.y() = -p.y();
  const Vec2 o = x[0], d = x[1] - x[0];
  const double a = d.norm() > 0 ? std::atan2(d.y(), d.x()) : 0.0;
  const Eigen::Rotation2Dd turn(-a);
  for (Vec2& p : x) p = turn * (p - o);
  return x;
}

/// Per vertex: whether it lies in a triangle of \p tris joined, side by side, to one at vertex 0
/// (the first such triangle's).
std::vector<char> determined_vertices(int n, const std::vector<std::array<int, 3>>& tris) {
  std::vector<int> up(tris.size());
  std::iota(up.begin(), up.end(), 0);
  auto root = [&](int i) {
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
  };
  std::map<std::pair<int, int>, int> side;  // first triangle on each side
  for (int t = 0; t < static_cast<int>(tris.size()); ++t)
    for (int m = 0; m < 3; ++m) {
      const int a = tris[t][m], b = tris[t][(m + 1) % 3];
      const auto [it, fresh] = side.emplace(std::minmax(a, b), t);
      if (!fresh) up[root(t)] = root(it->second);
    }
  std::vector<char> out(n, 0);
  int pinned = -1;
  for (int t = 0; t < static_cast<int>(tris.size()) && pinned < 0; ++t)
    if (std::find(tris[t].begin(), tris[t].end(), 0) != tris[t].end()) pinned = root(t);
  for (int t = 0; t < static_cast<int>(tris.size()); ++t)
    if (root(t) == pinned)
      for (int v : tris[t]) out[v] = 1;
  return out;
}

/// Least-squares conformal map of the triangulated patch, vertices 0 and 1 pinned at (0, 0) and
/// (|p1 - p0|, 0). Where the map leaves some vertices free (a vertex only in triangles of no
/// area, or a part of the patch joined to the rest only at a point: where a strip's rails touch,
/// it can turn and scale about that point), those are held, weakly, to the patch's best-fit
/// plane (plane_guess): the angle-length iteration that follows decides their place.
std::vector<Vec2> conformal_map(const LocalPatch& lp) {
  const int n = static_cast<int>(lp.p3.size());
  std::vector<Triplet> entries;
  int row = 0;
  // The triangles with an area, joined where they share a side: the map determines the vertices
  // of those joined to the pinned ruling's, and leaves the others free (a vertex only in
  // triangles of no area, or a part of the patch joined to the rest at a vertex or not at all).
  std::vector<std::array<int, 3>> tris;
  for (const auto& q : lp.quads)
    for (const std::array<int, 3> t :
         {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      const Vec3 &a = lp.p3[t[0]], &b = lp.p3[t[1]], &c = lp.p3[t[2]];
      const Vec3 normal = (b - a).cross(c - a);
      const double area = 0.5 * normal.norm();
      if (!(area > 1e-12)) continue;  // degenerate triangle: no conformality to ask for
      tris.push_back(t);
      const Vec3 e1 = (b - a).normalized(), e2 = normal.normalized().cross(e1);
      const std::array<Vec2, 3> x = {Vec2(0, 0), Vec2((b - a).norm(), 0),
                                     Vec2((c - a).dot(e1), (c - a).dot(e2))};
      const double w = std::sqrt(area);
      for (int m = 0; m < 3; ++m) {
        const Vec2 e = x[(m + 2) % 3] - x[(m + 1) % 3];
        const Vec2 g = Vec2(-e.y(), e.x()) / (2 * area);  // gradient of the hat function
        // u_x - v_y and u_y + v_x (Cauchy-Riemann), u at 2i, v at 2i + 1.
        entries.emplace_back(row, 2 * t[m], w * g.x());
        entries.emplace_back(row, 2 * t[m] + 1, -w * g.y());
        entries.emplace_back(row + 1, 2 * t[m], w * g.y());
        entries.emplace_back(row + 1, 2 * t[m] + 1, w * g.x());
      }
      row += 2;
    }
  SparseMatrix a(row, 2 * n);
  a.setFromTriplets(entries.begin(), entries.end());
  // Pinned values; the unknowns are the other 2n - 4 coordinates.
  const double len = (lp.p3[1] - lp.p3[0]).norm();
  Eigen::VectorXd pinned = Eigen::VectorXd::Zero(2 * n);
  pinned[2] = len;
  std::vector<int> free_index(2 * n, -1);
  int nfree = 0;
  for (int i = 4; i < 2 * n; ++i) free_index[i] = nfree++;
  std::vector<Triplet> free_entries;
  Eigen::VectorXd rhs = -(a * pinned);
  for (int k = 0; k < a.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(a, k); it; ++it)
      if (free_index[it.col()] >= 0)
        free_entries.emplace_back(it.row(), free_index[it.col()], it.value());
  SparseMatrix af(row, nfree);
  af.setFromTriplets(free_entries.begin(), free_entries.end());
  SparseMatrix normal = af.transpose() * af;
  Eigen::VectorXd b = af.transpose() * rhs;
  const std::vector<char> determined = determined_vertices(n, tris);
  bool free = std::find(determined.begin(), determined.end(), 0) != determined.end();
  // A millionth of the mean diagonal: the determined coordinates move by about as much.
  const double eps = 1e-6 * std::max(normal.diagonal().mean(), 1e-12);
  std::vector<Vec2> guess;
  auto pull_to_guess = [&](Eigen::VectorXd& rhs_of) {
    for (int i = 2; i < n; ++i)
      for (int k = 0; k < 2; ++k) rhs_of[free_index[2 * i + k]] += eps * guess[i][k];
  };
  Eigen::VectorXd with_guess = b;
  auto hold_to_guess = [&] {  // every free coordinate, weakly, to the plane guess
    free = true;
    guess = plane_guess(lp);
    for (int i = 2; i < n; ++i)
      for (int k = 0; k < 2; ++k)
        normal.coeffRef(free_index[2 * i + k], free_index[2 * i + k]) += eps;
    pull_to_guess(with_guess);
  };
  if (free) hold_to_guess();
  Eigen::SimplicialLDLT<SparseMatrix> solver(normal);
  // A pivot of about nothing: some freedom the sides did not show (Eigen's LDLT does not fail
  // on a zero pivot).
  auto singular = [&] {
    if (solver.info() != Eigen::Success) return true;
    const Eigen::VectorXd d = solver.vectorD();
    return d.size() > 0 && !(d.minCoeff() > 1e-12 * d.cwiseAbs().maxCoeff());
  };
  if (!free && singular()) {
    hold_to_guess();
    solver.compute(normal);
  }
  if (solver.info() != Eigen::Success) throw SolverError("conformal map: factorisation failed");
  Eigen::VectorXd z = solver.solve(with_guess);
  if (free) {
    // The plane guess in the map's own frame: the similarity (no reflection) that lays it best
    // onto the vertices the map determines, then solved again.
    auto at = [&](int i) {
      return i == 0   ? Vec2(0, 0)
             : i == 1 ? Vec2(len, 0)
                      : Vec2(z[free_index[2 * i]], z[free_index[2 * i + 1]]);
    };
    Vec2 cg = Vec2::Zero(), cz = Vec2::Zero();
    int m = 0;
    for (int i = 0; i < n; ++i)
      if (determined[i]) cg += guess[i], cz += at(i), ++m;
    cg /= m, cz /= m;
    double c = 0, s = 0, gg = 0;
    for (int i = 0; i < n; ++i)
      if (determined[i]) {
        const Vec2 g = guess[i] - cg, y = at(i) - cz;
        c += g.dot(y), s += cross2(g, y), gg += g.squaredNorm();
      }
    if (m > 0 && gg > 0) {
      const double scale = std::hypot(c, s) / gg, turn = std::atan2(s, c);
      const Eigen::Rotation2Dd r(turn);
      for (Vec2& g : guess) g = Vec2(scale * (r * (g - cg)) + cz);
      with_guess = b;
      pull_to_guess(with_guess);
      z = solver.solve(with_guess);
    }
  }
  std::vector<Vec2> out(n);
  out[0] = Vec2(0, 0);
  out[1] = Vec2(len, 0);
  for (int i = 2; i < n; ++i) out[i] = Vec2(z[free_index[2 * i]], z[free_index[2 * i + 1]]);
  return out;
}

/// A corner whose 2D angle is held to a target: at vertex \p at, counter-clockwise from the
/// direction to \p next to the direction to \p prev [rad].
struct Corner {
  int at = 0, next = 0, prev = 0;
  double target = 0;
};

/// Paper: quads of \p lp whose 3D corner angles fall short of 360 deg by more than
/// kTwistCrease (no flat quad meets them), as local vertex pairs along the shorter diagonal (the
/// other where that one's would leave a reflex corner; none where both would), with the quad's
/// signed fold across it (> 0: convex, seen from the side its corners turn counter-clockwise
/// around).
std::vector<Crease> twist_creases(const LocalPatch& lp) {
  std::vector<Crease> out;
  for (const auto& q : lp.quads) {
    std::array<Vec3, 4> p;
    for (int c = 0; c < 4; ++c) p[c] = lp.p3[q[c]];
    double sum = 0;
    bool degenerate = false;
    for (int c = 0; c < 4; ++c) {
      degenerate = degenerate || !((p[(c + 1) % 4] - p[c]).norm() > 0);
      sum += corner_angle_3d(p[c], p[(c + 1) % 4], p[(c + 3) % 4]);
    }
    if (degenerate || !(2 * M_PI - sum > kTwistCrease)) continue;
    // The shorter diagonal, else the other, where the corners at its ends (the sums of the two
    // triangles' angles there) stay convex: a reflex corner is no quad the flattening measures
    // (horse_quad in paper: a quad folded across its diagonal came out inverted, 114 deg off).
    auto convex_at_ends = [&](int d) {
      for (int end : {d, d + 2}) {
        const Vec3 &at = p[end], &next = p[(end + 1) % 4], &prev = p[(end + 3) % 4],
                   &across = p[(end + 2) % 4];
        if (!(corner_angle_3d(at, next, across) + corner_angle_3d(at, across, prev) <
              M_PI - kTwistCrease))
          return false;
      }
      return true;
    };
    int d = (p[2] - p[0]).norm() <= (p[3] - p[1]).norm() ? 0 : 1;
    if (!convex_at_ends(d)) d = 1 - d;
    if (!convex_at_ends(d)) continue;
    const Vec3 &a = p[d], &b = p[d + 1], &c = p[d + 2], &e = p[(d + 3) % 4];
    // Triangles (a, b, c) and (a, c, e) on either side of the diagonal a-c; convex where the
    // second one's far corner lies below the first one's plane.
    const Vec3 n1 = (b - a).cross(c - a), n2 = (c - a).cross(e - a);
    const double fold = std::atan2(n1.cross(n2).norm(), n1.dot(n2));
    out.push_back({{q[d], q[d + 2]}, n1.dot(e - a) < 0 ? fold : -fold});
  }
  return out;
}

/// Every quad's four corners, with their 3D angles as targets (of a quad creased along a
/// diagonal, one of \p creases, its two triangles' angles). A corner on a side of no length
/// (where a strip's rails meet, two vertices at one point) has no angle: it is left out, and
/// the side's length (0) holds its ends together.
std::vector<Corner> quad_corners(const LocalPatch& lp, const std::vector<Crease>& creases = {}) {
  std::set<std::pair<int, int>> creased;
  for (const Crease& c : creases) creased.insert(std::minmax(c.ends[0], c.ends[1]));
  std::vector<Corner> out;
  double longest = 0;
  for (const auto& q : lp.quads)
    for (int c = 0; c < 4; ++c)
      longest = std::max(longest, (lp.p3[q[(c + 1) % 4]] - lp.p3[q[c]]).norm());
  const double none = 1e-9 * longest;
  for (const auto& q : lp.quads) {
    // A quad creased along a diagonal is its two triangles: at the diagonal's ends a corner is
    // the sum of theirs, at the other two each one's own.
    int diagonal = -1;
    for (int d = 0; d < 2; ++d)
      if (creased.count(std::minmax(q[d], q[d + 2]))) diagonal = d;
    for (int c = 0; c < 4; ++c) {
      const Vec3 &p = lp.p3[q[c]], &next = lp.p3[q[(c + 1) % 4]], &prev = lp.p3[q[(c + 3) % 4]];
      if ((next - p).norm() <= none || (prev - p).norm() <= none) continue;
      double target = corner_angle_3d(p, next, prev);
      if (c % 2 == diagonal) {
        const Vec3& across = lp.p3[q[(c + 2) % 4]];
        target = corner_angle_3d(p, next, across) + corner_angle_3d(p, across, prev);
      }
      out.push_back({q[c], q[(c + 1) % 4], q[(c + 3) % 4], target});
    }
  }
  return out;
}

/// Eq. 2 as residuals r (energy = |r|^2) with their Jacobian: border edges held to their 3D
/// lengths, corners to their target angles. With \p wrapped an angle error is taken in
/// (-pi, pi] (an outline's corner may be reflex: its angle runs to 2 pi).
class AngleLengthEnergy {
 public:
  AngleLengthEnergy(const LocalPatch& lp, double lambda)
      : AngleLengthEnergy(lp, lambda, quad_corners(lp), false) {}
  AngleLengthEnergy(const LocalPatch& lp, double lambda, std::vector<Corner> corners, bool wrapped)
      : lp_(lp), corners_(std::move(corners)), wrapped_(wrapped) {
    double sum = 0;
    for (const auto& e : lp.border) {
      target_length_.push_back((lp.p3[e[1]] - lp.p3[e[0]]).norm());
      sum += target_length_.back();
    }
    mean_length_ = sum / std::max<std::size_t>(1, lp.border.size());
    w_length_ = std::sqrt(lambda) / mean_length_;
    w_angle_ = std::sqrt(1 - lambda);
  }
  int residual_count() const { return static_cast<int>(target_length_.size() + corners_.size()); }
  const std::vector<double>& target_lengths() const { return target_length_; }

  /// Corner \p c's angle error at \p x [rad].
  double angle_error(const std::vector<Vec2>& x, std::size_t c) const {
    const Corner& k = corners_[c];
    double e = corner_angle(x[k.at], x[k.next], x[k.prev]) - k.target;
    if (wrapped_) e = std::remainder(e, 2 * M_PI);
    return e;
  }
  /// The largest |angle error| over the corners at \p x [rad].
  double max_angle_error(const std::vector<Vec2>& x) const {
    double out = 0;
    for (std::size_t c = 0; c < corners_.size(); ++c)
      out = std::max(out, std::abs(angle_error(x, c)));
    return out;
  }

  Eigen::VectorXd residuals(const std::vector<Vec2>& x) const {
    Eigen::VectorXd r(residual_count());
    int k = 0;
    for (std::size_t e = 0; e < lp_.border.size(); ++e)
      r[k++] = w_length_ * ((x[lp_.border[e][1]] - x[lp_.border[e][0]]).norm() - target_length_[e]);
    for (std::size_t c = 0; c < corners_.size(); ++c) r[k++] = w_angle_ * angle_error(x, c);
    return r;
  }

  /// Jacobian with respect to all 2n coordinates (x at 2i, y at 2i + 1).
  SparseMatrix jacobian(const std::vector<Vec2>& x) const {
    std::vector<Triplet> t;
    int k = 0;
    for (const auto& e : lp_.border) {
      const Vec2 d = x[e[1]] - x[e[0]];
      const double len = d.norm();
      const Vec2 g = len > 0 ? Vec2(w_length_ * d / len) : Vec2(0, 0);
      for (int a = 0; a < 2; ++a) {
        t.emplace_back(k, 2 * e[1] + a, g[a]);
        t.emplace_back(k, 2 * e[0] + a, -g[a]);
      }
      ++k;
    }
    for (const Corner& c : corners_) {
      const int i = c.at, nx = c.next, pv = c.prev;
      const Vec2 u = x[nx] - x[i], v = x[pv] - x[i];
      const double uu = std::max(u.squaredNorm(), 1e-300), vv = std::max(v.squaredNorm(), 1e-300);
      const Vec2 gn = w_angle_ * Vec2(u.y(), -u.x()) / uu;
      const Vec2 gp = w_angle_ * Vec2(-v.y(), v.x()) / vv;
      for (int a = 0; a < 2; ++a) {
        t.emplace_back(k, 2 * nx + a, gn[a]);
        t.emplace_back(k, 2 * pv + a, gp[a]);
        t.emplace_back(k, 2 * i + a, -gn[a] - gp[a]);
      }
      ++k;
    }
    SparseMatrix j(residual_count(), 2 * static_cast<int>(x.size()));
    j.setFromTriplets(t.begin(), t.end());
    return j;
  }

 private:
  const LocalPatch& lp_;
  std::vector<Corner> corners_;
  bool wrapped_ = false;
  std::vector<double> target_length_;
  double mean_length_ = 1, w_length_ = 0, w_angle_ = 0;
};

/// Keeps the columns of the free coordinates: all but x0, y0 and y1 (rigid motion gauge).
SparseMatrix free_columns(const SparseMatrix& j, const std::vector<int>& free_index, int nfree) {
  std::vector<Triplet> t;
  for (int k = 0; k < j.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(j, k); it; ++it)
      if (free_index[it.col()] >= 0) t.emplace_back(it.row(), free_index[it.col()], it.value());
  SparseMatrix out(j.rows(), nfree);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

/// The Gauss-Newton damping, relative to J^T J's mean diagonal, at least and at most [-].
constexpr double kBaseDamping = 1e-12, kMaxDamping = 1e2;
/// Iterations of plain Gauss-Newton before the damping adapts (the strips' patches converge in
/// at most 4 to 10).
constexpr int kPlainIterations = 20;

struct Solve {
  int iterations = 0;
  double energy = 0;
  bool converged = false;
};

/// Gauss-Newton with backtracking line search, damped as in Levenberg-Marquardt where it stalls
/// (after kPlainIterations); stops when half the Newton decrement (-g^T d / 2 with g the
/// gradient of |r|^2) falls below the tolerance.
Solve minimise(const AngleLengthEnergy& energy, std::vector<Vec2>& x, const FlattenOptions& opt) {
  const int n = static_cast<int>(x.size());
  std::vector<int> free_index(2 * n, -1);
  int nfree = 0;
  for (int i = 0; i < 2 * n; ++i)
    if (i != 0 && i != 1 && i != 3) free_index[i] = nfree++;
  Solve s;
  Eigen::VectorXd r = energy.residuals(x);
  s.energy = r.squaredNorm();
  Eigen::SimplicialLDLT<SparseMatrix> solver;
  bool analysed = false;
  // Damping relative to J^T J's mean diagonal: a hair for the first kPlainIterations, then as
  // in Levenberg-Marquardt: ten times more after a step the line search cut short, a hundred
  // times more where it found no descent at all (and the step is tried again), ten times less
  // after a full step. Where J^T J is nearly singular, the Gauss-Newton step points far along a
  // direction the residuals barely see, the line search cuts it to a millionth, and the solver
  // crawls: a facet of the demo took all of its 1000 iterations at steps of 5e-7 and stopped
  // unconverged (energy 1.7e-5; damped, 2.4e-6 after 36 iterations).
  double relative_damping = kBaseDamping;
  for (s.iterations = 0; s.iterations < opt.max_iterations; ++s.iterations) {
    const SparseMatrix j = free_columns(energy.jacobian(x), free_index, nfree);
    SparseMatrix h = j.transpose() * j;
    const double damping = relative_damping * (h.diagonal().sum() / std::max(1, nfree) + 1e-30);
    for (int i = 0; i < nfree; ++i) h.coeffRef(i, i) += damping;
    if (!analysed) solver.analyzePattern(h), analysed = true;
    solver.factorize(h);
    if (solver.info() != Eigen::Success) break;
    const Eigen::VectorXd jr = j.transpose() * r;
    const Eigen::VectorXd d = solver.solve(-jr);
    const double decrement = -2.0 * jr.dot(d);  // -g^T d with g = 2 J^T r
    if (decrement / 2 < opt.tolerance) {
      s.converged = true;
      break;
    }
    double t = 1.0;
    std::vector<Vec2> trial(n);
    Eigen::VectorXd r_trial;
    bool accepted = false;
    for (int ls = 0; ls < 40; ++ls, t *= 0.5) {
      for (int i = 0; i < n; ++i) {
        trial[i] = x[i];
        for (int a = 0; a < 2; ++a)
          if (free_index[2 * i + a] >= 0) trial[i][a] += t * d[free_index[2 * i + a]];
      }
      r_trial = energy.residuals(trial);
      if (r_trial.squaredNorm() <= s.energy - 1e-4 * t * decrement) {
        accepted = true;
        break;
      }
    }
    if (!accepted && s.iterations >= kPlainIterations && relative_damping < kMaxDamping) {
      relative_damping = std::min(relative_damping * 100, kMaxDamping);  // a shorter, surer step
      continue;
    }
    if (!accepted) {  // no descent left at machine precision: as good as it gets
      s.converged = decrement / 2 < 1e3 * opt.tolerance + 1e-12 * s.energy;
      break;
    }
    if (s.iterations >= kPlainIterations)
      relative_damping = t < 1 ? std::min(relative_damping * 10, kMaxDamping)
                               : std::max(relative_damping * 0.1, kBaseDamping);
    x = trial;
    r = r_trial;
    const double before = s.energy;
    s.energy = r.squaredNorm();
    // Stationary: residuals that cannot vanish. (Not where a damped step was cut short: a
    // shorter one may still descend.)
    const bool damped_short =
        s.iterations >= kPlainIterations && t < 1 && relative_damping < kMaxDamping;
    if (!damped_short && before - s.energy <= 1e-12 * before) {
      s.converged = true;
      ++s.iterations;
      break;
    }
  }
  return s;
}

bool segments_cross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  auto orient = [](const Vec2& p, const Vec2& q, const Vec2& r) { return cross2(q - p, r - p); };
  const double scale = std::max({(b - a).norm(), (d - c).norm(), 1e-300});
  const double eps = 1e-12 * scale * scale;
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
               o4 = orient(c, d, b);
  if (((o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps)) &&
      ((o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps)))
    return true;
  // Touching or collinear overlap counts as crossing for an outline.
  auto on = [&](const Vec2& p, const Vec2& q, const Vec2& r, double o) {
    return std::abs(o) <= eps && (r - p).dot(r - q) <= 0;
  };
  return on(a, b, c, o1) || on(a, b, d, o2) || on(c, d, a, o3) || on(c, d, b, o4);
}

/// The quads' edges, each once, as (smaller, larger) local vertex.
std::vector<std::array<int, 2>> quad_edges(const LocalPatch& lp) {
  std::vector<std::array<int, 2>> out;
  for (const auto& q : lp.quads)
    for (int a = 0; a < 4; ++a)
      out.push_back({std::min(q[a], q[(a + 1) % 4]), std::max(q[a], q[(a + 1) % 4])});
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// Moves the 3D vertices so every quad edge (rail segment and ruling) takes its flat length:
/// Levenberg-Marquardt steps whose damping penalises each step's length, so the strip does not
/// drift along its free motions while the length error is driven to zero. Diagonals are left
/// free on purpose: a kerfed strip twists between rulings (paper Sec. 3.4), so its quads need
/// not stay planar; requiring the flat diagonals too would flatten every twisted quad.
std::vector<Vec3> deform_to_flat_metric(const LocalPatch& lp, const std::vector<Vec2>& x) {
  const std::vector<std::array<int, 2>> pairs = quad_edges(lp);
  const int n = static_cast<int>(lp.p3.size()), m = static_cast<int>(pairs.size());
  std::vector<double> target(m);
  double scale = 0;
  for (int k = 0; k < m; ++k) {
    target[k] = (x[pairs[k][1]] - x[pairs[k][0]]).norm();
    scale = std::max(scale, target[k]);
  }
  std::vector<Vec3> y = lp.p3;
  auto residuals = [&](const std::vector<Vec3>& p) {
    Eigen::VectorXd r(m);
    for (int k = 0; k < m; ++k) r[k] = (p[pairs[k][1]] - p[pairs[k][0]]).norm() - target[k];
    return r;
  };
  Eigen::VectorXd r = residuals(y);
  Eigen::SimplicialLDLT<SparseMatrix> solver;
  bool analysed = false;
  constexpr double kDamping = 1e-2;
  // Done once no edge is off its flat length by more than kLengthTolerance of the longest. One
  // or two steps reach a micrometre; after that the damped steps close the last digits by only
  // 12-27 % each (Spot's cage after three Catmull-Clark steps: 23 steps a strip on average to a
  // ten-billionth, 1.8 s of the flattening stage's 4.7 s, for a move 2 nm different; at a
  // millionth the move came out 1 % off).
  constexpr double kLengthTolerance = 1e-8;
  for (int it = 0; it < 60 && r.lpNorm<Eigen::Infinity>() > kLengthTolerance * scale; ++it) {
    std::vector<Triplet> t;
    for (int k = 0; k < m; ++k) {
      const Vec3 d = y[pairs[k][1]] - y[pairs[k][0]];
      const Vec3 g = d.norm() > 0 ? Vec3(d.normalized()) : Vec3::Zero();
      for (int a = 0; a < 3; ++a) {
        t.emplace_back(k, 3 * pairs[k][1] + a, g[a]);
        t.emplace_back(k, 3 * pairs[k][0] + a, -g[a]);
      }
    }
    SparseMatrix j(m, 3 * n);
    j.setFromTriplets(t.begin(), t.end());
    SparseMatrix h = j.transpose() * j;
    for (int i = 0; i < 3 * n; ++i) h.coeffRef(i, i) += kDamping;
    if (!analysed) solver.analyzePattern(h), analysed = true;
    solver.factorize(h);
    if (solver.info() != Eigen::Success) break;
    const Eigen::VectorXd d = solver.solve(-(j.transpose() * r));
    std::vector<Vec3> trial = y;
    for (int i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) trial[i][a] += d[3 * i + a];
    const Eigen::VectorXd rt = residuals(trial);
    if (!(rt.squaredNorm() < r.squaredNorm())) break;
    y = std::move(trial);
    r = rt;
  }
  return y;
}

/// A facet's corners lie near one plane (the strips put them there; a corner shared with another
/// facet lies between the two): that plane, in coordinates along its two main directions, is
/// where its flattening starts.
std::vector<Vec2> plane_coordinates(const std::vector<Vec3>& p3) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : p3) mean += p / static_cast<double>(p3.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : p3) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Vec3 u = eig.eigenvectors().col(2), w = eig.eigenvectors().col(1);
  std::vector<Vec2> out;
  for (const Vec3& p : p3) out.emplace_back((p - mean).dot(u), (p - mean).dot(w));
  return out;
}

/// Mirrors \p points where the quads of \p lp come out clockwise in total (a conformal map
/// reflected, or a facet's plane seen from behind): a wrong sign must never reach the cutter.
void make_quads_counter_clockwise(const LocalPatch& lp, std::vector<Vec2>& points) {
  double signed_area = 0;
  for (const auto& q : lp.quads)
    for (int c = 0; c < 4; ++c) signed_area += 0.5 * cross2(points[q[c]], points[q[(c + 1) % 4]]);
  if (signed_area < 0)
    for (auto& p : points) p.y() = -p.y();
}

/// Sets \p out's border length error (against \p lengths_3d, per outline edge of \p lp), its
/// areas and whether its outline is simple, from out.points.
void measure_shape(const LocalPatch& lp, const std::vector<double>& lengths_3d,
                   PatchFlattening& out) {
  for (std::size_t e = 0; e < lp.border.size(); ++e) {
    const double l = (out.points[lp.border[e][1]] - out.points[lp.border[e][0]]).norm();
    const double l3 = lengths_3d[e];
    if (l3 > 0)
      out.max_border_length_error_rel =
          std::max(out.max_border_length_error_rel, std::abs(l - l3) / l3);
  }
  for (const auto& q : lp.quads) {
    const Vec3 &a = lp.p3[q[0]], &b = lp.p3[q[1]], &c = lp.p3[q[2]], &d = lp.p3[q[3]];
    out.area_3d += 0.5 * ((b - a).cross(c - a).norm() + (c - a).cross(d - a).norm());
    for (int j = 0; j < 4; ++j)
      out.area_2d += 0.5 * cross2(out.points[q[j]], out.points[q[(j + 1) % 4]]);
  }
  std::vector<int> outline;
  for (const auto& e : lp.border) outline.push_back(e[0]);
  out.outline_simple = is_simple_polygon(out.points, outline);
}

/// A facet cut along its outline alone may come out at most this many times its quads' area
/// [-] (outline_flattening).
constexpr double kMostOutlineArea = 2.0;

/// flatten_facet_by_outline() on the patch \p lp, from \p start (the facet on its plane,
/// counter-clockwise). Empty where the outline is not one loop through distinct vertices.
std::optional<PatchFlattening> outline_flattening(const LocalPatch& lp,
                                                  const std::vector<Vec2>& start,
                                                  const FlattenOptions& opt) {
  const int n = static_cast<int>(lp.p3.size()), m = static_cast<int>(lp.border.size());
  if (m < 3) return std::nullopt;
  std::vector<int> ring_of(n, -1);
  for (int k = 0; k < m; ++k) {
    if (lp.border[k][1] != lp.border[(k + 1) % m][0] || ring_of[lp.border[k][0]] >= 0)
      return std::nullopt;
    ring_of[lp.border[k][0]] = k;
  }
  std::vector<double> intrinsic(m, 0.0);  // the facet's angle at each outline corner [rad]
  for (const Corner& c : quad_corners(lp))
    if (ring_of[c.at] >= 0) intrinsic[ring_of[c.at]] += c.target;
  LocalPatch ring;
  std::vector<Corner> corners;
  std::vector<Vec2> x;
  for (int k = 0; k < m; ++k) {
    ring.p3.push_back(lp.p3[lp.border[k][0]]);
    ring.border.push_back({k, (k + 1) % m});
    corners.push_back({k, (k + 1) % m, (k + m - 1) % m, intrinsic[k]});
    x.push_back(start[lp.border[k][0]]);
  }
  const AngleLengthEnergy energy(ring, std::max(opt.lambda, 0.9999), corners, true);
  FlattenOptions own = opt;
  own.max_iterations *= 10;
  PatchFlattening out;
  out.initial_energy = energy.residuals(x).squaredNorm();
  const Solve s = minimise(energy, x, own);
  out.iterations = s.iterations;
  out.energy = s.energy;
  out.converged = s.converged;
  out.max_angle_error = energy.max_angle_error(x);
  // Inner vertices: each the mean of its quad-edge neighbours, the outline held.
  out.points.assign(n, Vec2::Zero());
  std::vector<int> inner(n, -1);
  int ni = 0;
  for (int v = 0; v < n; ++v) {
    if (ring_of[v] >= 0)
      out.points[v] = x[ring_of[v]];
    else
      inner[v] = ni++;
  }
  if (ni > 0) {
    const std::vector<std::array<int, 2>> edges = quad_edges(lp);
    std::vector<Triplet> t;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ni, 2);
    for (const auto& e : edges)
      for (int side = 0; side < 2; ++side) {
        const int a = e[side], b = e[1 - side];
        if (inner[a] < 0) continue;
        t.emplace_back(inner[a], inner[a], 1.0);
        if (inner[b] >= 0)
          t.emplace_back(inner[a], inner[b], -1.0);
        else
          rhs.row(inner[a]) += out.points[b].transpose();
      }
    SparseMatrix l(ni, ni);
    l.setFromTriplets(t.begin(), t.end());
    Eigen::SimplicialLDLT<SparseMatrix> solver(l);
    if (solver.info() != Eigen::Success) return std::nullopt;
    const Eigen::MatrixXd z = solver.solve(rhs);
    for (int v = 0; v < n; ++v)
      if (inner[v] >= 0) out.points[v] = Vec2(z(inner[v], 0), z(inner[v], 1));
  }
  out.inverted_quads = count_inverted_quads(out.points, lp.quads);
  measure_shape(lp, energy.target_lengths(), out);
  // Each corner within its limit, the errors can still add up along a long side: a 250 mm rod
  // 4.2 mm across, whose facet took two of its sides (1556 mm^2), came out as a lens 44 mm
  // wide (7768 mm^2), no corner more than 0.46 deg off. A plate that large is no stand-in for
  // the surface it replaces. (The facets so cut on the shared meshes: 0.39 to 1.49 times
  // their quads' area.)
  if (out.area_2d > kMostOutlineArea * out.area_3d) return std::nullopt;
  return out;
}

/// \p lp of \p patch flattened, its quads creased along \p creases.
PatchFlattening flatten_local(const LocalPatch& lp, const Patch& patch, const FlattenOptions& opt,
                              std::vector<Crease> creases) {
  PatchFlattening out;
  out.creases = std::move(creases);
  out.points = patch.flat ? plane_coordinates(lp.p3) : conformal_map(lp);
  // The conformal map does not come out reflected for consistently oriented input.
  make_quads_counter_clockwise(lp, out.points);
  // A facet's corners may sit off its plane where it meets another facet: its border lengths
  // (which its neighbours keep) come first, its inner angles only hold it in shape.
  const AngleLengthEnergy energy(lp, patch.flat ? std::max(opt.lambda, 0.9999) : opt.lambda,
                                 quad_corners(lp, out.creases), false);
  out.initial_energy = energy.residuals(out.points).squaredNorm();
  // Border lengths as in 3D for a facet too: its mating strips' borders keep theirs.
  // (Gauss-Newton converges only linearly there: the residuals do not vanish.)
  FlattenOptions own = opt;
  if (patch.flat) own.max_iterations *= 10;
  const Solve s = minimise(energy, out.points, own);
  out.iterations = s.iterations;
  out.energy = s.energy;
  out.converged = s.converged;
  out.inverted_quads = count_inverted_quads(out.points, lp.quads);
  if (patch.flat && lp.quads.size() == 1 && out.inverted_quads > 0) {
    const auto& q = lp.quads[0];
    if (const auto built = convex_quad({lp.p3[q[0]], lp.p3[q[1]], lp.p3[q[2]], lp.p3[q[3]]})) {
      for (int j = 0; j < 4; ++j) out.points[q[j]] = (*built)[j];
      out.energy = energy.residuals(out.points).squaredNorm();
      out.inverted_quads = count_inverted_quads(out.points, lp.quads);
    }
  }
  out.max_angle_error = energy.max_angle_error(out.points);
  measure_shape(lp, energy.target_lengths(), out);
  return out;
}

PatchFlattening flatten_one(const Strips& strips, const Patch& patch, const FlattenOptions& opt) {
  const LocalPatch lp = local_patch(strips, patch);
  PatchFlattening out = flatten_local(lp, patch, opt, {});
  // Paper: where the strip flattens more than kCreaseNeeded off, its twisted quads are creased
  // (kept where that flattens it closer).
  if (opt.crease_twisted && !patch.flat && out.max_angle_error > kCreaseNeeded) {
    std::vector<Crease> creases = twist_creases(lp);
    if (!creases.empty()) {
      PatchFlattening creased = flatten_local(lp, patch, opt, std::move(creases));
      if (creased.max_angle_error < out.max_angle_error) out = std::move(creased);
    }
  }
  if (opt.mimic_3d) out.deformed_3d = deform_to_flat_metric(lp, out.points);
  return out;
}

/// Border pieces: every outline edge of every patch is assigned to the coarse edge it lies on;
/// two patch sides on one coarse edge mate.
void measure_borders(const Strips& strips, Flattening& flat) {
  struct Side {
    int patch;
    double l2, l3;
  };
  std::map<std::pair<int, int>, Side> sides;  // (coarse edge, patch * 4 + which side)
  for (std::size_t p = 0; p < strips.patches.size(); ++p) {
    const Patch& patch = strips.patches[p];
    const auto& x = flat.patches[p].points;
    const auto lv = patch.local_vertices();
    for (const OutlineEdge& e : patch.outline()) {
      Side& s = sides
                    .try_emplace({e.coarse_edge, static_cast<int>(p) * 4 + e.side},
                                 Side{static_cast<int>(p), 0, 0})
                    .first->second;
      const int a = e.v[0], b = e.v[1];
      s.l2 += (x[b] - x[a]).norm();
      s.l3 += (strips.vertices[lv[b]] - strips.vertices[lv[a]]).norm();
    }
  }
  std::map<int, std::vector<Side>> by_edge;
  for (const auto& [key, side] : sides) by_edge[key.first].push_back(side);
  std::map<std::pair<int, int>, SharedBorder> shared;
  for (const auto& [edge, list] : by_edge) {
    if (list.size() != 2) continue;  // on the mesh boundary (or an interior ruling: none here)
    BorderPiece piece;
    piece.edge = edge;
    // Order the two sides by patch id so each pair of patches has one key.
    const bool swap = list[1].patch < list[0].patch;
    const Side& a = swap ? list[1] : list[0];
    const Side& b = swap ? list[0] : list[1];
    piece.patches = {a.patch, b.patch};
    piece.length_3d = std::max(a.l3, b.l3);
    piece.length_2d = {a.l2, b.l2};
    if (piece.length_3d > 0)
      flat.max_mating_mismatch_rel =
          std::max(flat.max_mating_mismatch_rel, std::abs(a.l2 - b.l2) / piece.length_3d);
    SharedBorder& s = shared[{a.patch, b.patch}];
    s.patches = piece.patches;
    ++s.pieces;
    s.length_3d += piece.length_3d;
    s.length_2d[0] += a.l2;
    s.length_2d[1] += b.l2;
    flat.pieces.push_back(piece);
  }
  for (const auto& [key, s] : shared) {
    flat.borders.push_back(s);
    if (s.length_3d > 0)
      flat.max_shared_border_mismatch_rel =
          std::max(flat.max_shared_border_mismatch_rel,
                   std::abs(s.length_2d[0] - s.length_2d[1]) / s.length_3d);
  }
}

}  // namespace

std::optional<PatchFlattening> flatten_facet_by_outline(const Strips& strips, int patch,
                                                        const FlattenOptions& opt) {
  if (patch < 0 || patch >= static_cast<int>(strips.patches.size()) || !strips.patches[patch].flat)
    return std::nullopt;
  const LocalPatch lp = local_patch(strips, strips.patches[patch]);
  std::vector<Vec2> start = plane_coordinates(lp.p3);
  make_quads_counter_clockwise(lp, start);
  auto out = outline_flattening(lp, start, opt);
  if (out && opt.mimic_3d) out->deformed_3d = deform_to_flat_metric(lp, out->points);
  return out;
}

std::optional<std::array<Vec2, 4>> convex_quad(const std::array<Vec3, 4>& p) {
  std::array<double, 4> side{}, angle3{};
  for (int j = 0; j < 4; ++j) {
    side[j] = (p[(j + 1) % 4] - p[j]).norm();
    angle3[j] = corner_angle_3d(p[j], p[(j + 1) % 4], p[(j + 3) % 4]);
  }
  std::optional<std::array<Vec2, 4>> best;
  double best_error = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2; ++k) {  // the diagonal from corner k to corner k + 2
    const double a = side[k], b = side[(k + 1) % 4], c = side[(k + 2) % 4], d = side[(k + 3) % 4];
    const double lo = std::max(std::abs(a - b), std::abs(c - d)), hi = std::min(a + b, c + d);
    if (!(hi > lo)) continue;
    constexpr int kSamples = 256;
    const double own = (p[(k + 2) % 4] - p[k]).norm();  // the 3D diagonal: exact when planar
    for (int i = 0; i <= kSamples; ++i) {
      const double e = i == kSamples ? own : lo + (hi - lo) * (i + 0.5) / kSamples;
      if (!(e > lo && e < hi)) continue;
      // Corner k at the origin, corner k + 2 on the x axis; k + 1 below, k + 3 above (ccw).
      const double x1 = (a * a - b * b + e * e) / (2 * e), x3 = (d * d - c * c + e * e) / (2 * e);
      std::array<Vec2, 4> q;
      q[k] = Vec2(0, 0);
      q[(k + 2) % 4] = Vec2(e, 0);
      q[(k + 1) % 4] = Vec2(x1, -std::sqrt(std::max(0.0, a * a - x1 * x1)));
      q[(k + 3) % 4] = Vec2(x3, std::sqrt(std::max(0.0, d * d - x3 * x3)));
      double error = 0;
      bool convex = true;
      for (int j = 0; j < 4; ++j) {
        const double angle = corner_angle(q[j], q[(j + 1) % 4], q[(j + 3) % 4]);
        convex = convex && angle > 0 && angle < M_PI;
        error = std::max(error, std::abs(angle - angle3[j]));
      }
      if (convex && error < best_error) best_error = error, best = q;
    }
  }
  return best;
}

std::vector<Vec2> flat_outline(const Strips& strips, const Flattening& flat, int patch) {
  std::vector<Vec2> out;
  for (const OutlineEdge& e : strips.patches[patch].outline())
    out.push_back(flat.patches[patch].points[e.v[0]]);
  double area = 0;
  for (std::size_t i = 0; i < out.size(); ++i) area += cross2(out[i], out[(i + 1) % out.size()]);
  if (area < 0) std::reverse(out.begin(), out.end());
  return out;
}

int count_inverted_quads(const std::vector<Vec2>& points,
                         const std::vector<std::array<int, 4>>& quads) {
  int count = 0;
  for (const auto& q : quads) {
    bool inverted = false;
    for (int j = 0; j < 4; ++j) {
      const double a = corner_angle(points[q[j]], points[q[(j + 1) % 4]], points[q[(j + 3) % 4]]);
      if (!(a > 0 && a < M_PI)) inverted = true;
    }
    count += inverted ? 1 : 0;
  }
  return count;
}

bool is_simple_polygon(const std::vector<Vec2>& x, const std::vector<int>& outline) {
  const int m = static_cast<int>(outline.size());
  for (int i = 0; i < m; ++i) {
    const Vec2 &a = x[outline[i]], &b = x[outline[(i + 1) % m]];
    for (int j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;  // adjacent around the loop
      const Vec2 &c = x[outline[j]], &d = x[outline[(j + 1) % m]];
      if (std::max(a.x(), b.x()) < std::min(c.x(), d.x()) ||
          std::max(c.x(), d.x()) < std::min(a.x(), b.x()) ||
          std::max(a.y(), b.y()) < std::min(c.y(), d.y()) ||
          std::max(c.y(), d.y()) < std::min(a.y(), b.y()))
        continue;
      if (segments_cross(a, b, c, d)) return false;
    }
  }
  return true;
}

Flattening flatten_patches(const Strips& strips, const FlattenOptions& options) {
  if (!(options.lambda >= 0 && options.lambda <= 1))
    throw InvalidInput("--flatten-lambda must be in [0, 1]");
  if (options.max_iterations < 1) throw InvalidInput("flatten: max_iterations must be >= 1");
  if (!(options.tolerance > 0)) throw InvalidInput("flatten: tolerance must be > 0");
  if (!(options.max_angle_error > 0 && options.max_angle_error <= M_PI))
    throw InvalidInput("flatten: max_angle_error must be in (0, pi]");
  Flattening flat;
  const int np = static_cast<int>(strips.patches.size());
  flat.patches.resize(np);
  for_each_index(np, options.threads > 0 ? options.threads : hardware_threads(),
                 [&](int p) { flat.patches[p] = flatten_one(strips, strips.patches[p], options); });
  summarise_flattening(strips, flat);
  return flat;
}

void summarise_flattening(const Strips& strips, Flattening& flat) {
  flat.max_angle_error = flat.max_border_length_error_rel = 0;
  flat.inverted_quads = flat.non_simple_outlines = flat.unconverged = 0;
  for (const auto& p : flat.patches) {
    flat.max_angle_error = std::max(flat.max_angle_error, p.max_angle_error);
    flat.max_border_length_error_rel =
        std::max(flat.max_border_length_error_rel, p.max_border_length_error_rel);
    flat.inverted_quads += p.inverted_quads;
    flat.non_simple_outlines += p.outline_simple ? 0 : 1;
    flat.unconverged += p.converged ? 0 : 1;
  }
  flat.pieces.clear();
  flat.borders.clear();
  flat.max_mating_mismatch_rel = flat.max_shared_border_mismatch_rel = 0;
  measure_borders(strips, flat);
}

TriangleMesh patch_triangles(const Strips& strips, const Flattening& flat, bool deformed) {
  TriangleMesh out;
  for (std::size_t p = 0; p < strips.patches.size(); ++p) {
    const Patch& patch = strips.patches[p];
    const int base = static_cast<int>(out.vertices.size());
    if (deformed && !flat.patches[p].deformed_3d.empty()) {
      out.vertices.insert(out.vertices.end(), flat.patches[p].deformed_3d.begin(),
                          flat.patches[p].deformed_3d.end());
    } else if (deformed) {
      const auto moved = deform_to_flat_metric(local_patch(strips, patch), flat.patches[p].points);
      out.vertices.insert(out.vertices.end(), moved.begin(), moved.end());
    } else {
      for (int v : patch.local_vertices()) out.vertices.push_back(strips.vertices[v]);
    }
    for (const auto& q : patch.local_quads()) {
      out.triangles.push_back({base + q[0], base + q[1], base + q[2]});
      out.triangles.push_back({base + q[0], base + q[2], base + q[3]});
    }
  }
  return out;
}

}  // namespace kerfab
