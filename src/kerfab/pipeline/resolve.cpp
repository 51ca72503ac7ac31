#include "kerfab/pipeline/resolve.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "kerfab/adapters/polygon_ops.h"
#include "kerfab/core/errors.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/joints/tooth_offsets.h"
#include "kerfab/layout/layout.h"

namespace kerfab {
namespace {

constexpr int kNone = -1;

/// A flat region with holes is cut in two, and its pieces again, at most this many times deep
/// (plates_for_flat_regions).
constexpr int kPlateCuts = 3;
/// A plate larger than the sheet is cut along each side of its smallest rectangle into at most
/// this many pieces (fitting_pieces): a panel up to about 8 times the sheet each way.
constexpr int kPlateGrid = 8;
/// Of those grids, the one of fewest pieces whose pieces would take at most this share more
/// sheets than the grid of fewest sheets [-] (fitting_pieces).
constexpr double kPlateSheetSlack = 0.1;
/// A flat region of the model (plates_for_flat_regions): every corner of its quads within this
/// of the plane of the quad it grew from [mm], every quad facing within kPlateTilt of it [rad];
/// cut as one plate where at least kPlateBounded of its outline's length lies on folds sharper
/// than kPlateFold [rad] or on the model's border (a panel, not a flat stretch that a bent strip
/// runs on from).
constexpr double kPlateFlatness = 0.05;
constexpr double kPlateTilt = 0.5 * M_PI / 180;
constexpr double kPlateBounded = 0.75;
constexpr double kPlateFold = 20 * M_PI / 180;

/// A facet grown to make it big enough to handle (Resolver::facets) that is still not when it
/// has more quads than this, and lies farther than two sheets off its plane, is put back as it
/// was [-]: its cut-backs, not its size, are what leave it too small, and as a plate it is no
/// longer the shape. Measured: such growths that stayed too small reached 68 and 91 quads,
/// 18 and 25 mm off their planes, on demosthenes at 250 mm, and 70 and 105 quads, 12 and 43 mm,
/// on bunny_closed at 200 mm; on the fine quad meshes at 250 mm (quads of a few millimetres)
/// 13-31 quads, 1.1-5.3 mm, which later rounds use (put back, horse_quad kept 2 parts
/// unresolved and 4 borders without a joint).
constexpr std::size_t kMaxFailedGrowth = 16;

/// A critical region as it sits on the strips.
struct Region {
  int patch = kNone;
  int c0 = 0, c1 = 0;      // first and last column (position of row 0's quad along the strip)
  std::vector<int> quads;  // every row's quads in those columns
  Vec3 centre = Vec3::Zero();
  double spacing = 0, stress_ratio = 0;
  CriticalCause cause = CriticalCause::kTooDense;
  double fit_factor = 0;    // CriticalRegion::fit_factor
  bool small_part = false;  // a whole part too small or too narrow to handle, not a bend
  // Of a small part that fell apart into pieces a maker could handle each on its own: the
  // columns at whose first ruling it is split so that each becomes a part (columns_apart).
  std::vector<int> apart_at;
  // Of a facet that narrows to a neck: its quads in the groups that become facets of their own
  // (facet_quads_at_necks).
  std::vector<std::vector<int>> facet_groups;
};

/// Area of \p part as cut; 0 where its outline has nothing left [mm^2].
double area_as_cut(const PartOutline& part) {
  return part.designed.size() < 3 ? 0.0 : std::abs(polygon_area(part.designed));
}

/// True when the flattening \p flat (of patch \p p of \p b) has an inverted quad, crosses
/// itself, or has a corner angle off by the flattening's limit or more: a part that does not
/// have the angles of its neighbours' borders does not fit them.
bool distorted(const PatchFlattening& flat, double max_angle_error) {
  return flat.inverted_quads > 0 || !flat.outline_simple || flat.max_angle_error >= max_angle_error;
}
bool distorted(const PartsBuild& b, int p, double max_angle_error) {
  return distorted(b.flat.flattening.patches[p], max_angle_error);
}

/// True when patch \p p of \p b is a facet that flattens distorted: its corners, shared with
/// facets at other angles, bent it.
bool bent_facet(const PartsBuild& b, int p, double max_angle_error) {
  return b.flat.strips.patches[p].flat && distorted(b, p, max_angle_error);
}

/// Beyond twice the offset, the margin small_parts() keeps when it asks holds_point_deeper_than()
/// for the offset's rounding to Clipper's grid (10 nm) [mm].
constexpr double kDeepMargin = 0.01;

/// Parts a maker cannot handle: less than \p min_area as cut, nowhere as wide as \p
/// min_width (the outline shrunk by half of it is empty), fallen apart when cut, or one that
/// flattens inverted, crossing itself or with a corner off by the flattening's limit or more: a
/// facet whose corners shared with other facets moved it off its plane, or a strip of one quad
/// (which the flattening cannot split further) twisted or folded more than a sheet bends flat
/// (in paper, the bunny's collapsed strip ends flattened 216 deg off, with an inverted
/// sub-quad) [mm^2, mm].
std::vector<int> small_parts(const PartsBuild& b, double min_area, double min_width,
                             double max_angle_error) {
  std::vector<int> out;
  for (std::size_t p = 0; p < b.joints.parts.size(); ++p) {
    const Polygon2& outline = b.joints.parts[p].designed;
    if (distorted(b, static_cast<int>(p), max_angle_error) || b.joints.parts[p].repaired ||
        outline.size() < 3 || std::abs(polygon_area(outline)) < min_area ||
        (!holds_point_deeper_than(outline, min_width + kDeepMargin) &&
         polygon_offset({outline}, -0.5 * min_width).empty()))
      out.push_back(static_cast<int>(p));
  }
  return out;
}

int column_of(const std::vector<int>& starts, int interval) {
  return std::clamp(
      static_cast<int>(std::upper_bound(starts.begin(), starts.end(), interval) - starts.begin()) -
          1,
      0, static_cast<int>(starts.size()) - 2);
}

Region region_of(const Strips& s, const Flattening& f, const CriticalRegion& c) {
  Region r;
  r.patch = c.patch;
  r.spacing = c.spacing;
  r.stress_ratio = c.stress_ratio;
  r.cause = c.cause;
  r.fit_factor = c.fit_factor;
  const Patch& p = s.patches[c.patch];
  const StripFrame frame(f.patches[c.patch].points, static_cast<int>(p.faces.size()));
  const int i0 = frame.face_at(c.start), i1 = frame.face_at(c.end);
  const auto starts = column_starts(s, p);
  r.c0 = column_of(starts, i0);
  r.c1 = column_of(starts, i1);
  for (int col = r.c0; col <= r.c1; ++col) {
    r.quads.push_back(p.quads[col]);
    for (const PatchRow& row : p.more_rows) r.quads.push_back(row.quads[col]);
  }
  int n = 0;
  for (int i = i0; i <= i1 + 1; ++i) {
    r.centre += s.vertices[p.rulings[i][0]] + s.vertices[p.rulings[i][1]];
    n += 2;
  }
  r.centre /= n;
  return r;
}

/// A whole part as a region (one too small or too narrow to handle): all its quads, its middle.
Region part_region(const Strips& s, int p) {
  const Patch& patch = s.patches[p];
  Region r;
  r.patch = p;
  r.c0 = 0;
  r.c1 = static_cast<int>(patch.quads.size()) - 1;
  r.quads = patch.all_quads();
  r.small_part = true;
  const auto vertices = patch.local_vertices();
  for (int v : vertices) r.centre += s.vertices[v];
  r.centre /= std::max<std::size_t>(1, vertices.size());
  return r;
}

/// Where part \p p of \p b fell apart when cut into the piece kept and a lost piece of at least
/// \p min_area (one a maker can handle on its own; parts fall apart where the mitres of two
/// sharp folds meet across a strip, which no joint cures): the columns at whose first ruling the
/// strip is split so that each such piece becomes a part of its own, one where the columns change
/// from the kept piece to a lost one along the strip (between two, in the middle of the columns
/// that lie mostly in neither: the neck). Empty where there is none.
std::vector<int> columns_apart(const PartsBuild& b, int p, double min_area) {
  const PartOutline& part = b.joints.parts[p];
  const Patch& patch = b.flat.strips.patches[p];
  if (!part.repaired || patch.flat || patch.quads.size() < 2) return {};
  std::vector<Polygon2> large;
  for (const Polygon2& piece : part.lost)
    if (std::abs(polygon_area(piece)) >= min_area) large.push_back(piece);
  if (large.empty()) return {};
  const std::vector<Vec2>& x = b.flat.flattening.patches[p].points;
  const auto starts = column_starts(b.flat.strips, patch);
  // Per column: 1 where it lies mostly in the piece kept, -1 in a large lost one, else 0.
  const int columns = static_cast<int>(patch.quads.size());
  std::vector<int> side(static_cast<std::size_t>(columns), 0);
  for (int col = 0; col < columns; ++col) {
    Polygon2 quad;  // rail 0 along the column, the last rail back
    for (int i = starts[col]; i <= starts[col + 1]; ++i) quad.push_back(x[2 * i]);
    for (int i = starts[col + 1]; i >= starts[col]; --i) quad.push_back(x[2 * i + 1]);
    make_counter_clockwise(quad);
    const double whole = std::abs(polygon_area(quad)), kept = common_area(quad, part.designed);
    double lost = 0;
    for (const Polygon2& piece : large) lost += common_area(quad, piece);
    if (kept >= 0.5 * whole)
      side[col] = 1;
    else if (lost >= 0.5 * whole)
      side[col] = -1;
  }
  std::vector<int> at;
  int last = kNone;  // the last column in either piece
  for (int col = 0; col < columns; ++col) {
    if (side[col] == 0) continue;
    if (last != kNone && side[col] != side[last]) at.push_back((last + 1 + col + 1) / 2);
    last = col;
  }
  return at;
}

/// Where facet \p p of \p b narrows, as cut, to a neck under \p min_feature [mm] between two
/// stretches of it (the pieces of its erosion, neck_cores): its coarse quads in groups, each
/// quad with the piece that covers most of its flattened quad (one no piece reaches goes with
/// the piece nearest its middle). Empty where the quads fall in fewer than two groups (a
/// corner within one quad hanging on a neck) or the part is a strip.
std::vector<std::vector<int>> facet_quads_at_necks(const PartsBuild& b, int p, double min_feature) {
  const Patch& patch = b.flat.strips.patches[p];
  const Polygon2& outline = b.joints.parts[p].designed;
  if (!patch.flat || patch.quads.size() < 2 || outline.size() < 3) return {};
  const std::vector<Polygon2> cores = neck_cores(outline, min_feature);
  if (cores.size() < 2) return {};
  const std::vector<Vec2>& x = b.flat.flattening.patches[p].points;
  std::vector<std::vector<int>> groups(cores.size());
  for (std::size_t i = 0; i < patch.quads.size(); ++i) {
    Polygon2 quad;
    Vec2 middle = Vec2::Zero();
    for (int v : patch.flat_quads[i]) quad.push_back(x[v]), middle += 0.25 * x[v];
    make_counter_clockwise(quad);
    std::size_t best = 0;
    double most = 0, nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < cores.size(); ++k) {
      const double area = common_area(quad, cores[k]), d = distance_to_boundary(middle, cores[k]);
      if (area > most || (most == 0 && d < nearest)) best = k;
      most = std::max(most, area), nearest = std::min(nearest, d);
    }
    groups[best].push_back(patch.quads[i]);
  }
  std::erase_if(groups, [](const std::vector<int>& g) { return g.empty(); });
  if (groups.size() < 2) return {};
  return groups;
}

/// Largest fold across ruling \p i of patch \p p, over its rows' rail vertices [rad].
double fold_at(const Strips& s, const Patch& p, int i) {
  if (i <= 0 || i >= static_cast<int>(p.faces.size())) return 0.0;
  const auto lv = p.local_vertices();
  double fold = 0;
  for (int row = 0; row < p.rows(); ++row)
    for (int rail : {row, row + 1}) {
      const int v = lv[p.local(rail, i)];
      fold = std::max(fold, angle_between(sector_normal(s.vertices, s.faces[p.face(i - 1, row)], v),
                                          sector_normal(s.vertices, s.faces[p.face(i, row)], v)));
    }
  return fold;
}

std::array<int, 2> ends(const PolyMesh& m, int edge) {
  const auto h = m.halfedge_handle(m.edge_handle(edge), 0);
  return {m.from_vertex_handle(h).idx(), m.to_vertex_handle(h).idx()};
}

int edge_between(const PolyMesh& m, const std::array<int, 2>& v) {
  const auto h = m.find_halfedge(m.vertex_handle(v[0]), m.vertex_handle(v[1]));
  return h.is_valid() ? m.edge_handle(h).idx() : kNone;
}

/// The scale at which a bend would need no change in material \p m: its beams reach the
/// minimum spacing (w sqrt(h^2 + w^2) grows with the scale squared at a fixed twist per
/// length times strip width). Only bends too dense to cut count: a strip narrowing to a point,
/// converging cuts or a part too small are matters of layout that no scale cures, so they
/// give 1.
double size_factor(const Region& r, const Material& m, const KerfOptions& k) {
  const double g = m.shear_modulus / (m.yield_strength / m.safety);
  // Geometry constant 2 l / kappa of the region's tightest beam, from the spacing it needed.
  const double w = r.spacing, h = m.thickness;
  const double geometry = g * w * std::sqrt(h * h + w * w);
  double s = 1.0;
  if (geometry > 0 && r.cause == CriticalCause::kTooDense && !r.small_part) {
    const double d = k.min_cut_spacing;
    s = std::max(s, std::sqrt(g * d * std::sqrt(m.thickness * m.thickness + d * d) / geometry));
  }
  // A cut that does not fit the strip between its joints fits where the strip is wide enough.
  if (r.cause == CriticalCause::kTooNarrow && !r.small_part) s = std::max(s, r.fit_factor);
  return s;
}

enum class Remedy { kSplit, kMerge, kFacets };

const char* remedy_name(Remedy r) {
  switch (r) {
    case Remedy::kSplit:
      return "split";
    case Remedy::kMerge:
      return "merge";
    case Remedy::kFacets:
      return "facets";
  }
  return "";
}

/// The guidance the loop has added, with the coarse edges and quads it names (to avoid
/// contradictions).
struct Added {
  Guidance guidance;
  std::set<int> stiff, merge, split, facet_quads;
};

class Resolver {
 public:
  Resolver(PartsBuild& build, const PreparedInput& input, const PartsOptions& options,
           const ResolveOptions& resolve, const ResolveProgress& progress, PartsMemo* memo)
      : build_(build),
        in_(input),
        m_(input.quads),
        o_(options),
        r_(resolve),
        progress_(progress),
        memo_(memo ? *memo : own_memo_) {
    draft_options_ = o_;
    draft_options_.joints.stub_teeth = false;
  }

  ResolveResult run() {
    out_.critical_before = static_cast<int>(build_.kerf.critical.size());
    out_.parts_before = static_cast<int>(build_.flat.strips.patches.size());
    out_.minutes_before = build_.kerf.cutting.minutes;
    tightest_bend_ = build_.kerf.tightest_bend;
    out_.current_size_mm = in_.target_summary.bbox.largest_side();
    for (const auto& g : o_.bending.guidance)
      if (g.bendable) user_bendable_.insert(edge_between(m_, {g.v0, g.v1}));
    for (const auto& v : o_.strips.merge_edges) user_merge_.insert(edge_between(m_, v));
    for (const auto& v : o_.strips.split_edges) user_split_.insert(edge_between(m_, v));
    std::set<int> cheap_failed;  // quads where a crease split or a merge did not resolve
    // The best build so far (fewest critical regions and parts too small, then fewest parts):
    // the changes can take a round back (a facet regrown may leave more behind), and the loop
    // ends with the best it saw, not the last (a horse once ended its 16th round with 14
    // critical regions and 20 small parts after rounds with none and 4).
    struct Best {
      PartsBuild build;
      Added accepted;
      std::size_t changes = 0;
      std::pair<int, std::size_t> score;  // (defects, parts)
    };
    std::optional<Best> best;
    // \p small: small_now() of the current build.
    auto keep_if_best = [&](const std::vector<int>& small) {
      const std::pair<int, std::size_t> score = {
          static_cast<int>(build_.kerf.critical.size() + small.size()),
          build_.flat.strips.patches.size()};
      if (!best || score < best->score) best = Best{build_, accepted_, out_.changes.size(), score};
    };
    started_ = std::chrono::steady_clock::now();
    // What decides a round: the changes taken and the quads given up on. Where a round starts
    // from one seen before, the rounds after it repeat (a bust once went 4, 17, 4, 17 ...
    // critical regions to its last round): the loop ends there.
    using State = std::tuple<std::set<int>, std::set<int>, std::set<int>, std::set<int>,
                             std::set<std::vector<int>>, std::set<int>, std::set<int>>;
    std::set<State> seen;
    auto state = [&] {
      std::set<std::vector<int>> facets;
      for (std::vector<int> f : accepted_.guidance.facets) {
        std::sort(f.begin(), f.end());
        facets.insert(std::move(f));
      }
      return State{accepted_.stiff, accepted_.merge, accepted_.split, accepted_.facet_quads,
                   facets,          cheap_failed,    stuck_};
    };
    // The rebuilds leave the short borders' stub teeth out (drawing both parts for each
    // candidate tooth is most of the joints stage's time, and a stub tooth decides neither the
    // critical regions nor the parts too small, but for a rare few): the build the loop keeps
    // then gets them, and the rounds go on, with them, where that left a defect on quads the
    // draft had none on (a part that falls apart at a stub tooth's slot). The rounds are
    // counted across both.
    int round = 0;
    std::vector<int> small;
    for (const bool draft : {true, false}) {
      draft_ = draft;
      if (draft && r_.enabled) plates_for_flat_regions();
      if (!draft) {
        if (!build_.joints.draft) break;
        // The quads of the draft's critical regions and parts too small.
        const std::set<int> found = critical_quads(build_);
        cut_parts(build_, {}, o_, &memo_);  // nothing left out during the loop
        const std::set<int> now = critical_quads(build_);
        if (std::includes(found.begin(), found.end(), now.begin(), now.end())) {
          small = small_now();
          break;
        }
        if (progress_) {
          std::ostringstream line;
          std::vector<int> more;
          std::set_difference(now.begin(), now.end(), found.begin(), found.end(),
                              std::back_inserter(more));
          line << "with the stub teeth, " << more.size()
               << " quads are critical or in a part too small that were not in the draft: "
                  "the rounds go on";
          progress_(line.str());
        }
        seen.clear();
        best.reset();
        ++round;  // the draft's last round was one
      }
      for (; r_.enabled && round < r_.max_rounds; ++round) {
        small = small_now();
        keep_if_best(small);
        if (!seen.insert(state()).second) break;
        std::vector<Region> pending = current_regions(small);
        if (!pending.empty() && out_of_time()) {
          out_.time_limited = true;
          break;
        }
        if (progress_) {
          std::ostringstream line;
          line << "round " << round + 1 << ": " << build_.kerf.critical.size()
               << " critical regions, " << small.size() << " parts too small to handle, "
               << build_.flat.strips.patches.size() << " parts";
          progress_(line.str());
        }
        if (pending.empty()) break;
        // 1. Crease splits and merges, tried together and kept where they resolve their region.
        Added trial = accepted_;
        std::vector<std::tuple<Region, Added, Remedy>> applied;
        for (const Region& region : pending) {
          bool failed = false;
          for (int q : region.quads) failed = failed || cheap_failed.count(q);
          if (failed) continue;
          for (Remedy remedy : {Remedy::kSplit, Remedy::kMerge}) {
            Added own;
            if (apply(remedy, region, trial, own)) {
              applied.push_back({region, own, remedy});
              break;
            }
          }
        }
        if (!applied.empty()) {
          std::optional<PartsBuild> tried;
          try {
            tried = rebuild(trial);
            ++out_.rounds;
          } catch (const InvalidInput&) {  // the strips refused a merge (a branch or a tube)
            for (const auto& a : applied)
              cheap_failed.insert(std::get<0>(a).quads.begin(), std::get<0>(a).quads.end());
          }
          if (tried) {
            const std::set<int> still = critical_quads(*tried);
            const Added before = accepted_;
            const std::size_t recorded = out_.changes.size();
            std::size_t kept = 0;
            for (const auto& [region, own, remedy] : applied) {
              bool resolved = true;
              const bool apart = region.small_part && remedy == Remedy::kSplit;
              if (apart) {
                // A part split where it fell apart: kept where its pieces now are parts, holding
                // its piece kept and half what it lost (their neighbours may be ones the loop
                // changes next, as the folded-back part whose mitre cut it through). build_ is
                // still the build the region was found in.
                const PartOutline& was = build_.joints.parts[region.patch];
                double lost = 0;
                for (const Polygon2& piece : was.lost) lost += std::abs(polygon_area(piece));
                std::set<int> parts;
                for (int q : region.quads) parts.insert(tried->flat.strips.quad_patch[q]);
                double area = 0;
                for (int q : parts)
                  if (q >= 0) area += area_as_cut(tried->joints.parts[q]);
                resolved = area >= area_as_cut(was) + 0.5 * lost;
              } else {
                for (int q : region.quads)
                  for (int n : with_neighbours(q)) resolved = resolved && !still.count(n);
              }
              if (!resolved) {
                cheap_failed.insert(region.quads.begin(), region.quads.end());
                continue;
              }
              merge_into(accepted_, own);
              record(region, remedy_name(remedy));
              if (apart)
                out_.changes.back().reason =
                    "split where the part fell apart when cut: the piece it lost is a part of its "
                    "own";
              ++kept;
            }
            if (kept == applied.size()) {
              build_ = std::move(*tried);
            } else if (kept > 0) {
              try {
                build_ = rebuild(accepted_);
                ++out_.rounds;
              } catch (const InvalidInput&) {  // the kept ones contradict each other alone
                accepted_ = before;
                out_.changes.resize(recorded);
                for (const auto& a : applied)
                  cheap_failed.insert(std::get<0>(a).quads.begin(), std::get<0>(a).quads.end());
              }
            }
          }
          pending = current_regions(small_now());
        }
        // 2. Facets where nothing cheaper applies or it did not help: no region's once the time
        // is up (a region's facets, and the rebuild after them, take seconds each on a large mesh,
        // and a round of them was once 117 s). The regions left are then left to the next round's
        // start, which ends the loop, or, where this round changed nothing, to this one's end.
        const Added before = accepted_;
        const std::size_t recorded = out_.changes.size();
        std::set<int> tried;
        int made = 0;
        bool stopped = false;  // at the time limit
        for (const Region& region : pending) {
          if (out_of_time()) {
            stopped = true;
            break;
          }
          bool failed = false;
          for (int q : region.quads) failed = failed || cheap_failed.count(q);
          Added scratch = accepted_, ignore;
          const bool cheap = apply(Remedy::kSplit, region, scratch, ignore) ||
                             apply(Remedy::kMerge, region, scratch, ignore);
          if (cheap && !failed) continue;  // its cheap remedy comes first, next round
          bool given_up = true;
          for (int q : region.quads) given_up = given_up && stuck_.count(q);
          if (given_up) continue;
          Added own;
          tried.insert(region.quads.begin(), region.quads.end());
          if (!facets(region, accepted_, own)) continue;
          record(region, remedy_name(Remedy::kFacets));
          ++made;
        }
        if (made == 0 && applied.empty()) {
          out_.time_limited = stopped;
          break;
        }
        if (made > 0) {
          consolidate_facets();
          try {
            build_ = rebuild(accepted_);
            ++out_.rounds;
          } catch (const InvalidInput&) {
            // The facets cut an earlier merge or split apart (the strips refuse the mix): this
            // round's facets are taken back and their regions not tried again.
            accepted_ = before;
            out_.changes.resize(recorded);
            stuck_.insert(tried.begin(), tried.end());
            cheap_failed.insert(tried.begin(), tried.end());
          }
        }
      }
      small = small_now();
      if (best) {
        const Best earlier = *best;  // the final build competes with the best one seen
        best.reset();
        keep_if_best(small);
        if (earlier.score < best->score) {
          build_ = earlier.build;
          accepted_ = earlier.accepted;
          out_.changes.resize(earlier.changes);
          small = small_now();
        }
      }
    }
    if (r_.enabled) cut_bent_facets_by_outline(small);
    // Leaving parts out frees their neighbours' borders: a neighbour cut back by them may then
    // hold, or be left out in turn (a few times at most). Once even past the time limit (one
    // rebuild: a part left with nothing once cut is worse than a late run), again only within.
    for (int k = 0; r_.enabled && k < 3 && (k == 0 || !out_of_time()) && omit_thin_parts(small);
         ++k) {
    }
    if (r_.enabled) split_thin_necks(small);
    bool narrow_unsized = false;  // a too-narrow region whose fit factor is unknown
    for (const CriticalRegion& c : build_.kerf.critical) {
      const Region r = region_of(build_.flat.strips, build_.flat.flattening, c);
      record(r, "unresolved");
      RegionChange& change = out_.changes.back();
      std::ostringstream why;
      if (out_.time_limited)
        why << "left when the loop reached its time limit (--resolve-time-limit)";
      else if (c.cause == CriticalCause::kTooNarrow)
        why << "a cut the bend needs does not fit the part there: between its joints the strip "
               "is too narrow for the margins, the bridge and the shortest cut";
      else if (c.cause == CriticalCause::kFan)
        why << "the cut lines converge across the strip: their narrow ends would come closer "
               "than the minimum spacing";
      else
        why << "the bend overstresses the beams even at the minimum spacing";
      if (c.cause == CriticalCause::kTooNarrow) {
        ++out_.narrow_after;
        narrow_unsized = narrow_unsized || !(c.fit_factor > 0);
        out_.narrow_size_mm = std::max(out_.narrow_size_mm, c.fit_factor * out_.current_size_mm);
      }
      change.reason = why.str();
    }
    if (narrow_unsized) out_.narrow_size_mm = 0;  // one unknown: none named
    const double max_angle = o_.flatten.max_angle_error;
    for (int p : small) {
      record(part_region(build_.flat.strips, p), "unresolved");
      out_.unresolved_parts.push_back(p);
      const double area = area_as_cut(build_.joints.parts[p]);
      RegionChange& c = out_.changes.back();
      std::ostringstream why;
      const PatchFlattening& flat = build_.flat.flattening.patches[p];
      double size_factor = area > 0 ? std::max(1.0, std::sqrt(r_.min_part_area / area)) : 0.0;
      if (distorted(build_, p, max_angle)) {
        // Its quads' angles are the same at every scale: no size cures it (fertility at 250 mm
        // named --size 336 for four parts, two of them facets flattening 44 deg off and
        // inverted; run there with its quads, the twisted one was still 36 deg off).
        size_factor = 0;
        ++out_.distorted_parts_after;
        why << (strips().patches[p].flat ? "facet " : "part ") << p << " flattens "
            << (flat.inverted_quads > 0 ? "with an inverted quad"
                : !flat.outline_simple
                    ? "crossing itself"
                    : "with a corner " +
                          std::to_string(static_cast<int>(flat.max_angle_error * 180 / M_PI)) +
                          " deg off its 3D angle")
            << (strips().patches[p].flat ? " (its corners are shared with facets at other angles)"
                                         : " (it twists or folds more than a sheet bends flat)");
      } else {
        why << "part " << p << " is too small to handle (" << area << " mm^2 as cut";
        if (build_.joints.parts[p].repaired) why << ", falls apart at its slots";
        // Its joints cut it back from its borders by a depth that does not grow with the
        // model: at its sharpest fold the most. It holds where it is that deep plus half the
        // narrowest part a maker can handle across (its inscribed circle's radius).
        const CutBack cut = deepest_cut_back(p);
        const Polygon2 outline = flat_outline(strips(), build_.flat.flattening, p);
        const double across = inscribed_radius(outline);
        const bool apart = build_.joints.parts[p].repaired;
        double whole = 0;  // of a part that fell apart: one_piece_factor(), or 1000 past it
        if (cut.depth > 0 && across > 0) {
          const double hold = hold_factor(cut, across);
          why << "; its joints cut it back up to " << cut.depth << " mm (beside part " << cut.other
              << ") and it is " << 2 * across << " mm across";
          if (cut.fold > kFoldBackAngle)
            why << ", folded back " << std::lround(cut.fold * 180 / M_PI)
                << " deg onto that part: the shape is thinner there than the sheets";
          size_factor = std::max(size_factor, hold);
          // Fallen apart: where the part is narrowest, not at its widest place. Not one piece
          // up to 40 times the size: a thousand times it, past any size stderr names.
          if (apart) {
            const double f = one_piece_factor(outline, cut, hold);
            whole = f > 0 ? f : 1000.0;
          }
        }
        // One that fell apart although cut back all round it is one piece at this size broke
        // where no rule here sees (a tip between two slots): no size is known for it.
        if (apart) {
          size_factor = whole > 1 ? std::max(size_factor, whole) : 0.0;
          if (size_factor == 0) ++out_.unsized_parts_after;
        }
        why << (out_.time_limited ? "; left when the loop reached its time limit)"
                                  : "; no flat plate around it is big enough)");
      }
      c.reason = why.str();
      c.size_factor = size_factor;  // 0: unknown
      out_.small_parts_size_mm =
          std::max(out_.small_parts_size_mm, size_factor * out_.current_size_mm);
      ++out_.small_parts_after;
    }
    std::sort(out_.unresolved_parts.begin(), out_.unresolved_parts.end());
    out_.seconds = seconds();
    finish();
    return std::move(out_);
  }

 private:
  PartsBuild& build_;
  const PreparedInput& in_;
  const PolyMesh& m_;
  const PartsOptions& o_;
  const ResolveOptions& r_;
  /// The loop's rebuilds are drafts (draft_options_: no stub teeth) until its last rounds.
  PartsOptions draft_options_;
  bool draft_ = false;
  const ResolveProgress& progress_;
  ResolveResult out_;
  Added accepted_;
  std::set<int> user_bendable_, user_merge_, user_split_;
  double tightest_bend_ = 0;     // of the first build [mm^2]
  mutable std::set<int> stuck_;  // quads of facets that could not grow big enough
  // Quads of facets that flattened inverted or crossing (corners shared with facets at other
  // angles bent them): regrown from single quads, flatter.
  mutable std::set<int> bent_;
  mutable std::vector<char> marked_;  // plane_of(): per quad-mesh vertex, met (cleared after)
  // Per quad its corners (quad_vertices), read once: the facet tests read them for every
  // neighbour of a growing facet.
  mutable std::vector<std::array<int, 4>> corners_;
  const std::array<int, 4>& corners_of(int q) const {
    if (corners_.empty()) {
      corners_.reserve(m_.n_faces());
      for (int f = 0; f < static_cast<int>(m_.n_faces()); ++f)
        corners_.push_back(quad_vertices(m_, m_.face_handle(f)));
    }
    return corners_[q];
  }
  // The rebuilds change a few regions each: most parts' outlines are drawn and most patches'
  // cuts placed once.
  PartsMemo own_memo_;
  PartsMemo& memo_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();

  /// Seconds since the loop started.
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  }
  /// True once the loop has run for its time limit.
  bool out_of_time() const { return seconds() >= r_.time_limit; }

  struct CutBack {
    double depth = 0;  ///< [mm]
    double fold = 0;   ///< [rad]
    int other = kNone;
  };

  /// The deepest cut-back of part \p p from its borders by its joints (mitres and slots), the
  /// fold in the middle of that stretch (its offsets are for the sharpest fold in it) and the
  /// part across it.
  CutBack deepest_cut_back(int p) const {
    CutBack out;
    for (const BorderJoint& b : build_.joints.borders) {
      if (b.patches[0] != p && b.patches[1] != p) continue;
      for (const JointInterval& in : b.intervals) {
        const double depth = std::max(-in.plain, -in.offsets.slot);
        if (depth > out.depth)
          out = {depth, std::abs(in.fold), b.patches[0] == p ? b.patches[1] : b.patches[0]};
      }
    }
    return out;
  }

  /// The factor on the model's size at which a part cut back by \p cut holds: its joints' cut-back
  /// does not grow with the model, the part does. It holds where it is that deep plus half the
  /// narrowest part a maker can handle across (\p radius: its inscribed circle's, as flattened
  /// [mm]). 0 where either is unknown.
  double hold_factor(const CutBack& cut, double radius) const {
    return cut.depth > 0 && radius > 0 ? (cut.depth + 0.5 * r_.min_part_width) / radius : 0.0;
  }

  /// The factor on the model's size from which on \p outline (a part's, as flattened [mm]), cut
  /// back all round by \p cut's depth plus half the narrowest part a maker can handle, stays
  /// one piece: a part that fell apart at its slots did so where it is narrower than at its
  /// inscribed circle, so hold_factor() can name a size at which it falls apart again
  /// (fertility from its triangles at 250 mm named --size 336 for a part 9.2 mm across, cut
  /// back 4.7 mm; run there with its quads it fell apart once more). Scanned from \p from in
  /// steps of 2 % up to 40 times the size; 0 where it is not one piece even there.
  double one_piece_factor(const Polygon2& outline, const CutBack& cut, double from) const {
    const double inset = cut.depth + 0.5 * r_.min_part_width;
    double found = 0;
    for (double f = std::max(from, 1.0); f <= 40; f *= 1.02) {
      Polygon2 scaled = outline;
      for (Vec2& v : scaled) v *= f;
      int pieces = 0;
      for (const Polygon2& core : polygon_offset_round({scaled}, -inset, 0.01))
        pieces += std::abs(polygon_area(core)) > 1e-6;
      if (pieces != 1)
        found = 0;
      else if (found == 0)
        found = f;
    }
    return found;
  }

  /// True when part \p p has nothing left to cut once its joints are cut (under a square
  /// millimetre, or fallen apart into pieces of which the largest is under --min-part-area):
  /// it is missing from the sheets whether it is left out or not.
  bool nothing_left(int p) const {
    const double area = area_as_cut(build_.joints.parts[p]);
    return area < 1.0 || (build_.joints.parts[p].repaired && area < r_.min_part_area);
  }

  /// Parts still too small to handle that no size or plate cures are left out where their
  /// neighbours hold the surface: one folded back onto a neighbour by more than 150 deg (the
  /// shape is thinner there than the sheets: the neighbour's sheet stands where it was), or one
  /// narrower across than --min-part-width (a sliver: the slit it leaves is narrower than the
  /// part was). A part of which its joints left nothing (nothing_left()) is left out wherever it
  /// is: it is missing from the sheets either way, but kept, its neighbours are cut back for a
  /// part that is not there and their borders with it have no joint (the bunny's ear tips at
  /// 250 mm: 12 such borders, and mitres 17 mm deep beside nothing). So is a part of any size
  /// inside out (inside_out_parts(): quads folded over their neighbours, which no size cures)
  /// where the parts kept stand within two sheets of it, and one that fell apart at its slots
  /// (a sliver or folded back too) where they stand within two sheets of it: kept, only its
  /// largest piece is cut and its border where it broke has no joint (fertility at 250 mm: a
  /// part 10.5 mm across where the statue is thin, cut back 1.8 mm by the mitre beside a facet
  /// folded onto the other side, its surface within 4.1 mm of the parts kept; the one border
  /// without a joint on the shared models at 250 mm). So is a facet still flattening distorted
  /// that its joints cut back under --min-part-area (kCrumb) where they stand within a sheet of
  /// it. Their neighbours' borders with them become free edges. Kept only where the build has
  /// fewer defects (critical regions and parts too small, parts inside out counted among them),
  /// or as many and fewer borders without a joint, after it: returns whether it was. \p small:
  /// small_now(), updated.
  bool omit_thin_parts(std::vector<int>& small) {
    enum class Why { kGone, kFolded, kSliver, kApart, kCrumb, kInsideOut };
    struct Omitted {
      int part;
      Why why;
      CutBack cut;
      double across;        // twice the radius of the largest circle in it, as flattened [mm]
      bool gone;            // nothing_left()
      double distance = 0;  // of its surface from the parts kept [mm]
      bool apart = false;   // fell apart at its slots
      double area = 0;      // as cut [mm^2]
    };
    std::vector<Omitted> omitted;
    for (int p : small) {
      const bool gone = nothing_left(p);
      // A facet that flattens bent is the outline cut's business (cut_bent_facets_by_outline),
      // unless its joints leave a crumb of it: fertility from its triangles at 500 mm kept a
      // facet flattening 35 deg off that its mitres cut back to 1.4 mm^2, cut as a part of its
      // own, its three neighbours' teeth going into it.
      const bool bent = !gone && bent_facet(build_, p, o_.flatten.max_angle_error);
      if (bent && area_as_cut(build_.joints.parts[p]) >= r_.min_part_area) continue;
      const CutBack cut = deepest_cut_back(p);
      const double across = 2 * inscribed_radius(flat_outline(strips(), build_.flat.flattening, p));
      if (cut.fold > kFoldBackAngle)
        omitted.push_back({p, Why::kFolded, cut, across, gone});
      else if (across < r_.min_part_width)
        omitted.push_back({p, Why::kSliver, cut, across, gone});
      else if (gone)
        omitted.push_back({p, Why::kGone, cut, across, gone});
      else if (build_.joints.parts[p].repaired)
        omitted.push_back({p, Why::kApart, cut, across, gone});
      else if (bent)
        omitted.push_back({p, Why::kCrumb, cut, across, gone});
    }
    // Parts inside out, small or not: no size cures them, and where they lie over the parts
    // beside them (checked below), those hold the surface.
    const std::vector<int> turned = inside_out_parts(build_);
    for (int p : turned)
      if (std::none_of(omitted.begin(), omitted.end(),
                       [&](const Omitted& o) { return o.part == p; }))
        omitted.push_back({p, Why::kInsideOut, deepest_cut_back(p), 0.0, false});
    if (omitted.empty()) return false;
    for (Omitted& o : omitted) o.area = area_as_cut(build_.joints.parts[o.part]);
    // How far the surface that was there lies from the parts kept, sampled on a 4 x 4 grid in
    // each of its sub-quads: left out only where the sheets a maker builds stand within a
    // sheet's thickness of it (leaving one out can only bring the others' distances down when it
    // is kept instead), or where nothing of it was left anyway.
    std::vector<char> out(strips().patches.size(), 0);
    for (const Omitted& o : omitted) out[o.part] = 1;
    TriangleMesh kept;
    kept.vertices = strips().vertices;
    for (std::size_t f = 0; f < strips().faces.size(); ++f) {
      const int p = strips().face_patch[f];
      if (p < 0 || out[p]) continue;
      const auto& q = strips().faces[f];
      kept.triangles.push_back({q[0], q[1], q[2]});
      kept.triangles.push_back({q[0], q[2], q[3]});
    }
    // A strip's sub-quad with two corners in one point (a strip end narrowed to a point) has
    // a triangle of no area, which the closest-point queries refuse: stanford-bunny in paper
    // at 200 mm failed here ("target triangle 2570 has zero area").
    kept = without_degenerate(kept);
    if (kept.triangles.empty()) return false;
    const TargetSurface surface(kept);
    Added trial = accepted_;
    std::vector<Omitted> left;
    for (Omitted& o : omitted) {
      const Patch& patch = strips().patches[o.part];
      const auto& x = strips().vertices;
      for (int f : patch.all_faces()) {
        const auto& q = strips().faces[f];
        for (double u : {0.125, 0.375, 0.625, 0.875})
          for (double v : {0.125, 0.375, 0.625, 0.875})
            o.distance = std::max(o.distance,
                                  surface
                                      .closest((1 - u) * (1 - v) * x[q[0]] + u * (1 - v) * x[q[1]] +
                                               u * v * x[q[2]] + (1 - u) * v * x[q[3]])
                                      .distance);
      }
      // Two sheets for a part inside out, or one that fell apart whatever else it is (folded
      // back or a sliver too): kept, its largest piece alone is cut.
      o.apart = build_.joints.parts[o.part].repaired;
      const double reach = (o.why == Why::kInsideOut || o.apart ? 2 : 1) * o_.material.thickness;
      if (o.distance > reach && !o.gone) continue;
      for (int q : patch.all_quads()) trial.guidance.omit.push_back(q);
      left.push_back(std::move(o));
    }
    if (left.empty()) return false;
    std::vector<Region> regions;
    for (const Omitted& o : left) regions.push_back(part_region(strips(), o.part));
    // Leaving parts out changes neither the strips nor their flattening: only the parts are
    // cut again.
    PartsBuild tried{build_.bending, build_.strips, build_.flat, {}, {}};
    try {
      cut_parts(tried, trial.guidance, o_, &memo_);
    } catch (const InvalidInput&) {
      return false;
    }
    const auto score = [&](const PartsBuild& b) {
      return std::pair(defects(b) + inside_out_parts(b).size(), b.joints.borders_without_joint);
    };
    if (score(tried) >= score(build_)) return false;
    ++out_.rounds;
    build_ = std::move(tried);
    accepted_ = std::move(trial);
    small = small_now();
    // The reasons name the neighbours by their numbers on the sheets (of the build without the
    // parts left out).
    std::vector<int> gone_before;
    for (const Omitted& o : left) gone_before.push_back(o.part);
    std::sort(gone_before.begin(), gone_before.end());
    const auto part = [&](int p) {
      const auto at = std::lower_bound(gone_before.begin(), gone_before.end(), p);
      if (at != gone_before.end() && *at == p) return std::string("another part left out");
      return "part " + std::to_string(p - static_cast<int>(at - gone_before.begin()));
    };
    for (std::size_t k = 0; k < left.size(); ++k) {
      const Omitted& o = left[k];
      record(regions[k], "omit");
      RegionChange& c = out_.changes.back();
      c.local_distance = o.distance;
      std::ostringstream why;
      why << "a part left out: ";
      switch (o.why) {
        case Why::kGone:
          // Missing from the sheets either way; left out, its neighbours are not cut back for
          // it. It holds at the size its joints leave it a handle's width.
          c.size_factor = hold_factor(o.cut, 0.5 * o.across);
          out_.gone_parts_size_mm =
              std::max(out_.gone_parts_size_mm, c.size_factor * out_.current_size_mm);
          out_.small_parts_size_mm = std::max(out_.small_parts_size_mm, out_.gone_parts_size_mm);
          ++out_.gone_parts;
          why << "nothing of it was left once its joints were cut (it is " << o.across
              << " mm across";
          if (o.cut.other >= 0)
            why << " and they cut it back up to " << o.cut.depth << " mm beside "
                << part(o.cut.other);
          why << ")";
          break;
        case Why::kFolded:
          why << "folded back " << std::lround(o.cut.fold * 180 / M_PI) << " deg onto "
              << part(o.cut.other) << ", the shape is thinner there than the sheets";
          break;
        case Why::kSliver:
          why << "a sliver " << o.across << " mm across, narrower than --min-part-width";
          break;
        case Why::kApart:
          why << "it fell apart at its slots, too small to handle (" << o.across << " mm across";
          if (o.cut.other >= 0)
            why << ", cut back up to " << o.cut.depth << " mm beside " << part(o.cut.other);
          why << "), where the shape is so thin that the parts kept stand within " << o.distance
              << " mm of its surface";
          break;
        case Why::kCrumb:
          why << "it flattens distorted (its corners are shared with facets at other angles) and "
                 "its joints leave only "
              << o.area << " mm^2 of it, under --min-part-area, where the parts kept stand within "
              << o.distance << " mm of its surface";
          break;
        case Why::kInsideOut:
          why << "inside out: its faces are turned against the target's (its quads fold over "
                 "the parts beside it, within "
              << o.distance << " mm of them)";
          break;
      }
      // What else made it go: left out wherever it is, or within two sheets.
      if (o.gone && o.why != Why::kGone)
        why << "; nothing of it was left once its joints were cut";
      else if (o.apart && o.why != Why::kApart)
        why << "; it fell apart at its slots";
      why << "; its neighbours' borders with it are free edges";
      c.reason = why.str();
    }
    return true;
  }

  /// Facets that narrow to a neck no joint made (Joints::thin_neck_parts; the joints stage
  /// mends the necks its slots and teeth make): at 250 mm, fandisk kept a facet of 9 quads where
  /// the mitre of a sharp fold reached within 0.75 mm of its far side, and decimated-max's
  /// QuadriFlow quads one with a quad hanging on such a neck. Each is cut in two facets between
  /// the two largest stretches (facet_quads_at_necks, two_groups), all in one rebuild; a
  /// stretch split off too small to handle then grows as the loop grows such a facet, once.
  /// Kept where the build has no more defects (critical regions and parts too small), fewer
  /// parts with a thin neck, no more borders without a joint and no more stubs held at a corner
  /// than the cuts' own borders after it; where it was not, each alone. Even past the time limit (a
  /// part that breaks at its neck is worse than a late run). \p small: small_now(), updated.
  void split_thin_necks(std::vector<int>& small) {
    const auto necks = [&] {
      std::vector<Region> out;
      for (int p : build_.joints.thin_neck_parts) {
        Region region = part_region(strips(), p);
        region.facet_groups = two_groups(facet_quads_at_necks(build_, p, o_.joints.min_feature));
        if (!region.facet_groups.empty()) out.push_back(std::move(region));
      }
      return out;
    };
    const std::vector<Region> regions = necks();
    const auto score = [&](const PartsBuild& b) {
      return std::tuple(defects(b), b.joints.thin_neck_parts.size(), b.joints.borders_without_joint,
                        b.joints.stubs_joined_at_corners);
    };
    // Tries the splits of \p tried together; true where kept.
    const auto attempt = [&](const std::vector<Region>& tried) {
      Added trial = accepted_;
      for (const Region& region : tried)
        if (!split_facet(region, trial)) return false;
      std::optional<PartsBuild> built;
      try {
        built = rebuild(trial);
      } catch (const InvalidInput&) {  // the strips refused the facets
        return false;
      }
      ++out_.rounds;
      // A stretch split off too small to handle grows as the loop grows such a facet (facets()),
      // once (decimated-max's QuadriFlow quads: one quad of 15 mm^2 hung on the neck).
      std::set<int> split_quads;
      for (const Region& region : tried)
        split_quads.insert(region.quads.begin(), region.quads.end());
      // Part \p p of \p b is a facet the cuts made (of the quads they split).
      const auto cut_facet = [&](const PartsBuild& b, int p) {
        const Patch& patch = b.flat.strips.patches[p];
        return patch.flat && !patch.quads.empty() && split_quads.count(patch.quads.front()) > 0;
      };
      std::vector<Region> grow;
      for (int p :
           small_parts(*built, r_.min_part_area, r_.min_part_width, o_.flatten.max_angle_error))
        if (cut_facet(*built, p)) grow.push_back(part_region(built->flat.strips, p));
      bool made = false;
      if (!grow.empty()) {
        std::swap(build_, *built);  // facets() reads the build the regions were found in
        Added own_facets;
        for (const Region& region : grow) made = facets(region, trial, own_facets) || made;
        std::swap(build_, *built);
        if (made) {
          try {
            built = rebuild(trial);
          } catch (const InvalidInput&) {
            return false;
          }
          ++out_.rounds;
        }
      }
      // The border a cut makes between its two facets lies across the neck and is short
      // (fandisk: 0.38 mm): held at a corner, it counts as one stub more; any other border it
      // leaves held only at a corner is one too many (Spot's fine quad mesh from its triangles:
      // a 1.6 mm border lost its tooth beside the 5.1 mm cut). Left without a joint, it counts
      // against the cut only where it is at least the smallest feature long (the report counts
      // it either way): a shorter one is where the neck was, which no tooth or slot could cross
      // either and which broke where the part was handled (fandisk from its triangles at 250 mm
      // in 4 mm plywood: a facet of 6 quads on a neck 0.38 mm wide, cut in two across it).
      const auto [defects_before, necks_before, bare_before, stubs_before] = score(build_);
      const auto [defects_after, necks_after, bare_after, stubs_after] = score(*built);
      int bare_at_necks = 0;  // cuts' own borders, shorter than the smallest feature
      for (const BorderJoint& border : built->joints.borders) {
        if (border.kind() != "none" || !(border.length < o_.joints.min_feature)) continue;
        bare_at_necks +=
            cut_facet(*built, border.patches[0]) && cut_facet(*built, border.patches[1]) ? 1 : 0;
      }
      if (defects_after > defects_before || necks_after >= necks_before ||
          bare_after > bare_before + bare_at_necks ||
          stubs_after > stubs_before + static_cast<int>(tried.size()))
        return false;
      build_ = std::move(*built);
      accepted_ = std::move(trial);
      for (const Region& region : tried) {
        record(region, remedy_name(Remedy::kSplit));
        out_.changes.back().reason =
            "split where the part narrowed to a neck under the smallest feature: each stretch "
            "is a part of its own";
      }
      for (const Region& region : made ? grow : std::vector<Region>{}) {
        record(region, remedy_name(Remedy::kFacets));
        out_.changes.back().reason = "a stretch split off at a neck, grown to be handled";
      }
      return true;
    };
    if (regions.empty() || attempt(regions) || regions.size() == 1) {
      small = small_now();
      return;
    }
    // One at a time, each found again in the build as the ones before left it.
    std::set<int> seen;  // quads of the facets tried
    for (;;) {
      const std::vector<Region> left = necks();
      const auto next = std::find_if(left.begin(), left.end(),
                                     [&](const Region& r) { return !seen.count(r.quads.front()); });
      if (next == left.end()) break;
      seen.insert(next->quads.begin(), next->quads.end());
      attempt({*next});
    }
    small = small_now();
  }

  /// Facets still bent when the loop ends (it regrows a bent facet from its single quads under a
  /// tighter flatness first: a facet bends where its quads tilt steeply from its plane, far from
  /// the target) are cut along their outline alone where that flattens them within the limits
  /// (flatten_facet_by_outline): a horse's ears were capped by facets of quads up to 85 deg off
  /// their planes, flattened 130 to 280 deg off, with inverted quads. Kept where the build has
  /// fewer defects after it, or as many with fewer parts distorted (demosthenes: a hair facet
  /// cut so lay flat but fell apart at its slots; kept distorted, three borders beside it had
  /// no joint). \p small: small_now(), updated.
  void cut_bent_facets_by_outline(std::vector<int>& small) {
    CuttablePatches flat = build_.flat;
    std::vector<int> changed;
    for (int p : small) {
      if (!bent_facet(build_, p, o_.flatten.max_angle_error)) continue;
      FlattenOptions options = o_.flatten;
      options.mimic_3d = false;  // as in every build: measured once, on the final one
      auto cut = flatten_facet_by_outline(flat.strips, p, options);
      if (!cut || distorted(*cut, o_.flatten.max_angle_error)) continue;
      flat.flattening.patches[p] = std::move(*cut);
      changed.push_back(p);
    }
    if (changed.empty()) return;
    summarise_flattening(flat.strips, flat.flattening);
    PartsBuild tried{build_.bending, build_.strips, std::move(flat), {}, {}};
    try {
      cut_parts(tried, accepted_.guidance, o_, &memo_);
    } catch (const InvalidInput&) {
      return;
    }
    // Fewer defects, or as many with fewer of them distorted: a part that falls apart at its
    // slots keeps its largest piece, one flattened distorted does not fit its neighbours.
    const auto distorted_count = [&](const PartsBuild& b) {
      std::size_t n = 0;
      for (std::size_t p = 0; p < b.flat.flattening.patches.size(); ++p)
        n += distorted(b, static_cast<int>(p), o_.flatten.max_angle_error) ? 1 : 0;
      return n;
    };
    const std::size_t now = defects(build_), after = defects(tried);
    if (after > now || (after == now && distorted_count(tried) >= distorted_count(build_))) return;
    build_ = std::move(tried);
    small = small_now();
    for (int p : changed) {
      record(part_region(strips(), p), "outline");
      std::ostringstream why;  // no part number: leaving parts out after this renumbers them
      why << "a facet whose quads could not lie flat together, cut along its outline ("
          << std::lround(build_.flat.flattening.patches[p].max_angle_error * 180 / M_PI)
          << " deg off its corners' angles at most)";
      out_.changes.back().reason = why.str();
    }
  }

  /// Flat panels of the model cut as one plate each, before the loop: a box from its
  /// triangles came out as 48 strips, 8 to a face, each a row of flat quads joined to the next
  /// by dovetail tabs along its whole length, where a maker expects 6 panels. Quads connected
  /// across edges whose corners all lie within kPlateFlatness of a seed quad's plane, facing
  /// its way, form a region; one of at least two quads, bounded by folds (bounded_by_folds() at
  /// least kPlateBounded: fandisk's flat sides, not a flat stretch that a bent strip runs on
  /// from, where plates only cut the strips short), that is a plate (plate(): a disk with a
  /// simple outline on its plane), a part a maker can handle (big_enough()) and fits the sheet
  /// becomes a facet, its edges stiff, as the loop's facets are. Curved ground never qualifies:
  /// neighbouring quads on a curve are at an angle (a sphere of 125 mm radius in quads of
  /// 20 mm: 9 deg), far over what the flatness allows. Kept where the build has no more
  /// defects after it (critical regions and parts too small).
  void plates_for_flat_regions() {
    const int n = static_cast<int>(m_.n_faces());
    std::vector<char> seen(n, 0);
    Added trial = accepted_;
    std::vector<std::vector<std::set<int>>> plates;  // per flat region, its plates
    // Whether a quad's middle lies on the model (within kPlateFlatness): asked once per quad,
    // though every seed beside it looks at it again.
    std::vector<signed char> model_under(n, -1);
    const auto on_model = [&](int q) {
      if (model_under[q] < 0)
        model_under[q] = in_.surface.closest(middle(q)).distance <= kPlateFlatness ? 1 : 0;
      return model_under[q] == 1;
    };
    for (int seed = 0; seed < n; ++seed) {
      if (seen[seed] || accepted_.facet_quads.count(seed)) continue;
      seen[seed] = 1;
      const Vec3 normal = quad_normal(seed);
      if (!(normal.norm() > 0)) continue;
      const Vec3 origin = corner(corners_of(seed)[0]);
      // The quad flat, and the model under it too: a cylinder's wall swept in columns along
      // its axis has every column's quads in one plane, their corners on the model and their
      // middles inside it (a column of 30 mm radius in 16 columns: 0.58 mm), and two of them
      // were cut as plates 250 mm long, their rings around them cut in two (26 -> 54 parts).
      auto on_plane = [&](int q) {
        if (quad_normal(q).dot(normal) < std::cos(kPlateTilt)) return false;
        for (int v : corners_of(q))
          if (std::abs((corner(v) - origin).dot(normal)) > kPlateFlatness) return false;
        return on_model(q);
      };
      if (!on_plane(seed)) continue;
      std::set<int> group = {seed};
      std::vector<int> todo = {seed};
      while (!todo.empty()) {
        const int q = todo.back();
        todo.pop_back();
        for (auto f : m_.ff_range(m_.face_handle(q))) {
          const int g = f.idx();
          if (seen[g] || accepted_.facet_quads.count(g) || !on_plane(g)) continue;
          seen[g] = 1;
          group.insert(g);
          todo.push_back(g);
        }
      }
      if (group.size() < 2 || bounded_by_folds(group, normal) < kPlateBounded) continue;
      // Each piece a plate that fits the sheet, or the region stays as it is.
      std::vector<std::set<int>> pieces;
      bool handy = true;
      for (std::set<int>& piece : plate_pieces(group, kPlateCuts)) {
        std::vector<std::set<int>> fit = fitting_pieces(std::move(piece));
        handy = handy && !fit.empty();
        for (std::set<int>& f : fit) pieces.push_back(std::move(f));
      }
      if (pieces.empty() || !handy) continue;
      for (const std::set<int>& piece : pieces)
        add_facet({piece.begin(), piece.end()}, trial, nullptr);
      plates.push_back(std::move(pieces));
    }
    if (plates.empty()) return;
    // All at once; where that leaves more defects, one by one, each kept where it adds none
    // (a house at 150 mm: all seven gave a defect more and none was kept, so 58 parts).
    const auto try_build = [&](const Added& state) -> std::optional<PartsBuild> {
      try {
        std::optional<PartsBuild> b = rebuild(state);
        ++out_.rounds;
        if (defects(*b) > defects(build_)) return std::nullopt;
        return b;
      } catch (const InvalidInput&) {  // the strips refuse the mix (a user's merge across one)
        return std::nullopt;
      }
    };
    // One by one: a flat region's plates (more than one where it was cut to fit the sheet)
    // together.
    std::vector<std::set<int>> kept;
    if (std::optional<PartsBuild> all = try_build(trial)) {
      build_ = std::move(*all);
      accepted_ = std::move(trial);
      for (auto& region : plates)
        for (std::set<int>& group : region) kept.push_back(std::move(group));
    } else if (plates.size() > 1) {
      for (auto& region : plates) {
        if (out_of_time()) break;  // a rebuild each: a model of many faces could take minutes
        Added one = accepted_;
        for (const std::set<int>& group : region)
          add_facet({group.begin(), group.end()}, one, nullptr);
        std::optional<PartsBuild> b = try_build(one);
        if (!b) continue;
        build_ = std::move(*b);
        accepted_ = std::move(one);
        for (std::set<int>& group : region) kept.push_back(std::move(group));
      }
    }
    for (const std::set<int>& group : kept) {
      Region r;
      r.quads.assign(group.begin(), group.end());
      int corners = 0;
      for (int q : group)
        for (int v : corners_of(q)) r.centre += corner(v), ++corners;
      r.centre /= corners;
      record(r, "plate");
      out_.changes.back().reason = "a flat panel of the model, cut as one plate";
    }
  }

  /// A flat region \p group as plates: itself where it is one (plate()); where it is not a disk
  /// (a face with a hole, as the top of a square frame, came out as a part per quad) the pieces
  /// on either side of a line through its middle across its longer side, each connected piece
  /// cut again the same way where it still is not a disk, at most \p cuts deep. Empty where a
  /// piece is a disk but no plate, or still not a disk at that depth.
  std::vector<std::set<int>> plate_pieces(const std::set<int>& group, int cuts) const {
    if (plate(group)) return {group};
    if (cuts == 0 || disk(group)) return {};
    std::vector<std::set<int>> out;
    for (const std::set<int>& piece : halves(group)) {
      std::vector<std::set<int>> more = plate_pieces(piece, cuts - 1);
      if (more.empty()) return {};
      for (std::set<int>& m : more) out.push_back(std::move(m));
    }
    return out;
  }

  /// The plate \p piece itself where it fits the sheet with room for its teeth
  /// (with_room_for_teeth()), else in pieces that do, each a plate; empty where a piece would be
  /// too small to handle (big_enough()) or no grid qualifies. The pieces are the cells of a grid
  /// of na x nb along the sides of the plate's smallest rectangle on its plane (na, nb up to
  /// kPlateGrid), cut between quads so that each cell holds about as many of them as the next,
  /// each grid both cut between rows of quads and as evenly as the quads allow, where the two
  /// differ (of as many pieces, one cut between rows is taken first). Each grid's sheets
  /// are estimated: each piece, grown by its teeth and the spacing, counts as one over as many
  /// of its size as fit on a sheet in rows and columns. Of the grids whose pieces fit, the one
  /// of fewest pieces within kPlateSheetSlack of the fewest sheets is taken (a piece per sheet
  /// where smaller pieces would pack two or three to one costs sheets; smaller pieces than
  /// needed cost parts, joints and cutting time). A 250 mm box on a 300 x 200 mm laser bed had its
  /// faces (250 x 250 mm, over the bed's 280 x 180 inside its margins) cut as 48 strips, 8 to a
  /// face, joined along their whole length by dovetail tabs; now each face is two plates of 250 x
  /// 125 mm.
  std::vector<std::set<int>> fitting_pieces(std::set<int> piece) const {
    const LayoutOptions sheet = with_room_for_teeth();
    const Plane pl = plane_of(piece);
    const Polygon2 outline = plane_outline(piece, pl);
    if (fits_sheet(outline, sheet))
      return big_enough(piece) ? std::vector<std::set<int>>{std::move(piece)}
                               : std::vector<std::set<int>>{};
    // The quads' middles in the frame of the smallest rectangle.
    const MinRect rect = min_area_rect(outline);
    const Vec2 a(std::cos(rect.angle), std::sin(rect.angle)), b(-a.y(), a.x());
    std::vector<int> quads(piece.begin(), piece.end());
    std::vector<double> along_a, along_b;
    for (int q : quads) {
      const Vec3 c = middle(q);
      const Vec2 in_plane((c - pl.mean).dot(pl.u), (c - pl.mean).dot(pl.w));
      along_a.push_back(in_plane.dot(a)), along_b.push_back(in_plane.dot(b));
    }
    // Thresholds between n cells along one side, each holding about as many quads as the next:
    // at the first gap between the sorted middles over a micrometre from the even split on. Where
    // the quads of a row are not quite in line (the house's gable, its quads bent towards the
    // roof) that one can cut through a row and leave one quad on the other piece, a bump 25 mm
    // wide; \p straight: a gap of at least half a quad's size (the middles of two rows lie a
    // quad apart) within a quarter of a cell's share of the even split from it on, where there
    // is one, so that the cut runs between two rows. (Where the quads lie in rows the two are
    // the same gap; quads in no rows, as round a disc, have no such gap.)
    const double quad_size = std::sqrt(std::abs(polygon_area(outline)) / quads.size());
    // \p at sorted.
    const auto thresholds = [quad_size](const std::vector<double>& at, int n,
                                        bool straight) -> std::optional<std::vector<double>> {
      const int count = static_cast<int>(at.size());
      const int reach = std::max(1, count / (4 * n));
      std::vector<double> t;
      for (int k = 1; k < n; ++k) {
        const int even = static_cast<int>(std::lround(static_cast<double>(k) * count / n));
        int j = -1;
        for (int i = std::max(even, 1); straight && i <= std::min(count - 1, even + reach) && j < 0;
             ++i)
          if (at[i] - at[i - 1] >= 0.5 * quad_size) j = i;
        if (j < 0)
          for (j = even; j < count && j > 0 && at[j] - at[j - 1] < 1e-3;) ++j;
        if (j <= 0 || j >= count) return std::nullopt;
        const double cut = 0.5 * (at[j - 1] + at[j]);
        if (!t.empty() && cut <= t.back()) return std::nullopt;
        t.push_back(cut);
      }
      return t;
    };
    const Vec2 stock = o_.usable.size_of(-1);
    const double width = stock.x() - 2 * o_.usable.margin,
                 height = stock.y() - 2 * o_.usable.margin;
    const double grown = 2 * o_.material.thickness + sheet.spacing;  // teeth both sides, spacing
    const auto share = [&](const Polygon2& poly) {                   // of a sheet [-]
      const MinRect r = min_area_rect(poly);
      const auto per_sheet = [&](double w, double h) {
        return std::floor((width + sheet.spacing) / (w + grown)) *
               std::floor((height + sheet.spacing) / (h + grown));
      };
      const double n = std::max(per_sheet(r.width, r.height), per_sheet(r.height, r.width));
      return n >= 1 ? 1 / n : 1.0;
    };
    // Every grid whose pieces fit the sheet, cut between rows and as evenly as the middles
    // allow (where the two differ), with its pieces and sheets; then the qualifying one of
    // fewest pieces within kPlateSheetSlack of the fewest sheets, one cut between rows first.
    struct Grid {
      double sheets;
      std::vector<std::set<int>> pieces;
      bool straight;
    };
    // The cuts along each side into 1 to kPlateGrid cells: [side][straight ? 0 : 1][cells].
    using Cuts = std::optional<std::vector<double>>;
    std::array<std::array<std::array<Cuts, kPlateGrid + 1>, 2>, 2> cuts;
    for (int side = 0; side < 2; ++side) {
      std::vector<double> at = side == 0 ? along_a : along_b;
      std::sort(at.begin(), at.end());
      for (int v = 0; v < 2; ++v)
        for (int n = 1; n <= kPlateGrid; ++n) cuts[side][v][n] = thresholds(at, n, v == 0);
    }
    std::vector<Grid> grids;
    for (int na = 1; na <= kPlateGrid; ++na)
      for (int nb = 1; nb <= kPlateGrid; ++nb)
        for (const bool straight : {true, false}) {
          if (na * nb == 1 || na * nb > static_cast<int>(quads.size())) continue;
          const Cuts &ta = cuts[0][straight ? 0 : 1][na], &tb = cuts[1][straight ? 0 : 1][nb];
          if (!ta || !tb) continue;
          if (!straight && ta == cuts[0][0][na] && tb == cuts[1][0][nb]) continue;  // the same grid
          std::map<int, std::set<int>> cells;
          for (std::size_t i = 0; i < quads.size(); ++i) {
            const int ia = static_cast<int>(std::upper_bound(ta->begin(), ta->end(), along_a[i]) -
                                            ta->begin());
            const int ib = static_cast<int>(std::upper_bound(tb->begin(), tb->end(), along_b[i]) -
                                            tb->begin());
            cells[ia * kPlateGrid + ib].insert(quads[i]);
          }
          Grid g{0, {}, straight};
          for (auto& [cell, members] : cells)
            for (std::set<int>& c : connected_pieces(members)) g.pieces.push_back(std::move(c));
          bool fits = true;
          for (const std::set<int>& c : g.pieces) {
            const Polygon2 poly = plane_outline(c);
            fits = fits && fits_sheet(poly, sheet);
            if (!fits) break;
            g.sheets += share(poly);
          }
          if (fits) grids.push_back(std::move(g));
        }
    if (grids.empty()) return {};
    double fewest = std::numeric_limits<double>::infinity();
    for (const Grid& g : grids) fewest = std::min(fewest, g.sheets);
    std::sort(grids.begin(), grids.end(), [](const Grid& x, const Grid& y) {
      if (x.pieces.size() != y.pieces.size()) return x.pieces.size() < y.pieces.size();
      return x.straight != y.straight ? x.straight : x.sheets < y.sheets;
    });
    for (Grid& g : grids) {
      if (g.sheets > (1 + kPlateSheetSlack) * fewest + 1e-9) continue;
      bool handy = true;
      for (const std::set<int>& c : g.pieces) handy = handy && plate(c) && big_enough(c);
      if (handy) return std::move(g.pieces);
    }
    return {};
  }

  /// The sheet less its margins and less what a facet's teeth may reach past its outline on
  /// its plane (its margins grown by a sheet's thickness: box teeth reach half of it, dovetail
  /// tabs half a tooth's width, both at most the thickness with the defaults).
  LayoutOptions with_room_for_teeth() const {
    LayoutOptions sheet = o_.usable;
    sheet.margin += o_.material.thickness;
    return sheet;
  }
  /// True when a facet whose outline on its plane is \p outline fits the sheet with its teeth
  /// (with_room_for_teeth()): a facet is never split to fit, so facets join only so far.
  bool fits_with_teeth(const Polygon2& outline) const {
    return fits_sheet(outline, with_room_for_teeth());
  }

  /// The pieces of the quads \p group connected across their edges.
  std::vector<std::set<int>> connected_pieces(std::set<int> left) const {
    std::vector<std::set<int>> out;
    while (!left.empty()) {
      std::set<int> piece = {*left.begin()};
      std::vector<int> todo = {*left.begin()};
      left.erase(left.begin());
      while (!todo.empty()) {
        const int q = todo.back();
        todo.pop_back();
        for (auto f : m_.ff_range(m_.face_handle(q)))
          if (left.erase(f.idx()) > 0) piece.insert(f.idx()), todo.push_back(f.idx());
      }
      out.push_back(std::move(piece));
    }
    return out;
  }

  /// The connected pieces of the quads \p group on either side of a line through its middle
  /// (on its plane, the quads' centres) across its longer side.
  std::vector<std::set<int>> halves(const std::set<int>& group) const {
    const Plane p = plane_of(group);
    double lo_u = std::numeric_limits<double>::infinity(), hi_u = -lo_u, lo_w = lo_u, hi_w = -lo_u;
    for (int q : group) {
      const Vec3 d = middle(q) - p.mean;
      lo_u = std::min(lo_u, d.dot(p.u)), hi_u = std::max(hi_u, d.dot(p.u));
      lo_w = std::min(lo_w, d.dot(p.w)), hi_w = std::max(hi_w, d.dot(p.w));
    }
    const Vec3 across = hi_u - lo_u >= hi_w - lo_w ? p.u : p.w;
    std::array<std::set<int>, 2> sides;
    for (int q : group) sides[(middle(q) - p.mean).dot(across) > 0 ? 1 : 0].insert(q);
    std::vector<std::set<int>> out;
    for (const std::set<int>& side : sides)
      for (std::set<int>& piece : connected_pieces(side)) out.push_back(std::move(piece));
    return out;
  }

  /// The share of the outline of the quads \p group (facing \p normal) that lies on a fold
  /// sharper than kPlateFold or on the model's border, by length.
  double bounded_by_folds(const std::set<int>& group, const Vec3& normal) const {
    double folded = 0, all = 0;
    for (int q : group)
      for (auto h : m_.fh_range(m_.face_handle(q))) {
        const auto other = m_.opposite_face_handle(h);
        if (other.is_valid() && group.count(other.idx())) continue;
        const double length =
            (corner(m_.to_vertex_handle(h).idx()) - corner(m_.from_vertex_handle(h).idx())).norm();
        all += length;
        if (!other.is_valid() || quad_normal(other.idx()).dot(normal) < std::cos(kPlateFold))
          folded += length;
      }
    return all > 0 ? folded / all : 0.0;
  }

  /// Parts of \p b that lie inside out: over more than half their area their faces are turned
  /// against the target's normal at the nearest point (quads folded over their neighbours: a
  /// quad of bunny_closed's own mesh bridged an ear's base, and the part cut from it lay 0.04 mm
  /// over three others, facing them).
  std::vector<int> inside_out_parts(const PartsBuild& b) const {
    const Strips& s = b.flat.strips;
    std::vector<double> turned(s.patches.size(), 0.0), all(s.patches.size(), 0.0);
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
      const int p = s.face_patch[f];
      if (p < 0 || p >= static_cast<int>(s.patches.size())) continue;
      const auto& q = s.faces[f];
      const auto& x = s.vertices;
      const Vec3 n = 0.5 * (x[q[2]] - x[q[0]]).cross(x[q[3]] - x[q[1]]);
      const double area = n.norm();
      if (!(area > 0)) continue;
      const Vec3 centre = 0.25 * (x[q[0]] + x[q[1]] + x[q[2]] + x[q[3]]);
      all[p] += area;
      if (n.dot(in_.surface.closest(centre).normal) < 0) turned[p] += area;
    }
    std::vector<int> out;
    for (std::size_t p = 0; p < all.size(); ++p)
      if (turned[p] > 0.5 * all[p]) out.push_back(static_cast<int>(p));
    return out;
  }

  /// Critical regions and parts too small or narrow to handle in \p b.
  std::size_t defects(const PartsBuild& b) const {
    return b.kerf.critical.size() +
           small_parts(b, r_.min_part_area, r_.min_part_width, o_.flatten.max_angle_error).size();
  }

  /// The radius of the largest circle inside \p outline, to 1 % [mm].
  static double inscribed_radius(const std::vector<Vec2>& outline) {
    if (outline.size() < 3) return 0;
    Polygon2 poly(outline.begin(), outline.end());
    make_counter_clockwise(poly);
    double lo = 0, hi = std::sqrt(std::abs(polygon_area(poly)) / M_PI) + 1e-9;
    while (hi - lo > 0.01 * hi) {
      const double mid = 0.5 * (lo + hi);
      (polygon_offset({poly}, -mid).empty() ? hi : lo) = mid;
    }
    return lo;
  }

  /// True when one of \p quads was in a facet that flattened bent.
  template <class Quads>
  bool any_bent(const Quads& quads) const {
    return std::any_of(quads.begin(), quads.end(), [&](int q) { return bent_.count(q) > 0; });
  }

  PartsBuild rebuild(const Added& a) {
    return build_parts(
        in_, draft_ ? draft_options_ : o_, a.guidance,
        a.stiff == accepted_.stiff && a.guidance.edges.size() == accepted_.guidance.edges.size()
            ? &build_.bending
            : nullptr,
        &memo_);
  }

  static void merge_into(Added& into, const Added& from) {
    auto& g = into.guidance;
    g.edges.insert(g.edges.end(), from.guidance.edges.begin(), from.guidance.edges.end());
    g.split.insert(g.split.end(), from.guidance.split.begin(), from.guidance.split.end());
    g.merge.insert(g.merge.end(), from.guidance.merge.begin(), from.guidance.merge.end());
    g.facets.insert(g.facets.end(), from.guidance.facets.begin(), from.guidance.facets.end());
    into.facet_quads.insert(from.facet_quads.begin(), from.facet_quads.end());
    into.stiff.insert(from.stiff.begin(), from.stiff.end());
    into.merge.insert(from.merge.begin(), from.merge.end());
    into.split.insert(from.split.begin(), from.split.end());
  }

  /// The parts of the current build too small or narrow to handle (small_parts).
  std::vector<int> small_now() const {
    return small_parts(build_, r_.min_part_area, r_.min_part_width, o_.flatten.max_angle_error);
  }

  /// What the loop works on: critical regions, and parts too small or too narrow to handle.
  /// Facets that could not grow into a part a maker can handle are not tried again: each try
  /// would release and regrow the same quads.
  /// \p small: small_now() of the current build.
  std::vector<Region> current_regions(const std::vector<int>& small) const {
    std::vector<Region> out;
    for (const CriticalRegion& c : build_.kerf.critical)
      out.push_back(region_of(build_.flat.strips, build_.flat.flattening, c));
    for (int p : small) {
      const Patch& patch = build_.flat.strips.patches[p];
      if (bent_facet(build_, p, o_.flatten.max_angle_error))
        for (int q : patch.all_quads()) bent_.insert(q);
      bool tried = patch.flat;
      for (int q : patch.all_quads()) tried = tried && stuck_.count(q);
      if (tried) continue;
      out.push_back(part_region(build_.flat.strips, p));
      out.back().apart_at = columns_apart(build_, p, r_.min_part_area);
    }
    return out;
  }

  /// Quads of the critical regions and small parts of \p b.
  std::set<int> critical_quads(const PartsBuild& b) const {
    std::set<int> out;
    for (const CriticalRegion& c : b.kerf.critical) {
      const Region r = region_of(b.flat.strips, b.flat.flattening, c);
      out.insert(r.quads.begin(), r.quads.end());
    }
    for (int p : small_parts(b, r_.min_part_area, r_.min_part_width, o_.flatten.max_angle_error)) {
      const auto quads = b.flat.strips.patches[p].all_quads();
      out.insert(quads.begin(), quads.end());
    }
    return out;
  }

  /// Quad \p q and the quads sharing an edge with it.
  std::vector<int> with_neighbours(int q) const {
    std::vector<int> out = {q};
    for (auto f : m_.ff_range(m_.face_handle(q))) out.push_back(f.idx());
    return out;
  }

  void record(const Region& r, const std::string& action) {
    RegionChange c;
    c.centre = r.centre;
    c.quads = r.quads;
    c.action = action;
    c.spacing = r.spacing;
    c.stress_ratio = r.stress_ratio;
    c.size_factor = size_factor(r, o_.material, o_.kerf);
    out_.changes.push_back(std::move(c));
  }

  const Strips& strips() const { return build_.flat.strips; }

  static void add_edge(const PolyMesh& m, int e, std::set<int>& set, std::set<int>& own_set,
                       std::vector<std::array<int, 2>>& list) {
    set.insert(e);
    own_set.insert(e);
    list.push_back(ends(m, e));
  }

  /// Adds remedy \p remedy for region \p r to \p state (and, alone, to \p own); false where it
  /// does not apply.
  bool apply(Remedy remedy, const Region& r, Added& state, Added& own) const {
    if (r.small_part && remedy == Remedy::kSplit)
      return !r.apart_at.empty() && split_apart(r, state, own);
    if (strips().patches[r.patch].flat && remedy != Remedy::kFacets) return false;  // no strip
    switch (remedy) {
      case Remedy::kSplit:
        return split_crease(r, state, own);
      case Remedy::kMerge:
        return merge_sideways(r, state, own);
      case Remedy::kFacets:
        return facets(r, state, own);
    }
    return false;
  }

  /// A border at the sharpest fold between two quads in or at the ends of the region: a joint
  /// takes that fold instead of the kerf cuts (one more part, no loss of fidelity). For a
  /// crease this is the cure; for a bend spread over the quads it may take off just enough.
  bool split_crease(const Region& r, Added& state, Added& own) const {
    const Patch& p = strips().patches[r.patch];
    const auto starts = column_starts(strips(), p);
    double best = 0;
    int at = kNone;
    for (int col = std::max(1, r.c0);
         col <= std::min(r.c1 + 1, static_cast<int>(p.quads.size()) - 1); ++col) {
      const double fold = fold_at(strips(), p, starts[col]);
      if (fold > best) best = fold, at = col;
    }
    if (at == kNone) return false;
    const int edge = p.ruling_edges[starts[at]];
    if (!splittable(edge, state)) return false;
    add_split(edge, state, own);
    return true;
  }

  /// True where coarse edge \p edge (-1: a ruling inside a quad) may become a strip border: no
  /// merge, the user's or the loop's, runs across it, and it is not one already.
  bool splittable(int edge, const Added& state) const {
    return edge >= 0 && !state.merge.count(edge) && !user_merge_.count(edge) &&
           !state.split.count(edge);
  }

  /// Adds a strip border at coarse edge \p edge to \p state (and, alone, to \p own).
  void add_split(int edge, Added& state, Added& own) const {
    add_edge(m_, edge, state.split, own.split, state.guidance.split);
    own.guidance.split.push_back(ends(m_, edge));
  }

  /// Splits at the columns of \p r.apart_at (columns_apart): each piece the part fell into
  /// becomes a part of its own.
  bool split_apart(const Region& r, Added& state, Added& own) const {
    const Patch& p = strips().patches[r.patch];
    const auto starts = column_starts(strips(), p);
    std::vector<int> edges;
    for (int col : r.apart_at) {
      const int edge = p.ruling_edges[starts[col]];
      if (!splittable(edge, state)) return false;
      edges.push_back(edge);
    }
    for (int edge : edges) add_split(edge, state, own);
    return true;
  }

  /// \p groups of quads (none, or two or more) merged down to two: the one of fewest quads joins
  /// the group it shares the most quad edges with, until two are left. The split then comes only
  /// between the two largest stretches (spot_quadrangulated at 250 mm: a facet split in three
  /// left a piece too small to handle).
  std::vector<std::vector<int>> two_groups(std::vector<std::vector<int>> groups) const {
    while (groups.size() > 2) {
      const std::size_t smallest = static_cast<std::size_t>(
          std::min_element(groups.begin(), groups.end(),
                           [](const std::vector<int>& a, const std::vector<int>& b) {
                             return a.size() < b.size();
                           }) -
          groups.begin());
      const std::set<int> in(groups[smallest].begin(), groups[smallest].end());
      std::size_t best = smallest == 0 ? 1 : 0, most = 0;
      for (std::size_t g = 0; g < groups.size(); ++g) {
        if (g == smallest) continue;
        std::size_t shared = 0;
        for (int q : groups[g])
          for (auto f : m_.ff_range(m_.face_handle(q))) shared += in.count(f.idx());
        if (shared > most) best = g, most = shared;
      }
      groups[best].insert(groups[best].end(), groups[smallest].begin(), groups[smallest].end());
      groups.erase(groups.begin() + static_cast<std::ptrdiff_t>(smallest));
    }
    return groups;
  }

  /// Replaces the loop's facet of region \p r's quads in \p state by the groups
  /// r.facet_groups, each a facet of its own; false where the loop made no such facet (the
  /// user's) or a group is not a disk.
  bool split_facet(const Region& r, Added& state) const {
    auto& list = state.guidance.facets;
    const std::set<int> quads(r.quads.begin(), r.quads.end());
    const auto at = std::find_if(list.begin(), list.end(), [&](const std::vector<int>& g) {
      return std::set<int>(g.begin(), g.end()) == quads;
    });
    if (at == list.end()) return false;
    for (const std::vector<int>& group : r.facet_groups)
      if (!disk(std::set<int>(group.begin(), group.end()))) return false;
    list.erase(at);
    list.insert(list.end(), r.facet_groups.begin(), r.facet_groups.end());
    return true;
  }

  /// Merge with the aligned neighbour on one side, over the whole run where the two lie side by
  /// side, if the inner rail does not have to move too far.
  bool merge_sideways(const Region& r, Added& state, Added& own) const {
    const Patch& p = strips().patches[r.patch];
    const auto starts = column_starts(strips(), p);
    const int columns = static_cast<int>(p.quads.size());
    std::optional<std::pair<std::vector<int>, double>> best;  // edges, deviation
    for (int side = 0; side < 2; ++side) {
      // The neighbour across this side in column col if aligned there, and the rail edges.
      auto across = [&](int col) -> std::pair<int, std::vector<int>> {
        std::vector<int> edges;
        int neighbour = kNone;
        for (int i = starts[col]; i < starts[col + 1]; ++i) {
          const int e = p.rail_edges[i][side];
          if (!edges.empty() && edges.back() == e) continue;
          const auto eh = m_.edge_handle(e);
          int other = kNone;
          for (int k = 0; k < 2; ++k) {
            const auto f = m_.face_handle(m_.halfedge_handle(eh, k));
            if (f.is_valid() && strips().quad_patch[f.idx()] != r.patch) other = f.idx();
          }
          if (other == kNone || state.facet_quads.count(other)) return {kNone, {}};
          const auto qe = quad_edges(m_, m_.face_handle(other));
          const int local = static_cast<int>(std::find(qe.begin(), qe.end(), e) - qe.begin());
          if (local % 2 != strips().quads[other].axis) return {kNone, {}};  // not a rail there
          const int q = strips().quad_patch[other];
          if (neighbour != kNone && q != neighbour) return {kNone, {}};
          neighbour = q;
          edges.push_back(e);
        }
        return {neighbour, edges};
      };
      const int q = across(r.c0).first;
      if (q == kNone) continue;
      std::vector<int> edges;
      bool ok = true;
      for (int col = r.c0; col <= r.c1 && ok; ++col) {
        const auto [qc, e] = across(col);
        ok = qc == q;
        edges.insert(edges.end(), e.begin(), e.end());
      }
      if (!ok) continue;
      // Grow along the strip while the same neighbour stays aligned beside it.
      for (int col = r.c0 - 1; col >= 0; --col) {
        const auto [qc, e] = across(col);
        if (qc != q) break;
        edges.insert(edges.begin(), e.begin(), e.end());
      }
      for (int col = r.c1 + 1; col < columns; ++col) {
        const auto [qc, e] = across(col);
        if (qc != q) break;
        edges.insert(edges.end(), e.begin(), e.end());
      }
      // No singularity inside, no contradiction, and how far the inner rail moves.
      std::map<int, int> count;
      for (int e : edges)
        for (int v : ends(m_, e)) ++count[v];
      for (int e : state.merge)
        for (int v : ends(m_, e)) ++count[v];
      for (const auto& [v, c] : count) {
        const auto vh = m_.vertex_handle(v);
        if (c >= 2 && !m_.is_boundary(vh) && m_.valence(vh) != 4) ok = false;
      }
      for (int e : edges)
        ok = ok && !user_split_.count(e) && !state.split.count(e) && !state.merge.count(e) &&
             !state.stiff.count(e);
      if (!ok) continue;
      const double deviation = merge_deviation(p, q, side);
      if (deviation > r_.max_merge_deviation * in_.target_diagonal) continue;
      if (!best || deviation < best->second) best = {{edges, deviation}};
    }
    if (!best) return false;
    for (int e : best->first) {
      add_edge(m_, e, state.merge, own.merge, state.guidance.merge);
      own.guidance.merge.push_back(ends(m_, e));
    }
    return true;
  }

  /// How far merging patch \p p with patch \p q across p's rail \p side would move the shared
  /// rail's vertices: their distance to the straight rulings from p's far rail to q's [mm].
  double merge_deviation(const Patch& p, int q, int side) const {
    const Patch& other = strips().patches[q];
    const auto lv = other.local_vertices();
    std::map<int, int> local_of;
    for (std::size_t i = 0; i < lv.size(); ++i) local_of[lv[i]] = static_cast<int>(i);
    const int n1 = static_cast<int>(other.rulings.size());
    double worst = 0;
    for (const auto& ruling : p.rulings) {
      const int shared = ruling[side], far = ruling[1 - side];
      const auto it = local_of.find(shared);
      if (it == local_of.end()) continue;
      // Its ruling in q and q's rail on the other side of it.
      int i = kNone, rail = kNone;
      for (int k = 0; k <= other.rows() && i == kNone; ++k)
        for (int j = 0; j < n1; ++j)
          if (other.local(k, j) == it->second) i = j, rail = k;
      if (i == kNone || (rail != 0 && rail != other.rows())) return 1e300;
      const int beyond = rail == 0 ? other.rulings[i][1] : other.rulings[i][0];
      const Vec3 a = strips().vertices[far], b = strips().vertices[beyond];
      const Vec3 x = strips().vertices[shared];
      const double t =
          std::clamp((x - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.0, 1.0);
      worst = std::max(worst, (x - (a + t * (b - a))).norm());
    }
    return worst;
  }

  /// A group of quads on its way to a facet.
  struct Group {
    std::set<int> quads;
  };

  Vec3 corner(int v) const { return strips().vertices[v]; }

  /// Largest distance of the quads' corners (on the target) to their best-fit plane [mm].
  double flatness(const std::set<int>& quads) const {
    std::vector<Vec3> pts;
    pts.reserve(4 * quads.size());
    for (int q : quads)
      for (int v : corners_of(q)) pts.push_back(corner(v));
    Vec3 mean = Vec3::Zero();
    for (const Vec3& p : pts) mean += p;
    mean /= static_cast<double>(pts.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Vec3& p : pts) cov += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Vec3 n = eig.eigenvectors().col(0);
    double worst = 0;
    for (const Vec3& p : pts) worst = std::max(worst, std::abs((p - mean).dot(n)));
    return worst;
  }

  /// A union of two groups of quads, a candidate facet: its flatness, and whether it may be one
  /// facet (measured only where it could be the flattest so far).
  struct PairMeasure {
    double flatness = 0;
    std::optional<bool> joins;
  };

  /// Of the pairs of groups \p met (in the order a scan meets them; \p key(i) the memo key of
  /// pair i, \p merged(i) the union of its groups), the one a scan keeping the flattest pair
  /// that may join would keep: of the pairs at most \p limit flat whose union \p may_join
  /// (flatness, union), the flattest, of equally flat ones the last met; -1: none. Each pair's
  /// flatness and whether it may join are measured once per key in \p memo (a pair meeting
  /// along n quad edges is met n times, and again after every join that leaves both groups as
  /// they are). Whether a pair may join (the plate test, which walks its whole outline) is
  /// measured flattest first and only until one may: the same pick as a scan keeping the
  /// flattest so far, which measured it for every pair as flat as that (on a flat face, most
  /// of them after every join).
  template <class Key, class KeyOf, class Union, class MayJoin>
  int flattest_joining(std::map<Key, PairMeasure>& memo, int met, KeyOf key, double limit,
                       Union merged, MayJoin may_join) const {
    std::vector<std::pair<double, int>> flat;  // (flatness, -i) of the pairs within the limit
    std::vector<PairMeasure*> measure(met, nullptr);
    for (int i = 0; i < met; ++i) {
      auto it = memo.find(key(i));
      if (it == memo.end()) it = memo.emplace(key(i), PairMeasure{flatness(merged(i)), {}}).first;
      measure[i] = &it->second;
      if (it->second.flatness <= limit) flat.emplace_back(it->second.flatness, -i);
    }
    std::sort(flat.begin(), flat.end());
    for (const auto& [e, minus_i] : flat) {
      PairMeasure& m = *measure[-minus_i];
      if (!m.joins) m.joins = may_join(e, merged(-minus_i));
      if (*m.joins) return -minus_i;
    }
    return -1;
  }

  /// True when the quads can be one flat plate: a disk whose quads all face the same way as
  /// the best-fit plane (within \p max_tilt [rad]; a group flat within the tolerance can still
  /// fold back on itself in small quads), with a simple outline on that plane.
  bool plate(const std::set<int>& quads, double max_tilt = M_PI / 4) const {
    return plate_outline(quads, max_tilt).has_value();
  }
  /// The same test, and where it holds the plate's outline on its plane (plane_outline), which
  /// compact() measures next.
  std::optional<Polygon2> plate_outline(const std::set<int>& quads,
                                        double max_tilt = M_PI / 4) const {
    // The tilt first: it is the cheaper test, and the one a group grown to the edge of a face
    // fails for every neighbour across the fold (the disk test walks the whole outline).
    const Plane plane = plane_of(quads);
    const Vec3& n = plane.n;
    for (int q : quads) {
      // Each corner's triangle, so that a quad folded along a diagonal cannot flip half of it;
      // but a corner as good as straight (within kPlateFlatness of the line through its
      // neighbours) folds nothing, and its triangle's normal says nothing (a pyramid's side at
      // 250 mm: a quad with three corners on a ridge, the middle one 0.01 mm over it, whose
      // triangle there faced the next side's way, 72 degrees off; that side came out as 28
      // strips beside four plates).
      const auto v = corners_of(q);
      for (int k = 0; k < 4; ++k) {
        const Vec3 to_next = corner(v[(k + 1) % 4]) - corner(v[k]);
        const Vec3 to_prev = corner(v[(k + 3) % 4]) - corner(v[k]);
        const Vec3 a = to_next.cross(to_prev);
        const double chord = (to_next - to_prev).norm();
        if (to_next.dot(to_prev) < 0 && chord > 0 && a.norm() / chord <= kPlateFlatness) continue;
        if (!(a.norm() > 0) || a.normalized().dot(n) < std::cos(max_tilt)) return std::nullopt;
      }
    }
    if (!disk(quads)) return std::nullopt;
    Polygon2 poly = plane_outline(quads, plane);
    // No corner nearly closing on itself (a fan of quads almost all around a vertex): moving
    // the corners onto the plane would make such an outline cross itself.
    const std::size_t m = poly.size();
    for (std::size_t i = 0; i < m; ++i) {
      const Vec2 a = poly[(i + m - 1) % m] - poly[i], b = poly[(i + 1) % m] - poly[i];
      double inner = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));  // b to a, ccw
      if (inner < 0) inner += 2 * M_PI;
      inner = 2 * M_PI - inner;
      if (inner > 2 * M_PI - M_PI / 9) return std::nullopt;
    }
    std::vector<int> ring(m);
    for (std::size_t i = 0; i < m; ++i) ring[i] = static_cast<int>(i);
    if (!is_simple_polygon(poly, ring)) return std::nullopt;
    return poly;
  }

  /// The boundary of a group of quads, in the quads' own order: each boundary vertex -> the next.
  /// \p touches: two boundary edges leave one vertex (the later one is kept).
  std::map<int, int> boundary_next(const std::set<int>& quads, bool& touches) const {
    // The quads' directed edges, sorted: an edge is on the boundary where its reverse is not
    // among them (sorted vectors: this runs for every candidate of every facet's growth).
    std::vector<std::pair<int, int>> directed;
    directed.reserve(4 * quads.size());
    for (int q : quads) {
      const auto v = corners_of(q);
      for (int k = 0; k < 4; ++k) directed.emplace_back(v[k], v[(k + 1) % 4]);
    }
    std::sort(directed.begin(), directed.end());
    directed.erase(std::unique(directed.begin(), directed.end()), directed.end());
    std::map<int, int> next;
    touches = false;
    for (const auto& [a, b] : directed)
      if (!std::binary_search(directed.begin(), directed.end(), std::make_pair(b, a))) {
        if (!next.empty() && std::prev(next.end())->first == a) {  // sorted: a's last entry
          touches = true;
          std::prev(next.end())->second = b;  // the later one is kept
        } else {
          next.emplace_hint(next.end(), a, b);
        }
      }
    return next;
  }

  /// True when the quads form one disk: connected across edges, and a boundary that is one loop
  /// never touching itself.
  bool disk(const std::set<int>& quads) const {
    bool touches = false;
    std::map<int, int> next = boundary_next(quads, touches);
    if (touches || next.empty()) return false;
    int at = next.begin()->first, steps = 0;
    do {
      at = next[at];
      ++steps;
    } while (at != next.begin()->first && steps <= static_cast<int>(next.size()));
    return steps == static_cast<int>(next.size()) && connected_pieces(quads).size() == 1;
  }

  /// Planar facets over the region's quads (those not yet in one): adjacent groups merge,
  /// flattest first, while their corners stay within ResolveOptions::facet_flatness of a plane;
  /// a group still smaller than a part then takes in its flattest neighbour quads (from outside
  /// the region too). Every edge of the facets' quads is forced stiff, so neighbours meet them
  /// along straight borders.
  bool facets(const Region& r, Added& state, Added& own) const {
    const double tolerance = r_.facet_flatness * in_.target_diagonal;
    std::set<std::set<int>> before;  // the facets so far: making one of them again is no change
    for (const auto& list : state.guidance.facets) before.insert({list.begin(), list.end()});
    std::vector<Group> groups;
    std::map<int, int> group_of;
    // An earlier facet that came out too small or narrow is taken back and grown.
    auto release = [&](int q) {  // the facet group holding q leaves the state; its quads
      auto& list = state.guidance.facets;
      for (std::size_t g = 0; g < list.size(); ++g)
        if (std::find(list[g].begin(), list[g].end(), q) != list[g].end()) {
          std::vector<int> quads = list[g];
          list.erase(list.begin() + static_cast<std::ptrdiff_t>(g));
          for (int x : quads) state.facet_quads.erase(x);
          return quads;
        }
      return std::vector<int>{};
    };
    if (strips().patches[r.patch].flat) {
      const std::vector<int> quads = release(r.quads.front());
      if (any_bent(quads)) {  // start again from its single quads, under a tighter flatness
        for (int q : quads) {
          group_of[q] = static_cast<int>(groups.size());
          groups.push_back({{q}});
        }
      } else {
        Group g;
        for (int q : quads) g.quads.insert(q);
        for (int q : g.quads) group_of[q] = static_cast<int>(groups.size());
        groups.push_back(std::move(g));
      }
    }
    for (int q : r.quads)
      if (!state.facet_quads.count(q) && !group_of.count(q)) {
        group_of[q] = static_cast<int>(groups.size());
        groups.push_back({{q}});
      }
    if (groups.empty()) return false;
    // Quads around a group; with \p facets also those of other facets (taken whole).
    auto neighbours = [&](const Group& g, bool facets_too) {
      std::set<int> out;
      for (int q : g.quads)
        for (auto f : m_.ff_range(m_.face_handle(q))) {
          if (g.quads.count(f.idx())) continue;
          if (state.facet_quads.count(f.idx()) && !facets_too) continue;
          bool merged = false;  // a quad the loop merged sideways keeps its strip
          for (int e : quad_edges(m_, f)) merged = merged || state.merge.count(e);
          if (!merged) out.insert(f.idx());
        }
      return out;
    };
    auto facet_of = [&](int q) {  // the quads of the earlier facet holding q, or q alone
      for (const auto& list : state.guidance.facets)
        if (std::find(list.begin(), list.end(), q) != list.end()) return list;
      return std::vector<int>{q};
    };
    auto take = [&](int a, int q) {  // quad q (with its group or earlier facet) into group a
      const auto it = group_of.find(q);
      if (it != group_of.end()) {
        const int b = it->second;
        for (int x : groups[b].quads) group_of[x] = a, groups[a].quads.insert(x);
        groups[b] = {};
        return;
      }
      for (int x : state.facet_quads.count(q) ? release(q) : std::vector<int>{q}) {
        group_of[x] = a;
        groups[a].quads.insert(x);
      }
    };
    auto with = [&](int a, int q) {
      std::set<int> merged = groups[a].quads;
      const auto it = group_of.find(q);
      if (it != group_of.end()) {
        merged.insert(groups[it->second].quads.begin(), groups[it->second].quads.end());
      } else {
        const auto quads = facet_of(q);
        merged.insert(quads.begin(), quads.end());
      }
      return merged;
    };
    // The merges below only join these groups: whether any of their quads was in a bent facet
    // does not change.
    bool tight = false;
    for (const Group& g : groups) tight = tight || any_bent(g.quads);
    // A pair of groups is measured once while neither changes (a merge bumps both versions).
    std::vector<int> version(groups.size(), 0);
    std::map<std::array<int, 4>, PairMeasure> pairs;
    for (;;) {  // the flattest merge of two groups of the region, within the tolerance
      std::vector<std::pair<int, int>> met;  // (group, a neighbour quad in another group)
      for (std::size_t a = 0; a < groups.size(); ++a) {
        if (groups[a].quads.empty()) continue;
        for (int q : neighbours(groups[a], false)) {
          const auto it = group_of.find(q);
          if (it == group_of.end() || it->second == static_cast<int>(a)) continue;
          met.emplace_back(static_cast<int>(a), q);
        }
      }
      const int pick = flattest_joining(
          pairs, static_cast<int>(met.size()),
          [&](int i) {
            const int a = met[i].first, b = group_of.at(met[i].second);
            const int lo = std::min(a, b), hi = std::max(a, b);
            return std::array<int, 4>{lo, version[lo], hi, version[hi]};
          },
          tight ? 0.5 * tolerance : tolerance,
          [&](int i) { return with(met[i].first, met[i].second); },
          [&](double, const std::set<int>& merged) {
            const auto outline = plate_outline(merged);
            return outline && compact(*outline);
          });
      if (pick < 0) break;
      const int ba = met[pick].first, bq = met[pick].second;
      ++version[group_of.at(bq)];
      ++version[ba];
      take(ba, bq);
    }
    for (std::size_t a = 0; a < groups.size(); ++a) {
      if (groups[a].quads.empty() || big_enough(groups[a].quads)) continue;
      // A group that grows past kMaxFailedGrowth quads, more than two sheets off its plane, and
      // is still not big enough stays as it was: growing, it spreads a plate over curved ground,
      // taking in the facets beside it whole, and is left too small all the same (bunny_closed at
      // 200 mm: a facet of 105 quads, 43 mm off its plane, under its base; flattened, inverted, its
      // outline crossing itself, the strips there 19 mm off the target; demosthenes at 250 mm: 91
      // quads, 25 mm).
      const std::vector<Group> groups_before = groups;
      const std::map<int, int> group_of_before = group_of;
      const Added state_before = state;
      // Past the time limit a group grows no more (its growth checks every neighbour, and
      // pairs of them where no single one keeps it a plate, against a group of up to hundreds
      // of quads: on a 7470-quad Spot one region's growth went on for minutes); it is then
      // left as it is, too small or not.
      // (Not big enough when it starts: measured just above.)
      for (int guard = 0;
           (guard == 0 || !big_enough(groups[a].quads)) && guard < 64 && !out_of_time(); ++guard) {
        // The flattest neighbour that keeps the group compact (a snake of quads falls
        // apart at its necks once its slots are cut), else the flattest.
        double best = 1e300;
        bool best_compact = false;
        int pick = kNone;
        // A plate too small for its folds grows over curved ground too (a cap over a tip):
        // fidelity given up there is reported as the region's local distance. Steeper quads
        // only where nothing else is left.
        for (double tilt : {0.4 * M_PI, 0.49 * M_PI}) {
          std::set<std::set<int>> seen;  // every quad of a neighbouring facet gives its union
          for (int q : neighbours(groups[a], true)) {
            const auto merged = with(static_cast<int>(a), q);
            if (!seen.insert(merged).second) continue;
            // A compact group is beaten only by a flatter compact one: where the best so far
            // is compact, the plate and compactness tests only for a flatter one.
            const double e = flatness(merged);
            if (best_compact && !(e < best)) continue;
            const auto outline = plate_outline(merged, tilt);
            if (!outline) continue;
            const bool c = compact(*outline);
            if ((c && !best_compact) || (c == best_compact && e < best))
              best = e, best_compact = c, pick = q;
          }
          if (pick != kNone) break;
        }
        if (pick == kNone) {
          // No single neighbour keeps it a plate (it closes a concave notch only with the
          // next one): two at once, the flattest pair.
          int second = kNone;
          for (int q : neighbours(groups[a], true)) {
            if (out_of_time()) break;
            const auto one = with(static_cast<int>(a), q);
            Group g1{one};
            for (int q2 : neighbours(g1, true)) {
              auto both = one;
              if (group_of.count(q2)) {
                const auto& other = groups[group_of.at(q2)].quads;
                both.insert(other.begin(), other.end());
              } else {
                const auto quads = facet_of(q2);
                both.insert(quads.begin(), quads.end());
              }
              // The flattest pair wins: its flatness first, the costlier plate test only
              // where it would win.
              const double e = flatness(both);
              if (!(e < best) || !plate(both, 0.49 * M_PI)) continue;
              best = e, pick = q, second = q2;
            }
          }
          if (pick == kNone) break;
          take(static_cast<int>(a), pick);
          if (!groups[a].quads.count(second)) take(static_cast<int>(a), second);
          continue;
        }
        take(static_cast<int>(a), pick);
      }
      if (groups[a].quads.size() > kMaxFailedGrowth &&
          flatness(groups[a].quads) > 2 * o_.material.thickness && !big_enough(groups[a].quads))
        groups = groups_before, group_of = group_of_before, state = state_before;
    }
    bool changed = false;
    for (const Group& g : groups) changed = changed || (!g.quads.empty() && !before.count(g.quads));
    if (!changed) return false;
    int made = 0;
    for (const Group& g : groups) {
      if (g.quads.empty()) continue;
      if (!big_enough(g.quads)) stuck_.insert(g.quads.begin(), g.quads.end());
      add_facet({g.quads.begin(), g.quads.end()}, state, &own);
      ++made;
    }
    return made > 0;
  }

  /// Adds the quads \p list as one flat facet to \p state and, where given, to \p own: every
  /// edge of its quads forced stiff (but the user's bendable ones), so neighbours meet it along
  /// straight borders.
  void add_facet(const std::vector<int>& list, Added& state, Added* own) const {
    for (int q : list) {
      state.facet_quads.insert(q);
      if (own) own->facet_quads.insert(q);
      for (int e : quad_edges(m_, m_.face_handle(q))) {
        if (state.stiff.count(e) || user_bendable_.count(e)) continue;
        const auto v = ends(m_, e);
        state.stiff.insert(e);
        state.guidance.edges.push_back({v[0], v[1], false});
        if (own) {
          own->stiff.insert(e);
          own->guidance.edges.push_back({v[0], v[1], false});
        }
      }
    }
    state.guidance.facets.push_back(list);
    if (own) own->guidance.facets.push_back(list);
  }

  /// The best-fit plane of the quads' corners (as the facet will be flattened onto it): its
  /// centre, two in-plane directions and the normal on the side the quads face.
  struct Plane {
    Vec3 mean, u, w, n;
  };
  Plane plane_of(const std::set<int>& quads) const {
    std::vector<int> corners;  // each once, ascending
    corners.reserve(4 * quads.size());
    Vec3 facing = Vec3::Zero();
    for (int q : quads) {
      for (int v : corners_of(q)) corners.push_back(v);
      facing += quad_normal(q);
    }
    // Each once, ascending: marked and read off between the smallest and the largest where
    // that span is short, else sorted (the plate test fits a plane to every neighbour of a
    // growing facet; sorting four corners per quad was most of a thin rod's resolve stage).
    const auto [lo, hi] = std::minmax_element(corners.begin(), corners.end());
    if (!corners.empty() && *hi - *lo < 16 * static_cast<long>(corners.size())) {
      if (marked_.size() <= static_cast<std::size_t>(*hi)) marked_.resize(*hi + 1, 0);
      const int from = *lo, to = *hi;
      for (int v : corners) marked_[v] = 1;
      corners.clear();
      for (int v = from; v <= to; ++v)
        if (marked_[v]) corners.push_back(v), marked_[v] = 0;
    } else {
      std::sort(corners.begin(), corners.end());
      corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    }
    Plane p;
    p.mean = Vec3::Zero();
    for (int v : corners) p.mean += corner(v) / static_cast<double>(corners.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int v : corners) cov += (corner(v) - p.mean) * (corner(v) - p.mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    p.n = eig.eigenvectors().col(0);
    if (p.n.dot(facing) < 0) p.n = -p.n;
    p.u = eig.eigenvectors().col(2);
    p.w = p.n.cross(p.u);  // (u, w) counter-clockwise seen from the facing side
    return p;
  }

  /// The boundary loop of a disk of quads, as vertex ids in the quads' own order.
  std::vector<int> boundary_loop(const std::set<int>& quads) const {
    bool touches = false;
    std::map<int, int> next = boundary_next(quads, touches);
    std::vector<int> loop;
    for (int at = next.begin()->first; loop.size() <= next.size();) {
      loop.push_back(at);
      at = next[at];
      if (at == next.begin()->first) break;
    }
    return loop;
  }

  /// What is left of a facet once its borders are cut back on its best-fit plane: each
  /// outline edge goes back by the deeper of the plain mitre and the slot its fold with the
  /// quad across would need (a sharp fold takes back far more than half the thickness).
  std::vector<Polygon2> cut_back_outline(const std::set<int>& quads) const {
    const std::vector<int> loop = boundary_loop(quads);
    const Plane pl = plane_of(quads);
    const Vec3 n = pl.n;
    Polygon2 poly;
    for (int v : loop)
      poly.emplace_back((corner(v) - pl.mean).dot(pl.u), (corner(v) - pl.mean).dot(pl.w));
    const double h = o_.material.thickness;
    std::vector<Polygon2> cut;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      const auto he = m_.find_halfedge(m_.vertex_handle(b), m_.vertex_handle(a));
      if (!he.is_valid() || !m_.face_handle(he).is_valid()) continue;  // the mesh's boundary
      const double fold = angle_between(n, quad_normal(m_.face_handle(he).idx()));
      const double depth =
          std::min(2 * h, std::max(-plain_offset(fold, h), -tooth_offsets(fold, h).slot));
      if (!(depth > 0)) continue;
      const Vec2 pa = poly[k], pb = poly[(k + 1) % poly.size()], e = pb - pa;
      if (!(e.norm() > 0)) continue;
      const Vec2 in = Vec2(-e.y(), e.x()).normalized() * depth;
      Polygon2 rect = {pa - 1e-3 * in, pb - 1e-3 * in, pb + in, pa + in};
      make_counter_clockwise(rect);
      cut.push_back(std::move(rect));
    }
    make_counter_clockwise(poly);
    return cut.empty() ? std::vector<Polygon2>{poly} : polygon_difference({poly}, cut);
  }

  /// The middle of quad \p q: the mean of its corners [mm].
  Vec3 middle(int q) const {
    Vec3 c = Vec3::Zero();
    for (int v : corners_of(q)) c += 0.25 * corner(v);
    return c;
  }

  Vec3 quad_normal(int q) const {
    const auto v = corners_of(q);
    const Vec3 a = (corner(v[2]) - corner(v[0])).cross(corner(v[3]) - corner(v[1]));
    return a.norm() > 0 ? Vec3(a.normalized()) : Vec3::Zero();
  }

  /// A facet a maker can handle once its borders are cut back: one piece, at least the
  /// minimum part area, and somewhere as wide as the minimum part width.
  bool big_enough(const std::set<int>& quads) const {
    const auto left = cut_back_outline(quads);
    double area = 0;
    int pieces = 0;
    for (const auto& p : left) {
      area = std::max(area, std::abs(polygon_area(p)));
      pieces += std::abs(polygon_area(p)) > 0.1 * r_.min_part_area ? 1 : 0;
    }
    if (pieces != 1 || area < r_.min_part_area) return false;
    return !polygon_offset(left, -0.5 * r_.min_part_width).empty();
  }

  /// True when no more than a tenth of the facet whose outline on its plane is \p poly (as
  /// plate_outline() gives it) lies in necks or tails narrower than a part may be with a slot
  /// cut into each side: such a facet would fall apart when cut.
  bool compact(const Polygon2& poly) const {
    const double r = 0.5 * r_.min_part_width + 0.5 * o_.material.thickness;
    double kept = 0;
    for (const auto& p : polygon_offset(polygon_offset({poly}, -r), r)) kept += polygon_area(p);
    return kept >= 0.9 * polygon_area(poly);
  }

  /// The boundary loop of a disk of quads on its best-fit plane, counter-clockwise [mm].
  Polygon2 plane_outline(const std::set<int>& quads) const {
    return plane_outline(quads, plane_of(quads));
  }
  /// The same on \p pl, the quads' plane_of().
  Polygon2 plane_outline(const std::set<int>& quads, const Plane& pl) const {
    Polygon2 poly;
    for (int v : boundary_loop(quads))
      poly.emplace_back((corner(v) - pl.mean).dot(pl.u), (corner(v) - pl.mean).dot(pl.w));
    make_counter_clockwise(poly);
    return poly;
  }

  /// Adjacent facets join while the joined one stays flat enough (fewer, larger parts): the
  /// flattest pair that may join, one pair at a time. A pair's flatness and whether it may join
  /// are measured once and kept while neither facet changes (a pair meeting along n quad edges
  /// was measured n times per join, each join measuring all pairs again).
  void consolidate_facets() {
    auto& groups = accepted_.guidance.facets;
    const double tolerance = r_.facet_flatness * in_.target_diagonal;
    std::vector<int> id(groups.size());  // per group, an id that changes when the group does
    std::iota(id.begin(), id.end(), 0);
    int next_id = static_cast<int>(groups.size());
    std::map<std::pair<int, int>, PairMeasure> pairs;
    for (;;) {
      std::map<int, int> group_of;
      for (std::size_t g = 0; g < groups.size(); ++g)
        for (int q : groups[g]) group_of[q] = static_cast<int>(g);
      std::vector<std::pair<int, int>> met;  // pairs of adjacent groups, a < b
      for (std::size_t a = 0; a < groups.size(); ++a)
        for (int q : groups[a])
          for (auto f : m_.ff_range(m_.face_handle(q))) {
            const auto it = group_of.find(f.idx());
            if (it == group_of.end() || it->second <= static_cast<int>(a)) continue;
            met.emplace_back(static_cast<int>(a), it->second);
          }
      const int pick = flattest_joining(
          pairs, static_cast<int>(met.size()),
          [&](int i) {
            return std::pair{id[met[i].first], id[met[i].second]};
          },
          tolerance,
          [&](int i) {
            std::set<int> quads(groups[met[i].first].begin(), groups[met[i].first].end());
            quads.insert(groups[met[i].second].begin(), groups[met[i].second].end());
            return quads;
          },
          // A facet that flattened bent joins only a flatter one.
          [&](double e, const std::set<int>& quads) {
            if (e > 0.5 * tolerance && any_bent(quads)) return false;
            const auto outline = plate_outline(quads);
            return outline && compact(*outline) && fits_with_teeth(*outline);
          });
      if (pick < 0) break;
      const int ba = met[pick].first, bb = met[pick].second;
      groups[ba].insert(groups[ba].end(), groups[bb].begin(), groups[bb].end());
      groups.erase(groups.begin() + bb);
      id[ba] = next_id++;
      id.erase(id.begin() + bb);
    }
  }

  /// Local distances, sizes per material, counts after.
  void finish() {
    // A region made into facets again in a later round (a neighbour's change undid them) is one
    // change: its last record stays (a bust once listed one quad's facets five times).
    {
      std::set<std::tuple<std::string, std::vector<int>, std::string>> later;
      std::vector<RegionChange> kept;
      for (auto c = out_.changes.rbegin(); c != out_.changes.rend(); ++c) {
        std::vector<int> quads = c->quads;
        std::sort(quads.begin(), quads.end());
        if (later.insert({c->action, quads, c->reason}).second) kept.push_back(std::move(*c));
      }
      out_.changes.assign(std::make_move_iterator(kept.rbegin()),
                          std::make_move_iterator(kept.rend()));
    }
    out_.added = accepted_.guidance;
    out_.critical_after = static_cast<int>(build_.kerf.critical.size());
    out_.parts_after = static_cast<int>(build_.flat.strips.patches.size());
    out_.minutes_after = build_.kerf.cutting.minutes;
    const Strips& s = build_.flat.strips;
    std::vector<std::vector<int>> faces_of(m_.n_faces());
    for (std::size_t f = 0; f < s.face_quad.size(); ++f)
      if (s.face_patch[f] != kNone) faces_of[s.face_quad[f]].push_back(static_cast<int>(f));
    for (RegionChange& c : out_.changes) {
      std::set<int> vertices;
      for (int q : c.quads)
        for (int f : faces_of[q])
          for (int v : s.faces[f]) vertices.insert(v);
      for (int v : vertices)
        c.local_distance = std::max(c.local_distance, in_.surface.closest(s.vertices[v]).distance);
    }
    // Sizes from the first build's tightest bend: the shape as laid out before any change.
    const double d = o_.kerf.min_cut_spacing;
    out_.min_size_mm = bend_scale(tightest_bend_, o_.material, d) * out_.current_size_mm;
    for (const Material& m : sheet_presets())
      out_.materials.push_back(
          {m.name, m.thickness, bend_scale(tightest_bend_, m, d) * out_.current_size_mm});
  }
};

}  // namespace

std::vector<int> parts_too_small(const PartsBuild& b, double min_area, double min_width,
                                 double max_angle_error) {
  return small_parts(b, min_area, min_width, max_angle_error);
}

std::size_t parts_memo_bytes(double max_memory_mb) {
  const double mb = max_memory_mb > 0
                        ? std::clamp(max_memory_mb / 32, std::min(80.0, max_memory_mb / 8), 1024.0)
                        : 80.0;
  return static_cast<std::size_t>(mb * (1 << 20));
}

void cut_parts(PartsBuild& b, const Guidance& g, const PartsOptions& o, PartsMemo* memo) {
  if (!g.omit.empty()) omit_patches(b.flat, std::set<int>(g.omit.begin(), g.omit.end()));
  b.joints = make_joints(b.flat.strips, b.flat.flattening, o.material, o.machine, o.joints,
                         memo ? &memo->outlines : nullptr);
  b.kerf = place_kerf_cuts(b.flat.strips, b.flat.flattening, b.joints, o.material, o.machine,
                           o.kerf, memo ? &memo->kerf : nullptr);
}

PartsBuild build_parts(const PreparedInput& input, const PartsOptions& o, const Guidance& g,
                       const BendingResult* reuse, PartsMemo* memo) {
  PartsBuild b;
  if (reuse) {
    b.bending = *reuse;
  } else {
    BendingOptions bending = o.bending;
    bending.guidance.insert(bending.guidance.end(), g.edges.begin(), g.edges.end());
    b.bending = choose_bending_edges(input.quads, input.surface, bending);
  }
  StripsOptions strips = o.strips;
  strips.split_edges.insert(strips.split_edges.end(), g.split.begin(), g.split.end());
  strips.soft_merge_edges.insert(strips.soft_merge_edges.end(), g.merge.begin(), g.merge.end());
  strips.facets.insert(strips.facets.end(), g.facets.begin(), g.facets.end());
  b.strips = build_strips(input.quads, b.bending, input.surface, strips);
  FlattenOptions flatten = o.flatten;
  flatten.mimic_3d = false;  // an evaluation: measured once, on the final build
  b.flat = flatten_cuttable(b.strips, flatten, o.usable);
  cut_parts(b, g, o, memo);
  return b;
}

ResolveResult resolve_critical_regions(PartsBuild& build, const PreparedInput& input,
                                       const PartsOptions& options, const ResolveOptions& resolve,
                                       const ResolveProgress& progress, PartsMemo* memo) {
  if (resolve.max_rounds < 1) throw InvalidInput("resolve: max_rounds must be >= 1");
  if (!(resolve.time_limit > 0)) throw InvalidInput("--resolve-time-limit must be > 0 s");
  if (!(resolve.min_part_width > 0 && std::isfinite(resolve.min_part_width)))
    throw InvalidInput("--min-part-width must be > 0 mm");
  return Resolver(build, input, options, resolve, progress, memo).run();
}

}  // namespace kerfab
