#include "kerfab/quads/bridges.h"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <set>
#include <utility>

namespace kerfab::quads {
namespace {

using Key = std::pair<int, int>;
Key key(int a, int b) { return std::minmax(a, b); }

constexpr double kQuadCost = 1.0;    // a quad split in two
constexpr double kTurnCost = 3.0;    // a quad split in three (one more irregular vertex)
constexpr double kBorderCost = 1.0;  // a row ending on the border instead of a triangle
constexpr int kMaxValence = 6;       // no turn adds a seventh edge to a corner

/// One face of a row: the edge it is entered by (index of its first corner; -1 for the
/// triangle the row starts from) and the edge it is left by (-1 for the triangle it ends in).
struct Step {
  int face, entry, exit;
};

struct Row {
  double cost = std::numeric_limits<double>::infinity();
  std::vector<Step> steps;
};

/// Faces on each edge, with the index of the edge's first corner in the face.
std::map<Key, std::vector<std::pair<int, int>>> edge_faces(
    const std::vector<std::vector<int>>& faces) {
  std::map<Key, std::vector<std::pair<int, int>>> at;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    const int k = static_cast<int>(faces[f].size());
    for (int i = 0; i < k; ++i) at[key(faces[f][i], faces[f][(i + 1) % k])].push_back({f, i});
  }
  return at;
}

/// The cheapest row from triangle \p t to another triangle or to the border (Dijkstra over
/// faces, each entered once).
/// A triangle's own corner at the middle of its crossed edge is flat: such an edge must not be
/// a feature or border edge, whose middle cannot move off the line (\p feature).
Row cheapest_row(const std::vector<std::vector<int>>& faces,
                 const std::map<Key, std::vector<std::pair<int, int>>>& at, int t,
                 const std::function<bool(int, int)>& feature, const std::vector<int>& valence) {
  const int nf = static_cast<int>(faces.size());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(nf, inf);
  std::vector<int> prev(nf, -1), prev_exit(nf, -1), entry(nf, -1);
  std::vector<char> settled(nf, 0);
  struct End {
    double cost = std::numeric_limits<double>::infinity();
    int face = -1, exit = -1;  // the last face crossed and the edge it is left by
    int triangle = -1, triangle_entry = -1;  // -1: the row ends on the border
  } best;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  dist[t] = 0;
  queue.push({0.0, t});
  while (!queue.empty()) {
    const auto [cost, f] = queue.top();
    queue.pop();
    if (settled[f] || cost > dist[f]) continue;
    settled[f] = 1;
    if (cost >= best.cost) break;
    const int k = static_cast<int>(faces[f].size());
    for (int b = 0; b < k; ++b) {
      if (f != t && b == entry[f]) continue;
      // A turn joins the quad's centre to the corner facing the turn, one more edge there.
      double turn = 0;
      if (f != t && (b - entry[f] + 4) % 4 != 2) {
        const int facing = (b - entry[f] + 4) % 4 == 1 ? faces[f][(entry[f] + 3) % 4]
                                                       : faces[f][(entry[f] + 2) % 4];
        if (valence[facing] >= kMaxValence) continue;
        turn = kTurnCost + std::max(0, valence[facing] - 3);
      }
      const int x = faces[f][b], y = faces[f][(b + 1) % k];
      const auto& across = at.at(key(x, y));
      const std::pair<int, int>* other = nullptr;
      for (const auto& fi : across)
        if (fi.first != f) other = &fi;
      if (f == t && (!other || feature(x, y))) continue;
      if (!other) {  // the border
        if (cost + turn + kBorderCost < best.cost) best = {cost + turn + kBorderCost, f, b, -1, -1};
        continue;
      }
      const auto [g, gi] = *other;
      if (settled[g] || g == t) continue;
      if (faces[g].size() == 3) {
        // Two triangles side by side would share the middle as a doublet (two corners
        // summing to 360 degrees, one of them reflex): a row crosses at least one quad.
        if (f != t && cost + turn < best.cost && !feature(x, y)) best = {cost + turn, f, b, g, gi};
        continue;
      }
      const double next = cost + turn + kQuadCost;
      if (next < dist[g]) {
        dist[g] = next;
        prev[g] = f;
        prev_exit[g] = b;
        entry[g] = gi;
        queue.push({next, g});
      }
    }
  }
  Row row;
  if (best.face < 0) return row;
  row.cost = best.cost;
  if (best.triangle >= 0) row.steps.push_back({best.triangle, best.triangle_entry, -1});
  for (int f = best.face, exit = best.exit; f >= 0; exit = prev_exit[f], f = prev[f])
    row.steps.push_back({f, f == t ? -1 : entry[f], exit});
  std::reverse(row.steps.begin(), row.steps.end());
  return row;
}

}  // namespace

BridgeResult bridge_triangles(std::vector<std::vector<int>> faces, int vertex_count,
                              const std::function<bool(int, int)>& is_feature) {
  BridgeResult r;
  std::set<Key> feature_halves;  // halves of split feature edges (new vertex ids)
  auto feature = [&](int a, int b) {
    if (a < vertex_count && b < vertex_count) return is_feature(a, b);
    return feature_halves.count(key(a, b)) > 0;
  };
  const int max_rows = static_cast<int>(faces.size());
  for (int round = 0; round <= max_rows; ++round) {
    std::vector<int> triangles;
    for (int f = 0; f < static_cast<int>(faces.size()); ++f)
      if (faces[f].size() == 3) triangles.push_back(f);
    if (triangles.empty()) {
      r.complete = true;
      break;
    }
    const auto at = edge_faces(faces);
    std::vector<int> valence(vertex_count + r.added.size(), 0);
    for (const auto& [e, fs] : at) {
      ++valence[e.first];
      ++valence[e.second];
    }
    Row best;
    for (int t : triangles) {
      Row row = cheapest_row(faces, at, t, feature, valence);
      if (row.cost < best.cost) best = std::move(row);
    }
    if (best.steps.empty()) break;  // a triangle with nothing to pair with: not complete

    // The middles of the crossed edges, then the faces of the row replaced.
    std::map<Key, int> middle;
    auto middle_of = [&](int a, int b) {
      const auto [it, added] = middle.emplace(key(a, b), vertex_count + static_cast<int>(r.added.size()));
      if (added) {
        const bool on_feature = feature(a, b);
        r.added.push_back({{a, b, 0, 0}, 2, on_feature});
        if (on_feature) {
          feature_halves.insert(key(a, it->second));
          feature_halves.insert(key(it->second, b));
        }
      }
      return it->second;
    };
    std::vector<std::pair<int, std::vector<std::vector<int>>>> replaced;
    for (const Step& s : best.steps) {
      const std::vector<int>& p = faces[s.face];
      const int k = static_cast<int>(p.size());
      auto at_ = [&](int i) { return p[((i % k) + k) % k]; };
      std::vector<std::vector<int>> now;
      if (k == 3) {  // a triangle at either end: the middle of its crossed edge added
        const int i = s.entry >= 0 ? s.entry : s.exit;
        now.push_back({at_(i), middle_of(at_(i), at_(i + 1)), at_(i + 1), at_(i + 2)});
      } else {
        const int a = s.entry, b = s.exit;
        const int ma = middle_of(at_(a), at_(a + 1)), mb = middle_of(at_(b), at_(b + 1));
        const int d = (b - a + 4) % 4;
        if (d == 2) {  // straight through: two quads
          now.push_back({at_(a), ma, mb, at_(b + 1)});
          now.push_back({ma, at_(a + 1), at_(b), mb});
        } else {  // a turn: three quads around the centre
          const int c = vertex_count + static_cast<int>(r.added.size());
          r.added.push_back({{p[0], p[1], p[2], p[3]}, 4, false});
          ++r.turns;
          if (d == 1) {  // around corner a + 1
            now.push_back({ma, at_(a + 1), mb, c});
            now.push_back({at_(a), ma, c, at_(a + 3)});
            now.push_back({c, mb, at_(a + 2), at_(a + 3)});
          } else {  // around corner a
            now.push_back({mb, at_(a), ma, c});
            now.push_back({ma, at_(a + 1), at_(a + 2), c});
            now.push_back({c, at_(a + 2), at_(a + 3), mb});
          }
        }
      }
      replaced.push_back({s.face, std::move(now)});
    }
    for (auto& [f, now] : replaced) {
      faces[f] = now[0];
      for (std::size_t i = 1; i < now.size(); ++i) faces.push_back(now[i]);
    }
    ++r.rows;
  }
  r.faces = std::move(faces);
  return r;
}

}  // namespace kerfab::quads
