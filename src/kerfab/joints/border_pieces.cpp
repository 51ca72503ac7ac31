#include "kerfab/joints/border_pieces.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace kerfab::border {
namespace {

Vec2 right_of(const Vec2& d) { return {d.y(), -d.x()}; }

void make_rings(const Strips& strips, const Flattening& flat, Pieces& out) {
  for (const Patch& patch : strips.patches) out.locals.push_back(patch.local_vertices());
  for (std::size_t p = 0; p < strips.patches.size(); ++p) {
    Ring r;
    r.edges = strips.patches[p].outline();
    const auto& x = flat.patches[p].points;
    double area = 0;
    for (const auto& e : r.edges)
      area += x[e.v[0]].x() * x[e.v[1]].y() - x[e.v[1]].x() * x[e.v[0]].y();
    if (area < 0) {  // make it counter-clockwise
      std::reverse(r.edges.begin(), r.edges.end());
      for (auto& e : r.edges) std::swap(e.v[0], e.v[1]);
    }
    for (const auto& e : r.edges) {
      r.start.push_back(x[e.v[0]]);
      r.end.push_back(x[e.v[1]]);
      const Vec2 d = x[e.v[1]] - x[e.v[0]];
      r.normal.push_back(d.norm() > 0 ? Vec2(right_of(d).normalized()) : Vec2(0, 0));
    }
    r.piece.assign(r.edges.size(), -1);
    r.piece_side.assign(r.edges.size(), -1);
    out.rings.push_back(std::move(r));
  }
}

/// 3D end points of ring edge \p k of \p side in piece order.
std::pair<Vec3, Vec3> ends(const Strips& strips, const Pieces& out, const Side& side, int k) {
  const auto& e = out.rings[side.patch].edges[k];
  const Vec3 a = strips.vertices[out.locals[side.patch][e.v[0]]],
             b = strips.vertices[out.locals[side.patch][e.v[1]]];
  return side.reversed ? std::make_pair(b, a) : std::make_pair(a, b);
}

/// A border that closes on itself in 3D (two tubes meeting along a circle) has no common end:
/// each side's run of ring edges starts wherever its patch was cut open. The second side is
/// turned to start where the first does, and to run the same way, so that arc length means the
/// same place on both sides.
void align_closed_loop(const Strips& strips, const Pieces& out, const Side& first, Side& second) {
  const auto& f = first.ring_edges;
  auto& r = second.ring_edges;
  if (f.empty() || r.size() < 2) return;
  const Vec3 start = ends(strips, out, first, f.front()).first;
  if ((ends(strips, out, first, f.back()).second - start).norm() > 1e-6 ||
      (ends(strips, out, second, r.back()).second - ends(strips, out, second, r.front()).first)
              .norm() > 1e-6)
    return;
  std::size_t j = 0;
  for (std::size_t k = 1; k < r.size(); ++k)
    if ((ends(strips, out, second, r[k]).first - start).norm() <
        (ends(strips, out, second, r[j]).first - start).norm())
      j = k;
  std::rotate(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(j), r.end());
  // The same way round: the first side's next vertex is nearer the second side's next vertex
  // than its previous one.
  const Vec3 next = ends(strips, out, first, f.front()).second;
  if ((ends(strips, out, second, r.back()).first - next).norm() <
      (ends(strips, out, second, r.front()).second - next).norm()) {
    std::reverse(r.begin(), r.end());
    second.reversed = !second.reversed;
  }
}

void make_border_pieces(const Strips& strips, Pieces& out) {
  auto p3 = [&](int patch, int local) { return strips.vertices[out.locals[patch][local]]; };
  // Group outline edges by coarse edge and patch side.
  std::map<int, std::map<int, std::vector<int>>> groups;  // edge -> side key -> ring edges
  for (std::size_t p = 0; p < out.rings.size(); ++p)
    for (std::size_t k = 0; k < out.rings[p].edges.size(); ++k) {
      const auto& e = out.rings[p].edges[k];
      groups[e.coarse_edge][static_cast<int>(p) * 4 + e.side].push_back(static_cast<int>(k));
    }
  // Consecutive coarse edges along which the same two patch sides meet form one border (a
  // chain): its teeth run on across the coarse vertices, so a border made of short coarse
  // edges still has room for them. A chain that closes into a loop stays in coarse edges.
  auto pair_of = [&](int edge) {
    const auto& sides = groups.at(edge);
    return std::make_pair(sides.begin()->first, std::next(sides.begin())->first);
  };
  std::map<int, int> parent;
  auto root = [&](int e) {
    int r = e;
    while (parent.at(r) != r) r = parent.at(r);
    return parent[e] = r;
  };
  for (const auto& [edge, sides] : groups)
    if (sides.size() == 2) parent[edge] = edge;
  for (const Ring& ring : out.rings) {
    const std::size_t m = ring.edges.size();
    for (std::size_t k = 0; k < m; ++k) {
      const int a = ring.edges[k].coarse_edge, b = ring.edges[(k + 1) % m].coarse_edge;
      if (a == b || !parent.count(a) || !parent.count(b) || pair_of(a) != pair_of(b)) continue;
      parent[root(a)] = root(b);
    }
  }
  std::map<int, std::vector<int>> chains;  // root -> coarse edges
  for (const auto& [edge, up] : parent) chains[root(edge)].push_back(edge);
  std::vector<std::pair<std::vector<int>, std::map<int, std::vector<int>>>> borders;
  for (const auto& [r, edges] : chains) {
    std::map<int, std::vector<int>> sides;
    for (int e : edges)
      for (const auto& [key, ring_edges] : groups.at(e))
        sides[key].insert(sides[key].end(), ring_edges.begin(), ring_edges.end());
    const auto& first = sides.begin()->second;
    const bool loop = edges.size() > 1 &&
                      first.size() == out.rings[sides.begin()->first / 4].edges.size();
    if (!loop) {
      borders.emplace_back(edges, std::move(sides));
      continue;
    }
    for (int e : edges) borders.emplace_back(std::vector<int>{e}, groups.at(e));
  }
  for (auto& [edges, sides] : borders) {
    Piece piece;
    piece.edge = edges.front();
    piece.edges = edges;
    Vec3 common = strips.vertices[strips.edge_vertices[piece.edge].front()];
    int i = 0;
    for (auto& [key, ring_edges] : sides) {
      Side& side = piece.sides[i++];
      side.patch = key / 4;
      side.key = key;
      const Ring& ring = out.rings[side.patch];
      // Ring edges of one side are consecutive, but may wrap around the ring's start.
      std::sort(ring_edges.begin(), ring_edges.end());
      const int m = static_cast<int>(ring.edges.size());
      for (std::size_t j = 1; j < ring_edges.size(); ++j)
        if (ring_edges[j] != ring_edges[j - 1] + 1) {
          std::rotate(ring_edges.begin(), ring_edges.begin() + j, ring_edges.end());
          break;
        }
      const Vec3 first = p3(side.patch, ring.edges[ring_edges.front()].v[0]);
      const Vec3 last = p3(side.patch, ring.edges[ring_edges.back()].v[1]);
      if (i == 1 && edges.size() > 1) common = first;  // a chain: from the first side's start
      side.reversed = (last - common).norm() < (first - common).norm();
      if (side.reversed) std::reverse(ring_edges.begin(), ring_edges.end());
      side.ring_edges = ring_edges;
      if (i == 2) align_closed_loop(strips, out, piece.sides[0], side);
      side.s.push_back(0);
      for (int k : side.ring_edges) {
        const auto& e = ring.edges[k];
        int a = e.v[0], b = e.v[1];
        if (side.reversed) std::swap(a, b);
        side.s.push_back(side.s.back() + (p3(side.patch, b) - p3(side.patch, a)).norm());
        const auto& face = strips.faces[e.sub_quad];
        side.n0.push_back(sector_normal(strips.vertices, face, out.locals[side.patch][a]));
        side.n1.push_back(sector_normal(strips.vertices, face, out.locals[side.patch][b]));
      }
      (void)m;
    }
    piece.length = std::max(piece.sides[0].s.back(), piece.sides[1].s.back());
    const int id = static_cast<int>(out.pieces.size());
    for (int k = 0; k < 2; ++k)
      for (int e : piece.sides[k].ring_edges) {
        out.rings[piece.sides[k].patch].piece[e] = id;
        out.rings[piece.sides[k].patch].piece_side[e] = k;
      }
    out.pieces.push_back(std::move(piece));
  }
}

}  // namespace

Vec3 slerp_normal(const Vec3& a, const Vec3& b, double t) {
  const double w = angle_between(a, b), sw = std::sin(w);
  if (sw < 1e-9) return ((1 - t) * a + t * b).normalized();
  return (std::sin((1 - t) * w) / sw * a + std::sin(t * w) / sw * b).normalized();
}

int Side::edge_at(double at) const {
  const int m = static_cast<int>(ring_edges.size());
  int j = 0;
  while (j + 1 < m && s[j + 1] < at) ++j;
  return j;
}

Vec3 Side::normal_at(double at) const {
  const int j = edge_at(at);
  const double len = s[j + 1] - s[j];
  const double t = len > 0 ? std::clamp((at - s[j]) / len, 0.0, 1.0) : 0.5;
  return slerp_normal(n0[j], n1[j], t);
}

double Piece::fold_at(double at) const {
  return angle_between(sides[0].normal_at(at), sides[1].normal_at(at));
}

Pieces make_pieces(const Strips& strips, const Flattening& flat) {
  Pieces out;
  make_rings(strips, flat, out);
  make_border_pieces(strips, out);
  return out;
}

std::array<Vec3, 2> piece_ends(const Strips& strips, const Pieces& pieces, int piece) {
  const Side& side = pieces.pieces[piece].sides[0];
  return {ends(strips, pieces, side, side.ring_edges.front()).first,
          ends(strips, pieces, side, side.ring_edges.back()).second};
}

std::pair<double, double> s_range(const Side& side, int k) {
  const auto it = std::find(side.ring_edges.begin(), side.ring_edges.end(), k);
  const std::size_t j = static_cast<std::size_t>(it - side.ring_edges.begin());
  return {side.s[j], side.s[j + 1]};
}

double s_of(const Side& side, int k, double t) {
  const auto [a, b] = s_range(side, k);
  return side.reversed ? b - t * (b - a) : a + t * (b - a);
}

}  // namespace kerfab::border
