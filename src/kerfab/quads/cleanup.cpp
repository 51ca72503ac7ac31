#include "kerfab/quads/cleanup.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>

namespace kerfab::quads {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinRotatedCorner = 20 * kPi / 180;   // quads made by a rotation
constexpr double kMinCollapsedCorner = 10 * kPi / 180;  // quads around a merged vertex
constexpr int kMaxPasses = 30;
constexpr int kWanderRounds = 60;
constexpr int kMaxValence = 6;  // more quads at a vertex leave corners under 50 degrees

using Key = std::pair<int, int>;
Key key(int a, int b) { return std::minmax(a, b); }

class Cleaner {
 public:
  Cleaner(std::vector<std::vector<int>> faces, std::vector<Vec3> points,
          const std::vector<char>& pinned, const std::function<bool(int, int)>& is_feature,
          const std::function<Vec3(const Vec3&)>& normal_at)
      : points_(std::move(points)), pinned_(pinned), is_feature_(is_feature),
        normal_at_(normal_at) {
    for (const auto& f : faces) faces_.push_back({f[0], f[1], f[2], f[3]});
    alive_.assign(faces_.size(), 1);
    pinned_.resize(points_.size(), 0);
  }

  /// Two searches from the same mesh, greedy passes in mesh order and by largest gain (which
  /// does better differs from mesh to mesh; on a grid with one edge rotated wrongly only the
  /// second rotates it back), each with random plateau moves; the lower energy is kept.
  CleanupResult run() {
    const auto faces = faces_;
    const auto alive = alive_;
    const auto points = points_;
    const auto pinned = pinned_;
    by_gain_ = false;
    CleanupResult in_order = search();
    const double e_order = energy_of(in_order);
    faces_ = faces;
    alive_ = alive;
    points_ = points;
    pinned_ = pinned;
    by_gain_ = true;
    CleanupResult by_gain = search();
    return energy_of(by_gain) < e_order - 1e-9 ? by_gain : in_order;
  }

 private:
  double energy_of(const CleanupResult& r) {
    faces_.clear();
    for (const auto& f : r.faces) faces_.push_back({f[0], f[1], f[2], f[3]});
    alive_.assign(faces_.size(), 1);
    return energy();
  }

  CleanupResult search() {
    CleanupResult r;
    greedy(r);
    // Defects next to each other but not cancelling (a valence 3 beside a 5, a dislocation)
    // only move under a change of zero gain: such moves are taken at random (fixed seed) for
    // a while, each followed by the greedy passes, and the best mesh seen is kept.
    double best = energy();
    auto best_faces = faces_;
    auto best_alive = alive_;
    auto best_points = points_;
    CleanupResult best_r = r;
    std::uint64_t random = 0x9E3779B97F4A7C15ull;
    for (int round = 0; round < kWanderRounds; ++round) {
      index();
      std::vector<char> touched(faces_.size(), 0);
      for (const EdgeFaces& e : edges_) {
        random ^= random << 13;
        random ^= random >> 7;
        random ^= random << 17;
        const auto fs = faces_of(e);
        if (fs.size() == 2 && !touched[fs[0]] && !touched[fs[1]] && (random & 1) &&
            try_rotate(e.edge, fs[0], fs[1], touched, -1e-9, true) != 0)
          ++r.rotations;
      }
      greedy(r);
      const double e = energy();
      if (e < best - 1e-9) {
        best = e;
        best_faces = faces_;
        best_alive = alive_;
        best_points = points_;
        best_r = r;
      }
    }
    faces_ = std::move(best_faces);
    alive_ = std::move(best_alive);
    points_ = std::move(best_points);
    r = best_r;
    for (std::size_t f = 0; f < faces_.size(); ++f)
      if (alive_[f]) r.faces.push_back({faces_[f][0], faces_[f][1], faces_[f][2], faces_[f][3]});
    r.points = points_;
    return r;
  }

  /// Sum of squared valence defects over the mesh.
  double energy() {
    index();
    double e = 0;
    for (std::size_t v = 0; v < neighbours_.size(); ++v)
      if (!neighbours_[v].empty()) e += defect(static_cast<int>(v), valence(static_cast<int>(v)));
    return e;
  }

  /// Changes of positive gain until there are none.
  void greedy(CleanupResult& r) {
    for (int pass = 0; pass < kMaxPasses; ++pass) {
      index();
      std::vector<char> touched(faces_.size(), 0);
      bool changed = false;
      // Doublets first (an inner vertex of two quads: a flat corner in each).
      for (int v = 0; v < static_cast<int>(points_.size()); ++v)
        if (valence(v) == 2 && !border_[v] && try_remove_doublet(v, touched)) {
          ++r.collapses;
          changed = true;
        }
      if (!by_gain_) {  // collapses (two defects at once) in mesh order, then rotations
        for (int f = 0; f < static_cast<int>(faces_.size()); ++f)
          if (alive_[f] && !touched[f] && try_collapse(f, touched, true) > 0) {
            ++r.collapses;
            changed = true;
          }
        index();
        std::fill(touched.begin(), touched.end(), 0);
        touched.resize(faces_.size(), 0);
        for (const EdgeFaces& e : edges_)
          if (const auto fs = faces_of(e);
              fs.size() == 2 && !touched[fs[0]] && !touched[fs[1]] &&
              try_rotate(e.edge, fs[0], fs[1], touched, 1e-9, true) > 0) {
            ++r.rotations;
            changed = true;
          }
        if (!changed) break;
        continue;
      }
      // Collapses and rotations, the largest gain first.
      index();
      std::fill(touched.begin(), touched.end(), 0);
      touched.resize(faces_.size(), 0);
      struct Candidate {
        double gain;
        int face;  // a collapse of this face, or -1: a rotation of `edge`
        Key edge;
        int f1, f2;
      };
      std::vector<Candidate> candidates;
      for (int f = 0; f < static_cast<int>(faces_.size()); ++f)
        if (alive_[f])
          if (const double g = try_collapse(f, touched, false); g > 0)
            candidates.push_back({g, f, {}, -1, -1});
      for (const EdgeFaces& e : edges_)
        if (const auto fs = faces_of(e); fs.size() == 2)
          if (const double g = try_rotate(e.edge, fs[0], fs[1], touched, 1e-9, false); g > 0)
            candidates.push_back({g, -1, e.edge, fs[0], fs[1]});
      std::stable_sort(candidates.begin(), candidates.end(),
                       [](const Candidate& x, const Candidate& y) { return x.gain > y.gain; });
      for (const Candidate& c : candidates) {
        if (c.face >= 0) {
          if (alive_[c.face] && !touched[c.face] && try_collapse(c.face, touched, true) > 0) {
            ++r.collapses;
            changed = true;
          }
        } else if (!touched[c.f1] && !touched[c.f2] &&
                   try_rotate(c.edge, c.f1, c.f2, touched, 1e-9, true) > 0) {
          ++r.rotations;
          changed = true;
        }
      }
      if (!changed) break;
    }
  }

  /// Edges with their faces (sorted by edge, faces ascending) and every vertex's neighbours
  /// (sorted), from the live faces. Called once per pass: flat sorted arrays, reused from pass
  /// to pass, instead of a tree of nodes (a 10,000-quad mesh is indexed thousands of times).
  void index() {
    scratch_.clear();
    for (int f = 0; f < static_cast<int>(faces_.size()); ++f) {
      if (!alive_[f]) continue;
      for (int i = 0; i < 4; ++i)
        scratch_.push_back({key(faces_[f][i], faces_[f][(i + 1) % 4]), f});
    }
    std::sort(scratch_.begin(), scratch_.end());
    edges_.clear();
    edge_face_list_.clear();
    neighbours_.resize(points_.size());
    for (auto& ring : neighbours_) ring.clear();
    border_.assign(points_.size(), 0);
    for (std::size_t i = 0; i < scratch_.size();) {
      const Key e = scratch_[i].first;
      const int begin = static_cast<int>(edge_face_list_.size());
      for (; i < scratch_.size() && scratch_[i].first == e; ++i)
        edge_face_list_.push_back(scratch_[i].second);
      const int end = static_cast<int>(edge_face_list_.size());
      edges_.push_back({e, begin, end});
      neighbours_[e.first].push_back(e.second);
      if (e.second != e.first) neighbours_[e.second].push_back(e.first);
      if (end - begin == 1) border_[e.first] = border_[e.second] = 1;
    }
    for (auto& ring : neighbours_) std::sort(ring.begin(), ring.end());
  }

  struct EdgeFaces {
    Key edge;
    int begin, end;  // its faces: edge_face_list_[begin, end)
  };
  std::span<const int> faces_of(const EdgeFaces& e) const {
    return {edge_face_list_.data() + e.begin, static_cast<std::size_t>(e.end - e.begin)};
  }
  const EdgeFaces* find_edge(int a, int b) const {
    const Key k = key(a, b);
    const auto it = std::lower_bound(edges_.begin(), edges_.end(), k,
                                     [](const EdgeFaces& e, const Key& x) { return e.edge < x; });
    return it != edges_.end() && it->edge == k ? &*it : nullptr;
  }

  /// Sorted neighbour lists, as sets.
  static bool ring_has(const std::vector<int>& ring, int v) {
    return std::binary_search(ring.begin(), ring.end(), v);
  }
  static void ring_insert(std::vector<int>& ring, int v) {
    const auto it = std::lower_bound(ring.begin(), ring.end(), v);
    if (it == ring.end() || *it != v) ring.insert(it, v);
  }
  static void ring_erase(std::vector<int>& ring, int v) {
    const auto it = std::lower_bound(ring.begin(), ring.end(), v);
    if (it != ring.end() && *it == v) ring.erase(it);
  }

  int valence(int v) const { return static_cast<int>(neighbours_[v].size()); }
  int ideal(int v) const { return border_[v] ? 3 : 4; }
  /// An irregular vertex counts 1, plus a quarter of its squared defect (two vertices of
  /// valence 5 are worse than one of 6, a 6 worse than a 5).
  double defect(int v, int val) const {
    const int d = val - ideal(v);
    return (d != 0 ? 1.0 : 0.0) + 0.25 * d * d;
  }
  bool has_edge(int a, int b) const { return find_edge(a, b) != nullptr; }

  /// The quad \p q is convex, faces the surface's way and has no corner under \p min_corner.
  bool sound(const std::array<int, 4>& q, double min_corner) const {
    std::array<Vec3, 4> p;
    Vec3 centre = Vec3::Zero();
    for (int i = 0; i < 4; ++i) centre += p[i] = points_[q[i]];
    const Vec3 n = normal_at_(centre / 4);
    for (int i = 0; i < 4; ++i) {
      const Vec3 u = p[(i + 1) % 4] - p[i], w = p[(i + 3) % 4] - p[i];
      if (!(u.cross(w).dot(n) > 0)) return false;
      const double angle = std::atan2(u.cross(w).norm(), u.dot(w));
      if (!(angle >= min_corner)) return false;
    }
    return true;
  }

  /// The quad \p f rotated so that it starts with \p a followed by \p b.
  std::array<int, 4> starting(int f, int a, int b) const {
    const auto& q = faces_[f];
    for (int i = 0; i < 4; ++i)
      if (q[i] == a && q[(i + 1) % 4] == b) return {q[i], q[(i + 1) % 4], q[(i + 2) % 4], q[(i + 3) % 4]};
    return {-1, -1, -1, -1};
  }

  /// The gain of rotating the edge between quads \p f1 and \p f2 (0: none above
  /// \p min_gain, or not sound); rotated if \p apply.
  double try_rotate(const Key& edge, int f1, int f2, std::vector<char>& touched,
                    double min_gain, bool apply) {
    int a = edge.first, b = edge.second;
    if (border_[a] && border_[b]) return 0;
    if (is_feature_(a, b)) return 0;
    std::array<int, 4> q1 = starting(f1, a, b);
    if (q1[0] < 0) {
      std::swap(a, b);
      q1 = starting(f1, a, b);
    }
    const std::array<int, 4> q2 = starting(f2, b, a);
    if (q1[0] < 0 || q2[0] < 0) return 0;
    const int c = q1[2], d = q1[3], e = q2[2], f = q2[3];
    const std::array<int, 6> hex{b, c, d, a, e, f};
    for (int i = 0; i < 6; ++i)
      for (int j = i + 1; j < 6; ++j)
        if (hex[i] == hex[j]) return 0;
    if (valence(a) - 1 < (border_[a] ? 2 : 3) || valence(b) - 1 < (border_[b] ? 2 : 3))
      return 0;
    const double before = defect(a, valence(a)) + defect(b, valence(b));
    struct Option {
      int x, y;
      std::array<int, 4> n1, n2;
    };
    const Option options[2] = {{c, e, {c, d, a, e}, {e, f, b, c}},
                               {d, f, {d, a, e, f}, {f, b, c, d}}};
    double best_gain = min_gain;
    int best = -1;
    for (int o = 0; o < 2; ++o) {
      const auto& [x, y, n1, n2] = options[o];
      if (has_edge(x, y) || valence(x) + 1 > kMaxValence || valence(y) + 1 > kMaxValence) continue;
      const double gain = before + defect(x, valence(x)) + defect(y, valence(y)) -
                          (defect(a, valence(a) - 1) + defect(b, valence(b) - 1) +
                           defect(x, valence(x) + 1) + defect(y, valence(y) + 1));
      if (gain > best_gain && sound(n1, kMinRotatedCorner) && sound(n2, kMinRotatedCorner)) {
        best_gain = gain;
        best = o;
      }
    }
    if (best < 0) return 0;
    if (!apply) return std::max(best_gain, 1e-12);
    faces_[f1] = options[best].n1;
    faces_[f2] = options[best].n2;
    touched[f1] = touched[f2] = 1;
    // Neighbourhoods for later candidates of this pass (those touching f1, f2 are skipped).
    ring_erase(neighbours_[a], b);
    ring_erase(neighbours_[b], a);
    ring_insert(neighbours_[options[best].x], options[best].y);
    ring_insert(neighbours_[options[best].y], options[best].x);
    for (int v : hex)
      for (int g : faces_around(v)) touched[g] = 1;
    return std::max(best_gain, 1e-12);
  }

  std::vector<int> faces_around(int v) const {
    std::vector<int> out;
    for (int w : neighbours_[v])
      if (const EdgeFaces* e = find_edge(v, w))
        for (int g : faces_of(*e)) out.push_back(g);
    return out;
  }

  /// The two quads around inner vertex \p v of valence 2 merged into one (when it is convex).
  bool try_remove_doublet(int v, std::vector<char>& touched) {
    std::vector<int> around = faces_around(v);
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    if (around.size() != 2 || touched[around[0]] || touched[around[1]]) return false;
    const auto& q1 = faces_[around[0]];
    int i = 0;
    while (i < 4 && q1[i] != v) ++i;
    if (i == 4) return false;
    const int a = q1[(i + 1) % 4], x = q1[(i + 2) % 4], b = q1[(i + 3) % 4];
    const std::array<int, 4> q2 = starting(around[1], v, b);
    if (q2[0] < 0 || q2[3] != a) return false;
    const int y = q2[2];
    if (x == y || valence(a) - 1 < (border_[a] ? 2 : 3) || valence(b) - 1 < (border_[b] ? 2 : 3))
      return false;
    const std::array<int, 4> merged{a, x, b, y};
    if (!sound(merged, 0.0)) return false;
    faces_[around[0]] = merged;
    alive_[around[1]] = 0;
    touched[around[0]] = touched[around[1]] = 1;
    for (int w : {a, b}) ring_erase(neighbours_[w], v);
    neighbours_[v].clear();
    return true;
  }

  /// The gain of collapsing quad \p f along a diagonal of two valence-3 (or so) corners (0:
  /// none, or not sound); collapsed if \p apply.
  double try_collapse(int f, std::vector<char>& touched, bool apply) {
    const auto q = faces_[f];
    for (int i = 0; i < 2; ++i) {
      const int a = q[i], b = q[i + 1], c = q[(i + 2) % 4], d = q[(i + 3) % 4];
      if (border_[a] || border_[c] || (pinned_[a] && pinned_[c])) continue;
      if (has_edge(a, c) || has_edge(b, d)) continue;
      // Link: a and c share exactly b and d as neighbours.
      int shared = 0;
      for (int w : neighbours_[a]) shared += ring_has(neighbours_[c], w) ? 1 : 0;
      if (shared != 2) continue;
      const int merged = valence(a) + valence(c) - 2;
      if (merged > kMaxValence) continue;
      if (valence(b) - 1 < (border_[b] ? 2 : 3) || valence(d) - 1 < (border_[d] ? 2 : 3))
        continue;
      const double gain = defect(a, valence(a)) + defect(c, valence(c)) +
                          defect(b, valence(b)) + defect(d, valence(d)) -
                          (defect(a, merged) + defect(b, valence(b) - 1) +
                           defect(d, valence(d) - 1));
      if (gain <= 1e-9) continue;
      std::vector<int> around = faces_around(c);
      std::sort(around.begin(), around.end());
      around.erase(std::unique(around.begin(), around.end()), around.end());
      for (int g : faces_around(a)) around.push_back(g);
      bool fresh = true;
      for (int g : around) fresh = fresh && !touched[g];
      if (!fresh) continue;
      const Vec3 at = pinned_[a] ? points_[a] : pinned_[c] ? points_[c]
                                                          : Vec3(0.5 * (points_[a] + points_[c]));
      const Vec3 old_a = points_[a];
      points_[a] = at;
      std::vector<std::pair<int, std::array<int, 4>>> changed;
      bool ok = true;
      std::sort(around.begin(), around.end());
      around.erase(std::unique(around.begin(), around.end()), around.end());
      for (int g : around) {
        if (g == f) continue;
        std::array<int, 4> n = faces_[g];
        for (int& v : n) v = v == c ? a : v;
        ok = ok && sound(n, kMinCollapsedCorner);
        changed.push_back({g, n});
      }
      if (!ok || !apply) {
        points_[a] = old_a;
        if (ok) return gain;
        continue;
      }
      pinned_[a] = pinned_[a] || pinned_[c];
      for (auto& [g, n] : changed) {
        faces_[g] = n;
        touched[g] = 1;
      }
      alive_[f] = 0;
      touched[f] = 1;
      // Neighbourhoods: c's neighbours move to a; b and d lose one.
      for (int w : neighbours_[c]) {
        ring_erase(neighbours_[w], c);
        if (w != a) {
          ring_insert(neighbours_[w], a);
          ring_insert(neighbours_[a], w);
        }
      }
      neighbours_[c].clear();
      return gain;
    }
    return 0;
  }

  std::vector<std::array<int, 4>> faces_;
  std::vector<char> alive_;
  bool by_gain_ = false;
  std::vector<Vec3> points_;
  std::vector<char> pinned_;
  const std::function<bool(int, int)>& is_feature_;
  const std::function<Vec3(const Vec3&)>& normal_at_;
  std::vector<std::pair<Key, int>> scratch_;  // (edge, face) per side, for index()
  std::vector<EdgeFaces> edges_;
  std::vector<int> edge_face_list_;
  std::vector<std::vector<int>> neighbours_;
  std::vector<char> border_;
};

}  // namespace

CleanupResult clean_up_valences(std::vector<std::vector<int>> faces, std::vector<Vec3> points,
                                const std::vector<char>& pinned,
                                const std::function<bool(int, int)>& is_feature,
                                const std::function<Vec3(const Vec3&)>& normal_at) {
  return Cleaner(std::move(faces), std::move(points), pinned, is_feature, normal_at).run();
}

int untangle(PolyMesh& q, const std::function<bool(const PolyMesh&, OpenMesh::FaceHandle)>& sound,
             const std::function<Vec3(const Vec3&)>& onto) {
  std::vector<OpenMesh::FaceHandle> stuck;
  for (auto f : q.faces()) {
    if (sound(q, f)) continue;
    bool fixed = false;
    for (auto v : q.fv_range(f)) {
      if (fixed || q.is_boundary(v)) continue;
      const Vec3 old = to_eigen(q.point(v));
      Vec3 mean = Vec3::Zero();
      int n = 0;
      for (auto w : q.vv_range(v)) {
        mean += to_eigen(q.point(w));
        ++n;
      }
      mean /= std::max(n, 1);
      for (double t : {0.25, 0.5, 1.0}) {
        q.set_point(v, to_openmesh(onto(old + t * (mean - old))));
        bool ok = true;
        for (auto g : q.vf_range(v)) ok = ok && sound(q, g);
        if (ok) {
          fixed = true;
          break;
        }
        q.set_point(v, to_openmesh(old));
      }
    }
    if (!fixed) stuck.push_back(f);
  }
  // A corner moved for a later quad may have freed an earlier one (a move is taken only where
  // every quad round it is then sound, so no sound quad is made bad).
  return static_cast<int>(
      std::count_if(stuck.begin(), stuck.end(), [&](auto f) { return !sound(q, f); }));
}

}  // namespace kerfab::quads
