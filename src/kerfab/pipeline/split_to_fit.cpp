#include "kerfab/pipeline/split_to_fit.h"

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

/// The coarse edge of strip \p p's ruling nearest its middle at a boundary between two of its
/// quads (a strip border there leaves a whole quad on each side), or -1.
int middle_ruling_edge(const Strips& s, const Patch& p) {
  const std::vector<int> starts = column_starts(s, p);
  const double half = 0.5 * starts.back();
  int best = -1;
  double off = 0;
  for (std::size_t col = 1; col + 1 < starts.size(); ++col) {
    const int edge = p.ruling_edges[starts[col]];
    if (edge < 0) continue;
    const double d = std::abs(starts[col] - half);
    if (best < 0 || d < off) best = edge, off = d;
  }
  return best;
}

/// No nesting uses fewer sheets than \p l does: it is at one sheet or a lower bound.
bool at_bound(const LayoutResult& l) {
  return l.sheets <= std::max({1, l.sheets_lower_bound, l.sheets_lower_bound_spaced});
}

}  // namespace

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
  std::set<int> tried_edges;  // the last attempt's, to skip one that adds nothing
  // Per fraction, rings (strips the strips stage cut open) cut in two first, then only cut open
  // at their middle instead (their other shape may nest better; Bob at 600 mm saved a sheet
  // that way and not the other).
  std::vector<std::pair<double, bool>> attempts;
  for (double fraction : options.fractions)
    for (bool halve_rings : {true, false}) attempts.push_back({fraction, halve_rings});
  for (const auto& [fraction, halve_rings] : attempts) {
    const double min_length = fraction * side;
    std::vector<int> edges;
    int strips = 0, rings = 0;
    const Strips& s = build.flat.strips;
    for (std::size_t p = 0; p < s.patches.size(); ++p) {
      const Patch& patch = s.patches[p];
      if (patch.flat || patch.rows() > 1 || patch.quads.size() < 2) continue;
      const MinRect rect = min_area_rect(build.joints.parts[p].designed);
      if (std::max(rect.width, rect.height) < min_length) continue;
      const int edge = middle_ruling_edge(s, patch);
      if (edge < 0) continue;
      edges.push_back(edge);
      // A ring cut open where the strips stage chose: a border there too cuts it in two;
      // without, the one in the middle moves the cut there.
      if (!patch.loop_cut) {
        ++strips;
      } else if (halve_rings && patch.end_edges[0] >= 0) {
        edges.push_back(patch.end_edges[0]);
        ++strips;
      } else {
        ++rings;
      }
    }
    const std::set<int> these(edges.begin(), edges.end());
    if (these.empty() || these == tried_edges) continue;
    tried_edges = these;
    Guidance g = guidance;
    std::vector<std::array<int, 2>> added;
    for (int edge : these) {
      const auto h = m.halfedge_handle(m.edge_handle(edge), 0);
      added.push_back({m.from_vertex_handle(h).idx(), m.to_vertex_handle(h).idx()});
    }
    g.split.insert(g.split.end(), added.begin(), added.end());
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
    tried_edges.clear();
    if (at_bound(layout) || too_full_for_one_fewer(layout.spaced_fill, layout.sheets)) break;
  }
  if (!r.saved()) r.why_not = "splitting the longest strips saved no sheet without a defect more";
  return done();
}

}  // namespace kerfab
