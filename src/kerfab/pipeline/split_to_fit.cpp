#include "kerfab/pipeline/split_to_fit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <string>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

/// What a build must not have more of to be taken.
struct Defects {
  std::size_t critical = 0, small = 0, off_sheet = 0;
  int without_joint = 0;
  bool no_worse_than(const Defects& o) const {
    return critical <= o.critical && small <= o.small && off_sheet <= o.off_sheet &&
           without_joint <= o.without_joint;
  }
};

Defects defects_of(const PartsBuild& b, const LayoutResult& l, const SplitToFitInput& in) {
  return {b.kerf.critical.size(),
          parts_too_small(b, in.min_part_area, in.min_part_width, in.parts->flatten.max_angle_error)
              .size(),
          l.unplaced.size(), b.joints.borders_without_joint};
}

/// Strip \p p's ruling nearest its middle at a boundary between two of its quads (a strip border
/// there leaves a whole quad on each side): its coarse edge and its index among the strip's
/// rulings; {-1, -1} if none.
std::array<int, 2> middle_ruling(const Strips& s, const Patch& p) {
  const std::vector<int> starts = column_starts(s, p);
  const double half = 0.5 * starts.back();
  std::array<int, 2> best{-1, -1};
  double off = 0;
  for (std::size_t col = 1; col + 1 < starts.size(); ++col) {
    const int edge = p.ruling_edges[starts[col]];
    if (edge < 0) continue;
    const double d = std::abs(starts[col] - half);
    if (best[0] < 0 || d < off) best = {edge, starts[col]}, off = d;
  }
  return best;
}

/// No nesting uses fewer sheets than \p l does: it is at one sheet or a lower bound.
bool at_bound(const LayoutResult& l) {
  return l.sheets <= std::max({1, l.sheets_lower_bound, l.sheets_lower_bound_spaced});
}

/// Strip \p p's laser path cut at ruling \p ruling in its own flattening (halves_in_plane):
/// the pieces on the first half's side, and the rest.
std::array<std::vector<Polygon2>, 2> cut_in_plane(const CuttablePatches& flat, const Joints& joints,
                                                  int p, int ruling, double reach) {
  const Patch& patch = flat.strips.patches[p];
  const std::vector<Vec2>& pts = flat.flattening.patches[p].points;
  const Polygon2& path = joints.parts[p].cut;
  const Vec2 a = pts[patch.local(0, ruling)], c = pts[patch.local(1, ruling)];
  if (!((c - a).norm() > 0)) return {};
  // The first half: rail 0 up to the ruling, the last rail back.
  Polygon2 first;
  for (int i = 0; i <= ruling; ++i) first.push_back(pts[patch.local(0, i)]);
  for (int i = ruling; i >= 0; --i) first.push_back(pts[patch.local(1, i)]);
  make_counter_clockwise(first);
  const std::vector<Polygon2> near = polygon_offset({first}, reach);
  // Its side of the ruling's line: a square of side 2 L beyond it, L past any part.
  const Vec2 u = (c - a).normalized();
  Vec2 n(-u.y(), u.x());
  const Vec2 inside = 0.5 * (pts[patch.local(0, 0)] + pts[patch.local(1, 0)]);
  if (n.dot(inside - a) < 0) n = -n;
  double l = 0;
  for (const Vec2& v : path) l = std::max(l, (v - a).norm());
  l = 2 * l + 1;
  Polygon2 side{a - l * u, a + l * u, a + l * u + 2 * l * n, a - l * u + 2 * l * n};
  make_counter_clockwise(side);
  std::vector<Polygon2> one;
  for (const Polygon2& h : polygon_intersection(path, side))
    for (const Polygon2& region : near)
      for (auto& piece : polygon_intersection(h, region))
        if (polygon_area(piece) > 0) one.push_back(std::move(piece));
  if (one.empty()) return {};
  std::array<std::vector<Polygon2>, 2> out;
  for (auto& piece : polygon_union(one))
    if (polygon_area(piece) > 0) out[0].push_back(std::move(piece));
  for (auto& piece : polygon_difference({path}, one))
    if (polygon_area(piece) > 0) out[1].push_back(std::move(piece));
  return out;
}

}  // namespace

std::vector<Polygon2> halves_in_plane(const CuttablePatches& flat, const Joints& joints, int p,
                                      int ruling, double reach) {
  auto [one, rest] = cut_in_plane(flat, joints, p, ruling, reach);
  if (one.empty()) return {joints.parts[p].cut};
  for (auto& piece : one) rest.push_back(std::move(piece));
  return rest;
}

std::vector<Polygon2> ring_recut_in_plane(const CuttablePatches& flat, const Joints& joints, int p,
                                          int ruling, double reach) {
  const Patch& patch = flat.strips.patches[p];
  const std::vector<Vec2>& pts = flat.flattening.patches[p].points;
  const int last = static_cast<int>(patch.rulings.size()) - 1;
  const Vec2 a0 = pts[patch.local(0, 0)], c0 = pts[patch.local(1, 0)];
  const Vec2 an = pts[patch.local(0, last)], cn = pts[patch.local(1, last)];
  if (!patch.loop_cut || !((c0 - a0).norm() > 0) || !((cn - an).norm() > 0))
    return {joints.parts[p].cut};
  auto [one, rest] = cut_in_plane(flat, joints, p, ruling, reach);
  if (one.empty() || rest.empty()) return {joints.parts[p].cut};
  // The first ruling and the last are one in 3D, where the ring was cut open: the first half
  // turned and moved to continue the rest there.
  const double turn =
      std::atan2((cn - an).y(), (cn - an).x()) - std::atan2((c0 - a0).y(), (c0 - a0).x());
  const Eigen::Rotation2Dd r(turn);
  for (Polygon2& piece : one)
    for (Vec2& v : piece) v = r * (v - a0) + an;
  for (auto& piece : one) rest.push_back(std::move(piece));
  std::vector<Polygon2> out;
  for (auto& piece : polygon_union(rest))
    if (polygon_area(piece) > 0) out.push_back(std::move(piece));
  return out;
}

SplitToFitResult split_to_fit(PartsBuild& build, LayoutResult& layout, const SplitToFitInput& in,
                              const SplitToFitOptions& options, PartsMemo* memo) {
  for (double f : options.fractions)
    if (!(f > 0 && f <= 2)) throw InvalidInput("split to fit: every fraction must be in (0, 2]");
  const auto t0 = std::chrono::steady_clock::now();
  SplitToFitResult r;
  r.sheets_before = r.sheets_after = layout.sheets;
  r.parts_before = r.parts_after = static_cast<int>(build.joints.parts.size());
  r.minutes_before = r.minutes_after = build.kerf.cutting.minutes;
  auto done = [&] {
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  };
  if (!in.blocked.empty()) {
    r.why_not = in.blocked;
    return done();
  }
  if (!options.enabled) {
    r.why_not = "strips kept whole (--keep-strips-whole)";
    return done();
  }
  if (!(in.parts->material.thickness > 0)) {
    r.why_not = "paper: parts are split to fit the page only";
    return done();
  }
  if (at_bound(layout)) {
    r.why_not = "no nesting uses fewer sheets";
    return done();
  }
  if (too_full_for_one_fewer(layout.spaced_fill, layout.sheets)) {
    r.why_not =
        "the parts, grown by half the spacing, would fill the sheets but one fuller than "
        "any nesting here reaches";
    return done();
  }
  // Each attempt cuts the parts again and nests them: only where a nesting is cheap (a job of
  // hundreds of parts on ten sheets takes minutes per attempt).
  if (static_cast<double>(build.joints.parts.size()) * layout.sheets > kCheapNest) {
    r.why_not = "too many parts on too many sheets to cut and nest again (parts x sheets over " +
                std::to_string(static_cast<int>(kCheapNest)) + ")";
    return done();
  }
  r.tried = true;
  const LayoutOptions& sheets = *in.layout;
  const Vec2 stock = sheets.size_of(-1);
  const double side = std::min(stock.x(), stock.y()) - 2 * sheets.margin;
  const PolyMesh& m = in.input->quads;
  Guidance guidance = in.guidance;
  Defects now = defects_of(build, layout, in);
  // The edge sets tried since the last build taken: the same set again (a smaller fraction
  // adding no strip, the rings halved again after a recut between) would screen or build the
  // same parts again, with the same outcome.
  std::set<std::set<int>> tried_since;
  // How far a strip's teeth reach beyond its flattened quads (halves_in_plane) [mm].
  const double reach = 2 * in.parts->material.thickness + 2;
  // Per fraction, rings (strips the strips stage cut open) cut in two first, then only cut open
  // at their middle instead (their other shape may nest better).
  std::vector<std::pair<double, bool>> attempts;
  for (double fraction : options.fractions)
    for (bool halve_rings : {true, false}) attempts.push_back({fraction, halve_rings});
  for (const auto& [fraction, halve_rings] : attempts) {
    const double min_length = fraction * side;
    std::vector<int> edges;
    // Strip, ruling, whether it is a ring recut there (else it is cut in two there).
    std::vector<std::array<int, 3>> cuts;
    int strips = 0, rings = 0;
    const Strips& s = build.flat.strips;
    for (std::size_t p = 0; p < s.patches.size(); ++p) {
      const Patch& patch = s.patches[p];
      if (patch.flat || patch.rows() > 1 || patch.quads.size() < 2) continue;
      const MinRect rect = min_area_rect(build.joints.parts[p].designed);
      if (std::max(rect.width, rect.height) < min_length) continue;
      const auto [edge, ruling] = middle_ruling(s, patch);
      if (edge < 0) continue;
      edges.push_back(edge);
      // A ring cut open where the strips stage chose: a border there too cuts it in two;
      // without, the one in the middle moves the cut there.
      const bool recut = patch.loop_cut && !(halve_rings && patch.end_edges[0] >= 0);
      cuts.push_back({static_cast<int>(p), ruling, recut ? 1 : 0});
      if (!patch.loop_cut) {
        ++strips;
      } else if (!recut) {
        edges.push_back(patch.end_edges[0]);
        ++strips;
      } else {
        ++rings;
      }
    }
    const std::set<int> these(edges.begin(), edges.end());
    if (these.empty() || !tried_since.insert(these).second) continue;
    Guidance g = guidance;
    std::vector<std::array<int, 2>> added;
    for (int edge : these) {
      const auto h = m.halfedge_handle(m.edge_handle(edge), 0);
      added.push_back({m.from_vertex_handle(h).idx(), m.to_vertex_handle(h).idx()});
    }
    g.split.insert(g.split.end(), added.begin(), added.end());
    // Cutting and nesting the parts again takes seconds; first the paths as they are, the
    // strips cut in two in the plane (halves_in_plane) and the rings recut there
    // (ring_recut_in_plane), are nested: where even those need as many sheets, the attempt is
    // not built.
    {
      std::vector<Polygon2> paths;
      std::vector<char> taken(build.joints.parts.size(), 0);
      for (const auto& [p, ruling, recut] : cuts) {
        taken[p] = 1;
        for (auto& piece : recut ? ring_recut_in_plane(build.flat, build.joints, p, ruling, reach)
                                 : halves_in_plane(build.flat, build.joints, p, ruling, reach))
          paths.push_back(std::move(piece));
      }
      for (std::size_t p = 0; p < build.joints.parts.size(); ++p)
        if (!taken[p]) paths.push_back(build.joints.parts[p].cut);
      if (nest_parts(paths, sheets).sheets >= layout.sheets) {
        ++r.screened;
        continue;
      }
    }
    ++r.attempts;
    PartsBuild tried;
    try {
      tried = build_parts(*in.input, *in.parts, g, &build.bending, memo);
    } catch (const InvalidInput&) {  // the strips refused a border there
      continue;
    }
    LayoutResult laid =
        lay_out_parts(tried.flat.strips, tried.flat.flattening, tried.joints, tried.kerf, sheets);
    const Defects after = defects_of(tried, laid, in);
    if (laid.sheets >= layout.sheets || !after.no_worse_than(now)) continue;
    build = std::move(tried);
    layout = std::move(laid);
    guidance = std::move(g);
    now = after;
    r.strips_split += strips;
    r.rings_recut += rings;
    r.split_edges.insert(r.split_edges.end(), added.begin(), added.end());
    r.min_length_mm = min_length;
    r.sheets_after = layout.sheets;
    r.parts_after = static_cast<int>(build.joints.parts.size());
    r.minutes_after = build.kerf.cutting.minutes;
    tried_since.clear();
    if (at_bound(layout) || too_full_for_one_fewer(layout.spaced_fill, layout.sheets)) break;
  }
  if (!r.saved()) r.why_not = "splitting the longest strips saved no sheet without a defect more";
  return done();
}

}  // namespace kerfab
