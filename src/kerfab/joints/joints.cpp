#include "kerfab/joints/joints.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include "kerfab/core/errors.h"
#include "kerfab/core/parallel.h"
#include "kerfab/joints/border_pieces.h"
#include "kerfab/joints/corners.h"
#include "kerfab/joints/glue_tabs.h"
#include "kerfab/joints/plates.h"

namespace kerfab {
namespace {

using border::Piece;
using border::Ring;
using border::s_of;
using border::s_range;
using border::Side;

/// A tooth on a short border between corners, checked in 3D instead of by the bands (sampled at
/// 0.1 mm): it may reach no deeper than this into a third part's plate (the teeth the bands let
/// through reach 0 into third parts on the demo: the bands' own standard) [mm] ...
constexpr double kThirdPartReach = 0.05;
/// ... nor deeper than this into its mate's plate beside the slot cut for it: the 3D misfit that
/// 93 % of the demo's band-placed teeth keep, from the bend of kerfed mates across the slot and
/// the two sides' arc lengths, measured the same way (median 0.044 mm, largest 0.8 mm) [mm].
constexpr double kMateReach = 0.2;
/// A part that falls apart without a stub tooth may take one where it then loses up to this much
/// more (a crumb beside the neck where it comes apart; same_loss) [mm^2]: under the smallest
/// tooth's own area (1.2 by 0.5 mm), a little of a sheet no maker would miss.
constexpr double kMoreLost = 0.5;
/// Candidate teeth drawn per short border at most once the bands are left behind (with 8, one
/// 3.1 mm border of the demo found none: its first candidates reach 0.26-0.47 mm into its mate).
constexpr int kStubDrawings = 16;
/// Outline vertices from which drawing a part costs so much more than looks_sound() that stub
/// teeth are screened by it before they are drawn: the quad sphere's raw strips (about 500 to
/// 1000 vertices, 20 to 30 ms a drawing) where a slot pinching a V-shaped strip end failed 14
/// drawings per border; the parts of the demo after its first build have under 520, those of
/// spot_quadrangulated under 200 (there the screening bought nothing and changed which stub
/// teeth were chosen).
constexpr std::size_t kScreenFrom = 600;
/// Round corners of the outlines' morphological opening keep within this of the true arc (a
/// hundredth of the smallest feature; 4 segments a quarter turn at half of it) [mm].
constexpr double kOpeningArc = 0.01;
/// Erosions that find necks go this much under half the smallest feature: a neck exactly that
/// wide is none (two slots from both sides of a 4 mm strip leave exactly 1 mm between them) [mm].
constexpr double kNeckSlack = 0.01;
/// narrow_tails() and narrow_slits() (the sheet auditor's test) open and close this much under
/// half the smallest feature: a feature exactly that wide is allowed (teeth are laid out exactly
/// the smallest feature clear of the bands beside them), and an opening by exactly half of it
/// erodes such a strip to a line of no area and takes it all [mm].
constexpr double kAtTheLimit = 1e-3;

/// Needles of material narrower than this along all their length are taken off an outline:
/// nothing a cutter makes is that thin, and grown by half the kerf each would become a hair as
/// wide as the beam [mm].
constexpr double kNeedleWidth = 0.01;

/// The edges of \p rings that come within \p margin of \p piece's bounding box: the only
/// ones a vertex of \p piece can be within \p margin of.
std::vector<std::array<Vec2, 2>> edges_near(const Polygon2& piece,
                                            const std::vector<const Polygon2*>& rings,
                                            double margin) {
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec2& v : piece) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  lo -= Vec2::Constant(margin), hi += Vec2::Constant(margin);
  std::vector<std::array<Vec2, 2>> near;
  for (const Polygon2* ring : rings)
    for (std::size_t i = 0, n = ring->size(); i < n; ++i) {
      const Vec2& a = (*ring)[i];
      const Vec2& b = (*ring)[(i + 1) % n];
      if (std::max(a.x(), b.x()) < lo.x() || std::min(a.x(), b.x()) > hi.x() ||
          std::max(a.y(), b.y()) < lo.y() || std::min(a.y(), b.y()) > hi.y())
        continue;
      near.push_back({a, b});
    }
  return near;
}

/// \p from less \p cut, grown by a hair: a tail shares its sides with the outline, and taken
/// away exactly it can come back as a hole touching the outline (the outline whole, with the
/// tail as a hole), which left the tail on the part (a spike of a quad sphere's facet, 4.7 mm
/// under 1 mm wide).
std::vector<Polygon2> cut_away(const std::vector<Polygon2>& from, std::vector<Polygon2> cut) {
  for (auto& poly : cut) make_counter_clockwise(poly);
  std::vector<Polygon2> kept;
  for (auto& c : polygon_difference(from, polygon_offset(cut, 1e-4)))
    if (polygon_area(c) > 0) kept.push_back(std::move(c));
  return kept;
}

/// The morphological closing of \p outline by a disc of radius \p r, and what it fills: its
/// slits and notches narrower than 2r (slit_widenings() widens them, narrow_slits() names those
/// left).
struct Closing {
  std::vector<Polygon2> closed, gaps;
};
Closing closing_of(const Polygon2& outline, double r) {
  Closing c;
  c.closed = polygon_offset(polygon_offset({outline}, r), -r);
  c.gaps = polygon_difference(c.closed, {outline});
  return c;
}

class Builder {
 public:
  Builder(const Strips& s, const Flattening& f, double thickness, double kerf_width,
          const JointOptions& o, OutlineMemo* memo)
      : memo_(memo),
        s_(s),
        f_(f),
        thickness_(thickness),
        kerf_width_(kerf_width),
        o_(o),
        bp_(border::make_pieces(s, f)),
        rings_(bp_.rings),
        pieces_(bp_.pieces),
        plates_(s, f, thickness),
        lost_(rings_.size()) {}

  Joints run() {
    out_.draft = !o_.stub_teeth;
    std::vector<std::vector<std::array<double, 2>>> forbidden(pieces_.size() * 2);
    std::set<int> all;
    for (std::size_t p = 0; p < rings_.size(); ++p) all.insert(static_cast<int>(p));
    const std::vector<int> every(all.begin(), all.end());  // for for_each_of
    // Each part writes only the sides of its own ring: on all threads.
    for_each_of(every, [&](int p) { restrict_by_bands(p, forbidden); });
    place_teeth(forbidden);
    drop_bitten_teeth(all);
    out_.parts.resize(rings_.size());
    draw(all);
    // A part so thin that its slots cut it through takes the teeth of its borders instead: its
    // outline then grows where it was cut back (its mates, larger as a rule, get the slots).
    // So does a part too small to handle, from mates that are not smaller still; where it
    // cannot own a tooth, it keeps the slot.
    // (Only intervals change here; the parts are redrawn after.)
    std::set<int> swapped;
    for (std::size_t p = 0; p < out_.parts.size(); ++p) {
      const bool repaired = out_.parts[p].repaired;
      if (!repaired && !too_small(out_.parts[p])) continue;
      const double area = std::abs(polygon_area(out_.parts[p].designed));
      for (std::size_t i = 0; i < out_.borders.size(); ++i) {
        BorderJoint& b = out_.borders[i];
        for (int side = 0; side < 2; ++side) {
          if (b.patches[side] != static_cast<int>(p)) continue;
          const PartOutline& mate = out_.parts[b.patches[1 - side]];
          if (!repaired && too_small(mate) && !(std::abs(polygon_area(mate.designed)) > area))
            continue;
          for (JointInterval& in : b.intervals) {
            if (in.owner < 0 || in.owner == side) continue;
            if (untrimmed_owner(static_cast<int>(i), in, side) == side)
              in.owner = side;
            else if (repaired)
              make_plain(b, in);
            else
              continue;
            swapped.insert(b.patches[0]);
            swapped.insert(b.patches[1]);
          }
        }
      }
    }
    redraw(swapped);
    // A part that still falls apart loses the joints next to where it comes apart: the
    // intervals whose tooth, slot or cut-back on it touches a piece it lost go plain on both
    // parts (the mitre alone cuts back far less), a few rounds; only a part that still falls
    // apart then keeps all its borders plain, and so do the parts whose teeth reached into its
    // slots.
    for (int round = 0; round < 4; ++round) {
      std::set<int> redo;
      for (std::size_t p = 0; p < out_.parts.size(); ++p)
        if (out_.parts[p].repaired) plain_where_lost(static_cast<int>(p), redo);
      if (redo.empty()) break;
      redraw(redo);
    }
    // Each part that still falls apart tries all its borders plain; where even that leaves it
    // in pieces (the mitres alone cut it: a neck narrower than the smallest feature between two
    // folds), its joints are not what cuts it, and the kept piece keeps them.
    for (std::size_t p = 0; p < out_.parts.size(); ++p) {
      if (!out_.parts[p].repaired) continue;
      Trial trial(*this);
      std::set<int> redo;
      for (BorderJoint& b : out_.borders) {
        if (b.patches[0] != static_cast<int>(p) && b.patches[1] != static_cast<int>(p)) continue;
        for (JointInterval& in : b.intervals) make_plain(b, in);
        redo.insert(b.patches[0]);
        redo.insert(b.patches[1]);
      }
      redraw(redo);
      if (out_.parts[p].repaired) trial.revert();
    }
    give_stubs_a_tooth(forbidden);
    if (o_.stub_teeth) {
      widen_thin_necks(forbidden, true);
      widen_thin_necks(forbidden, false);
    }
    give_corners_a_tooth();
    // Last, with every joint settled: corners hanging on a short neck go (never a tooth). Done
    // while drawing, it changed which stub teeth fit (one of the demo's short borders lost its
    // joint: the tooth would have hung on the neck the cut corner had shared).
    for_each_of(every, [&](int p) {
      PartOutline& part = out_.parts[p];
      Polygon2 trimmed = trimmed_outline(p);
      if (trimmed != part.designed) set_outline(part, std::move(trimmed));
    });
    // What the thin-neck pass could not mend, said (stanford-bunny from its triangles at 250
    // mm: a strip end of part 266 hung on a neck 0.24 mm wide as cut, found only by the auditor).
    // And slits left narrower than the smallest feature: the widening that would cut the part
    // in two is not made (slit_widenings), nor one into a tooth, and a tapering slit may stay
    // narrow at its end after the last widening (Spot's cage remeshed at 4000 mm: a V 1.2 mm
    // deep beside a tooth, which the auditor finds).
    // Slits as the laser cuts them, as the auditor reads the sheets back: a notch narrower than
    // the kerf is one the laser path does not enter (the bowl at 600 mm: a notch 0.04 mm wide
    // and 1.5 mm deep where a tooth met a cut-back, named here, absent from the sheet).
    // A draft's are not looked for: the resolve loop reads neither, and its final build, with
    // stub teeth, names them.
    std::vector<char> necked(out_.parts.size(), 0), slit(out_.parts.size(), 0);
    for_each_of(out_.draft ? std::vector<int>{} : every, [&](int p) {
      necked[p] = thin_necks(p).empty() && !splits_apart(p) ? 0 : 1;
      const Polygon2& path = out_.parts[p].cut;
      slit[p] =
          checked(
              'S', [&](std::string& key) { put_polygons(key, {path}); },
              [&] {
                return OutlineCheck{narrow_slits_as_cut(path, kerf_width_, o_.min_feature), {}};
              }).polygons.empty()
              ? 0
              : 1;
    });
    for (std::size_t p = 0; p < out_.parts.size(); ++p) {
      if (necked[p]) out_.thin_neck_parts.push_back(static_cast<int>(p));
      if (slit[p]) out_.slit_parts.push_back(static_cast<int>(p));
    }
    for (std::size_t p = 0; p < out_.parts.size(); ++p) {
      if (!out_.parts[p].repaired) continue;
      ++out_.repaired_parts;
      out_.parts[p].lost = lost_[p];
      for (const Polygon2& piece : lost_[p]) {
        const double area = std::abs(polygon_area(piece));
        out_.lost_area += area;
        out_.largest_lost_piece = std::max(out_.largest_lost_piece, area);
      }
    }
    for (std::size_t b = 0; b < out_.borders.size(); ++b) {
      std::vector<TabFlare> flares;
      for (int j = 0; j + 1 < static_cast<int>(out_.borders[b].intervals.size()); ++j)
        if (const auto f = flare_between(static_cast<int>(b), j)) flares.push_back(*f);
      out_.flares.push_back(std::move(flares));
    }
    join_stubs_at_corners(out_, s_, bp_, kStubAtCorner * o_.tooth_width);
    return std::move(out_);
  }

 private:
  OutlineMemo* memo_;  // may be null
  const Strips& s_;
  const Flattening& f_;
  const double thickness_, kerf_width_;  // [mm]
  const JointOptions& o_;
  const border::Pieces bp_;
  const std::vector<Ring>& rings_;
  const std::vector<Piece>& pieces_;
  const border::Plates plates_;
  std::vector<std::vector<Polygon2>> lost_;  // per part: the pieces it lost when last drawn
  Joints out_;
  // While stub teeth are tried in parallel: the outlines of the parts the wave's borders
  // change, as they were when it began (give_stubs_a_tooth()).
  std::map<int, Polygon2> wave_outlines_;
  // While the thin-neck pass gives borders it left bare their tooth again the second time
  // (widen_thin_necks()): a tooth whose part the round erosion parts is refused too.
  bool round_necks_ = false;

  /// A try of several changes to the joints that may be taken back (revert()), as if out_ and
  /// lost_ had been copied when it began: it keeps the joints but for the parts' outlines, and
  /// the outline and lost pieces of each part as they were before the try first drew it again
  /// (outline() tells the open try, touch()); a part not drawn again is as it was. Copying
  /// every part for each try grew as the parts times the tries (Spot's cage after four
  /// Catmull-Clark steps: the joints stage 202 s with the copies, 159 s without). One try at a
  /// time; its parts may be drawn on several threads.
  class Trial {
   public:
    explicit Trial(Builder& b) : b_(b) {
      std::vector<PartOutline> parts = std::move(b.out_.parts);
      shell_ = b.out_;
      b.out_.parts = std::move(parts);
      b.trial_ = this;
    }
    ~Trial() { b_.trial_ = nullptr; }
    Trial(const Trial&) = delete;
    Trial& operator=(const Trial&) = delete;

    /// Everything as when the try began.
    void revert() {
      std::vector<PartOutline> parts = std::move(b_.out_.parts);
      b_.out_ = shell_;
      b_.out_.parts = std::move(parts);
      for (const auto& [p, saved] : saved_) b_.out_.parts[p] = saved.part, b_.lost_[p] = saved.lost;
    }
    /// Part \p p is about to be drawn again: kept as it is, if not yet.
    void touch(int p) {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!saved_.contains(p)) saved_.emplace(p, Saved{b_.out_.parts[p], b_.lost_[p]});
    }
    /// The borders as when the try began.
    const std::vector<BorderJoint>& borders() const { return shell_.borders; }
    /// Part \p p as when the try began.
    const PartOutline& part(int p) const {
      const auto it = saved_.find(p);
      return it == saved_.end() ? b_.out_.parts[p] : it->second.part;
    }
    /// True when part \p p's outline differs from the one it had when the try began.
    bool changed(int p) const {
      const auto it = saved_.find(p);
      return it != saved_.end() && it->second.part.designed != b_.out_.parts[p].designed;
    }

   private:
    struct Saved {
      PartOutline part;
      std::vector<Polygon2> lost;
    };
    Builder& b_;
    Joints shell_;  // out_ without its parts
    std::map<int, Saved> saved_;
    std::mutex mutex_;
  };
  Trial* trial_ = nullptr;  // the open try, if any

  /// Box teeth where they are deep enough, else tabs if they are, else nothing (shallow).
  JointKind kind_for(double fold) const {
    const ToothOffsets box = offsets_of(JointKind::kBox, fold);
    if (box.tip - box.slot >= o_.min_depth) return JointKind::kBox;
    // Paper (no thickness) is glued with tabs of its own, not with tabs cut from the sheet.
    if (o_.tab_misfit > o_.protrusion && thickness_ > 0) {
      const ToothOffsets tab = offsets_of(JointKind::kTab, fold);
      if (tab.tip - tab.slot >= o_.min_depth) return JointKind::kTab;
    }
    return JointKind::kNone;
  }
  /// A tab's tip may leave the mate's faces by the misfit; it is no longer than a tooth is wide
  /// (a longer tab locates no better and needs more room in both parts).
  ToothOffsets offsets_of(JointKind kind, double fold) const {
    const double f = std::clamp(fold, 1e-6, kMaxJointFold);
    if (kind == JointKind::kTab)
      return tooth_offsets(f, thickness_, o_.tab_misfit,
                           std::min(o_.max_tip, 0.5 * o_.tooth_width));
    return tooth_offsets(f, thickness_, o_.protrusion, o_.max_tip);
  }
  /// The offsets an interval of \p kind is drawn with: box offsets where there is no joint.
  static JointKind drawn_as(JointKind kind) {
    return kind == JointKind::kNone ? JointKind::kBox : kind;
  }
  ToothOffsets offsets_at(const Piece& piece, double s) const {
    const double fold = piece.fold_at(s);
    return offsets_of(drawn_as(kind_for(fold)), fold);
  }

  /// Paper Fig. 6: every mated outline edge gets a band from its slot to its tip offset; where
  /// bands of other edges of the part (and the transitions at sharp corners) overlap it, the
  /// overlap, projected onto the edge, is no place for teeth.
  void restrict_by_bands(int p, std::vector<std::vector<std::array<double, 2>>>& forbidden) {
    const Ring& ring = rings_[p];
    const int m = static_cast<int>(ring.edges.size());
    std::vector<Polygon2> band(m);
    std::vector<std::array<double, 4>> box(m);
    for (int k = 0; k < m; ++k) {
      if (ring.piece[k] < 0) continue;
      const Piece& piece = pieces_[ring.piece[k]];
      const Side& side = piece.sides[ring.piece_side[k]];
      const ToothOffsets a = offsets_at(piece, s_of(side, k, 0)),
                         b = offsets_at(piece, s_of(side, k, 1));
      const Vec2 n = ring.normal[k];
      band[k] = {ring.start[k] + a.slot * n, ring.end[k] + b.slot * n, ring.end[k] + b.tip * n,
                 ring.start[k] + a.tip * n};
      box[k] = {1e300, 1e300, -1e300, -1e300};
      for (const auto& v : band[k])
        box[k] = {std::min(box[k][0], v.x()), std::min(box[k][1], v.y()),
                  std::max(box[k][2], v.x()), std::max(box[k][3], v.y())};
    }
    auto turn = [&](int k, int j) {  // angle between the directions of edges k and j
      const Vec2 a = ring.end[k] - ring.start[k], b = ring.end[j] - ring.start[j];
      return std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)));
    };
    // Transitions at sharp corners between two mated edges.
    std::vector<Polygon2> transition(m);
    for (int k = 0; k < m; ++k) {
      const int j = (k + 1) % m;
      if (band[k].empty() || band[j].empty() || turn(k, j) < o_.sharp_turn) continue;
      transition[k] = {band[k][1], band[k][2], band[j][3], band[j][0]};
    }
    for (int k = 0; k < m; ++k) {
      if (band[k].empty()) continue;
      const Vec2 d = ring.end[k] - ring.start[k];
      const double len2 = d.squaredNorm();
      if (!(len2 > 0)) continue;
      auto project = [&](const std::vector<Polygon2>& overlap) {
        for (const auto& poly : overlap) {
          if (std::abs(polygon_area(poly)) < 1e-10) continue;
          double t0 = 1e300, t1 = -1e300;
          for (const auto& v : poly) {
            const double t = (v - ring.start[k]).dot(d) / len2;
            t0 = std::min(t0, t), t1 = std::max(t1, t);
          }
          t0 = std::clamp(t0, 0.0, 1.0), t1 = std::clamp(t1, 0.0, 1.0);
          const Piece& piece = pieces_[ring.piece[k]];
          const Side& side = piece.sides[ring.piece_side[k]];
          double s0 = s_of(side, k, t0), s1 = s_of(side, k, t1);
          if (s0 > s1) std::swap(s0, s1);
          forbidden[2 * ring.piece[k] + ring.piece_side[k]].push_back({s0, s1});
        }
      };
      for (int j = 0; j < m; ++j) {
        if (j == k || band[j].empty()) continue;
        const bool adjacent = j == (k + 1) % m || k == (j + 1) % m;
        if (adjacent && turn(k, j) < o_.sharp_turn) continue;
        if (box[j][0] > box[k][2] || box[k][0] > box[j][2] || box[j][1] > box[k][3] ||
            box[k][1] > box[j][3])
          continue;
        project(polygon_intersection(band[k], band[j]));
      }
      for (int j = 0; j < m; ++j) {
        if (transition[j].empty() || j == k || (j + 1) % m == k) continue;
        project(polygon_intersection(band[k], transition[j]));
      }
    }
  }

  /// Interval [s0, s1] of \p piece, not yet owned, with the fold at its middle, \p kind the
  /// joint that fold calls for, and the offsets of that kind (box where none) taken
  /// conservatively over the interval: the shortest tip, the deepest slot and plain cut-back.
  JointInterval interval_on(const Piece& piece, double s0, double s1, JointKind& kind) const {
    JointInterval in;
    in.s0 = s0;
    in.s1 = s1;
    in.fold = piece.fold_at(0.5 * (s0 + s1));
    in.plain = plain_offset(in.fold, thickness_);
    kind = kind_for(in.fold);
    const JointKind shape = drawn_as(kind);
    in.offsets = offsets_of(shape, in.fold);
    for (double at : {s0, s1}) {
      const ToothOffsets e = offsets_of(shape, piece.fold_at(at));
      in.offsets.tip = std::min(in.offsets.tip, e.tip);
      in.offsets.slot = std::min(in.offsets.slot, e.slot);
      in.plain = std::min(in.plain, plain_offset(piece.fold_at(at), thickness_));
    }
    return in;
  }

  void place_teeth(const std::vector<std::vector<std::array<double, 2>>>& forbidden) {
    for (std::size_t i = 0; i < pieces_.size(); ++i) {
      const Piece& piece = pieces_[i];
      BorderJoint b;
      b.edge = piece.edge;
      b.edges = piece.edges;
      b.patches = {piece.sides[0].patch, piece.sides[1].patch};
      b.length = piece.length;
      for (const Stretch& st :
           tooth_stretches(piece.length, forbidden[2 * i], forbidden[2 * i + 1])) {
        JointKind kind;
        JointInterval in = interval_on(piece, st.s0, st.s1, kind);
        bool free = true;
        for (int side = 0; side < 2 && free; ++side)
          for (const auto& f : forbidden[2 * i + side])
            if (std::min(f[1], in.s1) - std::max(f[0], in.s0) > 1e-9) free = false;
        if (kind == JointKind::kNone || in.offsets.tip - in.offsets.slot < o_.min_depth) {
          ++b.shallow;
        } else if (!free) {
          ++b.blocked;
        } else if (const int owner = owner_of(static_cast<int>(i), in, st); owner < 0) {
          ++b.blocked;  // a tooth would have to be trimmed at a corner
        } else {
          in.owner = owner;
          in.kind = kind;
          ++b.teeth;
          out_.toothed_length += in.s1 - in.s0;
          if (kind == JointKind::kTab) ++b.tabs, ++out_.tabs, out_.tab_length += in.s1 - in.s0;
        }
        b.intervals.push_back(in);
      }
      out_.teeth += b.teeth;
      out_.border_length += piece.length;
      out_.borders.push_back(std::move(b));
    }
  }

  /// An interval of a border as tooth_stretches() lays it out.
  struct Stretch {
    double s0 = 0, s1 = 0;  // arc length along the piece [mm]
    int phase = -1;         // side whose turn it is for a tooth (0 or 1); -1: plain
    bool lone = false;      // the only tooth stretch of its free run
  };

  /// True when \p part, drawn whole, is smaller than a maker can handle: less than
  /// JointOptions::min_part_area, or nowhere JointOptions::min_part_width wide. A part whose
  /// every point lies within r of its outline has A <= r P (it lies in the band of width r
  /// inside its outline), so one with 2 A / P at least that width is not narrow and needs no
  /// offset.
  bool too_small(const PartOutline& part) const {
    if (part.designed.size() < 3) return false;
    return std::abs(polygon_area(part.designed)) < o_.min_part_area || narrow(part);
  }
  /// Nowhere JointOptions::min_part_width wide (see too_small).
  bool narrow(const PartOutline& part) const {
    if (part.designed.size() < 3 || !(o_.min_part_width > 0)) return false;
    const double area = std::abs(polygon_area(part.designed));
    double perimeter = 0;
    for (std::size_t i = 0; i < part.designed.size(); ++i)
      perimeter += (part.designed[(i + 1) % part.designed.size()] - part.designed[i]).norm();
    return 2 * area < o_.min_part_width * perimeter &&
           polygon_offset({part.designed}, -0.5 * o_.min_part_width).empty();
  }

  /// A border that has no tooth, tab or glue line yet (a short stretch between two corners,
  /// where the free room between the corners' bands is narrower than a tooth plus the usual
  /// margins) gets one tooth in that room if both parts, drawn with it, stay whole and no tooth of
  /// either is bitten: the margins guard against slits and tails next to a tooth, and the outline
  /// cleanup (without_thin_features) already widens such slits and cuts such tails off where they
  /// occur, so here the drawn outlines decide. The room is the band-free stretch (the bands keep
  /// the tooth out of third parts, as for every tooth); widest first, then with a margin of
  /// half the smallest feature, then none; the tooth is as wide as the tooth width allows and at
  /// least 1.2 times the smallest feature (1.2 mm).
  /// The borders are tried in waves of borders that share no part, each wave in parallel:
  /// trying one border changes only it and its two parts, so a border waits for the earlier
  /// ones that share a part with it. It also reads the outlines of third parts near it in 3D
  /// (reach_into): those of a part another border of the wave changes are read as they
  /// were when the wave began (wave_outlines_), so the outcome does not depend on timing.
  void give_stubs_a_tooth(const std::vector<std::vector<std::array<double, 2>>>& forbidden,
                          const std::set<int>* only = nullptr) {
    if (!o_.stub_teeth) return;
    std::vector<int> pending;
    for (std::size_t i = 0; i < out_.borders.size(); ++i)
      if (out_.borders[i].teeth == 0 && (!only || only->contains(static_cast<int>(i))))
        pending.push_back(static_cast<int>(i));
    while (!pending.empty()) {
      std::vector<int> wave, later;
      std::set<int> busy;  // parts of the borders before, in this wave or waiting
      for (int i : pending) {
        const auto& parts = out_.borders[i].patches;
        (busy.count(parts[0]) || busy.count(parts[1]) ? later : wave).push_back(i);
        busy.insert(parts.begin(), parts.end());
      }
      wave_outlines_.clear();
      for (int i : wave)
        for (int q : out_.borders[i].patches) wave_outlines_[q] = out_.parts[q].designed;
      std::vector<StubTrial> trials(wave.size());
      for_each_index(static_cast<int>(wave.size()), hardware_threads(),
                     [&](int k) { give_stub_a_tooth(wave[k], forbidden, trials[k]); });
      for (const StubTrial& t : trials) add_totals(t);
      pending = std::move(later);
    }
    wave_outlines_.clear();
  }

  /// A border left without a joint that its parts' joints at its corners would hold
  /// (join_stubs_at_corners()) if each of those had one within reach of the corner: a stub
  /// tooth on each such border, in that reach, clear of its other teeth by a tooth width; like
  /// a stub tooth in the bands, checked in 3D against the parts around it and drawn. All of a
  /// border's, or none (a tooth that holds nothing more is not cut).
  /// (stanford-bunny from its triangles at 250 mm: a 6.4 mm border folded 100 deg, whose
  /// every tooth reached 0.2-0.6 mm into a third part, between parts each jointed to the parts
  /// at both its corners, two of those joints 7.7 and 10.9 mm from the corner.)
  void give_corners_a_tooth() {
    if (!o_.stub_teeth) return;
    const double reach = kStubAtCorner * o_.tooth_width;
    for (const std::vector<CornerEnd>& want : joints_wanted_at_corners(out_, s_, bp_, reach)) {
      Trial trial(*this);
      StubTrial t;
      bool all = true;
      for (const CornerEnd& c : want) {
        const BorderJoint& b = out_.borders[c.border];
        if (out_.parts[b.patches[0]].repaired || out_.parts[b.patches[1]].repaired) {
          all = false;
          break;
        }
        // The stretch from the corner to the reach, a tooth width short of its nearest tooth.
        double lo = 0, hi = b.length;
        for (const JointInterval& in : b.intervals)
          if (in.owner >= 0) {
            if (c.end == 0)
              hi = std::min(hi, in.s0 - o_.tooth_width);
            else
              lo = std::max(lo, in.s1 + o_.tooth_width);
          }
        if (c.end == 0)
          hi = std::min(hi, reach);
        else
          lo = std::max(lo, b.length - reach);
        bool given = false;
        for (const auto& [s0, s1] : stub_candidates(lo, hi))
          if ((given = try_tooth(c.border, s0, s1, t, true))) break;
        if (!given) {
          all = false;
          break;
        }
      }
      if (!all) {
        trial.revert();
        continue;
      }
      add_totals(t);
    }
  }

  /// One border's try at a stub tooth: candidates drawn, the part that failed the last one
  /// (drawn first next), and what it added to the totals.
  struct StubTrial {
    int drawings = 0;
    int failed_last = -1;
    int teeth = 0, tabs = 0;
    double toothed_length = 0, tab_length = 0;  // [mm]
  };

  /// The narrowest stub tooth: one only as wide as the smallest feature is what the outline
  /// rules call a tail (an opening by half that width takes all of it): a fifth wider, and at
  /// least 1 mm [mm].
  double narrowest_stub() const { return std::max(1.0, 1.2 * o_.min_feature); }

  /// Stub teeth on the stretch [\p lo, \p hi] of a border [mm], in the order they are tried:
  /// widest first (the tooth width, then 0.5 mm narrower each, down to narrowest_stub()), and
  /// of each width centred first, then at a quarter, three quarters and either end.
  std::vector<std::array<double, 2>> stub_candidates(double lo, double hi) const {
    std::vector<std::array<double, 2>> candidates;
    for (double width = std::min(o_.tooth_width, hi - lo); width >= narrowest_stub() - 1e-9;
         width -= 0.5) {
      const double slack = hi - lo - width;
      for (double place : {0.5, 0.25, 0.75, 0.0, 1.0}) {
        candidates.push_back({lo + place * slack, lo + place * slack + width});
        if (slack < 1e-9) break;  // one place only
      }
    }
    return candidates;
  }

  /// Adds what a border's stub teeth added (\p t) to the joints' totals.
  void add_totals(const StubTrial& t) {
    out_.teeth += t.teeth, out_.tabs += t.tabs;
    out_.toothed_length += t.toothed_length, out_.tab_length += t.tab_length;
  }

  /// give_stubs_a_tooth() for border \p i.
  void give_stub_a_tooth(int i, const std::vector<std::vector<std::array<double, 2>>>& forbidden,
                         StubTrial& t) {
    const double narrowest = narrowest_stub();
    BorderJoint& b = out_.borders[i];
    const Piece& piece = pieces_[i];
    std::vector<std::array<double, 2>> room;  // free stretches, widest first
    double at = 0;
    for (const auto& f : blocked(piece.length, forbidden[2 * i], forbidden[2 * i + 1])) {
      if (f[0] > at) room.push_back({at, f[0]});
      at = f[1];
    }
    if (piece.length > at) room.push_back({at, piece.length});
    std::sort(room.begin(), room.end(),
              [](const auto& x, const auto& y) { return x[1] - x[0] > y[1] - y[0]; });
    b.free_room = room.empty() ? 0.0 : room.front()[1] - room.front()[0];
    // A part that fell apart and joins itself (a loop cut open): which of its pieces the two
    // sides are on is unknown (on Spot's raw strips such a tooth reached 1.2 mm into a third
    // part in 3D).
    if (b.patches[0] == b.patches[1] && out_.parts[b.patches[0]].repaired) return;
    for (const auto& r : room)
      for (double margin : {o_.min_feature, 0.5 * o_.min_feature, 0.0}) {
        // Ends of the border are corners of both parts, not bands: no margin there.
        const double lo = r[0] > 1e-9 ? r[0] + margin : r[0];
        const double hi = r[1] < piece.length - 1e-9 ? r[1] - margin : r[1];
        const double width = std::min(o_.tooth_width, hi - lo);
        if (width < narrowest - 1e-6) continue;
        const double mid = 0.5 * (lo + hi);
        if (try_tooth(i, mid - 0.5 * width, mid + 0.5 * width, t)) return;
      }
    // A part that fell apart takes a tooth in the free room only: its pieces' plates, as drawn,
    // are no ground for the 3D check below.
    if (out_.parts[b.patches[0]].repaired || out_.parts[b.patches[1]].repaired) return;
    // No room between the bands: the bands are the conservative rule (every tooth they let
    // through is clear of third parts in 3D); here the tooth is checked in 3D directly against
    // the plates of the parts around it, as drawn, and may reach into the bands.
    // Widest first, centred first, but where a part is long (kScreenFrom) and a drawing
    // failed, those that look sound near the border (looks_sound) before the others; only the
    // candidates clear of third parts are drawn, and at most kStubDrawings of them (drawing is
    // what costs).
    const std::vector<std::array<double, 2>> candidates = stub_candidates(0, piece.length);
    const int drawn_before = t.drawings;
    const bool screen = std::max(out_.parts[b.patches[0]].designed.size(),
                                 out_.parts[b.patches[1]].designed.size()) >= kScreenFrom;
    std::vector<std::pair<std::array<double, 2>, std::array<bool, 2>>> later;
    for (const auto& c : candidates) {
      if (t.drawings - drawn_before >= kStubDrawings) break;
      // Until a drawing fails, every candidate looks sound: most first candidates are.
      const std::array<bool, 2> looks = !screen || t.drawings == drawn_before
                                            ? std::array{true, true}
                                            : looks_sound(i, c[0], c[1]);
      if (!looks[0] || !looks[1]) later.push_back({c, {!looks[0], !looks[1]}});
      if ((looks[0] || looks[1]) && try_tooth(i, c[0], c[1], t, true, looks)) return;
    }
    for (const auto& [c, owners] : later) {
      if (t.drawings - drawn_before >= kStubDrawings) break;
      if (try_tooth(i, c[0], c[1], t, true, owners)) return;
    }
  }

  /// The rectangles a tooth of interval \p in of border \p i, owned by side \p owner, takes on
  /// side \p k, one per ring edge it runs along: on the owner from the plain cut-back to the
  /// tip, on its mate from \p mate_from (the border line, or just inside it) to the slot depth.
  /// Counter-clockwise; those of no area left out.
  std::vector<Polygon2> joint_rects(int i, const JointInterval& in, int owner, int k,
                                    double mate_from) const {
    const double lo = k == owner ? std::min(in.plain, 0.0) : mate_from,
                 hi = k == owner ? in.offsets.tip : std::min(in.offsets.slot, in.plain);
    std::vector<Polygon2> rects;
    for (const Zone& z : tooth_zones(i, in, k)) {
      Polygon2 r = {z.from + lo * z.normal, z.to + lo * z.normal, z.to + hi * z.normal,
                    z.from + hi * z.normal};
      if (std::abs(polygon_area(r)) < 1e-12) continue;
      make_counter_clockwise(r);
      rects.push_back(std::move(r));
    }
    return rects;
  }

  /// Per side of border \p i, whether a tooth on [s0, s1] it owns, reaching into the bands,
  /// looks sound before either part is drawn with it: the side may own it and neither part falls in
  /// more pieces near the border under an opening by half the smallest feature (adds_thin_neck)
  /// when the tooth's rectangle is added to the owner as drawn and the slot's cut from its mate.
  /// Drawing decides (try_tooth); this only orders the candidates, as drawing a long strip costs
  /// tens of milliseconds and a slot that pinches its mate through (the quad sphere's V-shaped
  /// strip ends) fails at every width.
  std::array<bool, 2> looks_sound(int i, double s0, double s1) const {
    const BorderJoint& b = out_.borders[i];
    JointKind kind;
    const JointInterval in = interval_on(pieces_[i], s0, s1, kind);
    std::array<bool, 2> looks = {false, false};
    if (kind == JointKind::kNone || in.offsets.tip - in.offsets.slot < o_.min_depth) return looks;
    constexpr double kOverlap = 1e-3;  // as in shapes(): the rectangles cross the border line
    for (int owner : {0, 1}) {
      if (untrimmed_owner(i, in, owner) != owner) continue;
      bool sound = true;
      for (int k = 0; k < 2 && sound; ++k) {
        const Polygon2& before = out_.parts[b.patches[k]].designed;
        if (before.size() < 3) continue;
        const std::vector<Polygon2> rects = joint_rects(i, in, owner, k, kOverlap);
        if (rects.empty()) continue;
        Vec2 bl = rects[0][0], tr = rects[0][0];
        for (const Polygon2& r : rects)
          for (const Vec2& v : r) bl = bl.cwiseMin(v), tr = tr.cwiseMax(v);
        const std::vector<Polygon2> near = clipped(before, bl, tr);
        std::vector<Polygon2> with = near;
        with.insert(with.end(), rects.begin(), rects.end());
        sound =
            !more_pieces(k == owner ? polygon_union(with) : polygon_difference(near, rects), near);
      }
      looks[owner] = sound;
    }
    return looks;
  }

  /// True when the tooth of interval \p in of border \p i, owned by side \p owner, is on its
  /// part as drawn (its rectangle from the plain cut-back to the tip within the outline, to 1 %)
  /// and the slot for it is cut from the mate (its rectangle from the border line to the slot
  /// depth clear of the outline, to 1 %).
  /// The slot's rectangle on the mate must also lie clear of the pieces \p lost_before (per side)
  /// the mate lost without the tooth: a slot cut from a piece that is lost anyway holds nothing.
  bool tooth_and_slot_drawn(int i, const JointInterval& in, int owner,
                            const std::array<std::vector<Polygon2>, 2>& lost_before) const {
    const BorderJoint& b = out_.borders[i];
    for (int k : {0, 1}) {
      const Polygon2& drawn = out_.parts[b.patches[k]].designed;
      for (const Polygon2& r : joint_rects(i, in, owner, k, 0.0)) {
        const double area = std::abs(polygon_area(r));
        if (area < 1e-9) continue;
        const double inside = common_area(drawn, r);
        if (k == owner ? inside < 0.99 * area : inside > 0.01 * area) return false;
        if (k == owner || lost_before[k].empty()) continue;
        double on_lost = 0;
        for (const Polygon2& piece : lost_before[k]) on_lost += common_area(piece, r);
        if (on_lost > 0.01 * area) return false;
      }
    }
    return true;
  }

  /// True when \p after are the pieces \p before lost, with a slot or tooth added to the piece
  /// kept: as many, of the same area within 0.05 mm^2, or up to kMoreLost more (a slot beside
  /// the neck where the part comes apart takes a crumb more with the lost piece: fertility's
  /// part 307 at 250 mm, 0.19 mm^2 more of a 13.1 mm^2 piece, was left without a joint on three
  /// borders for it). A tooth on a lost piece adds its own area, at least 0.6 mm^2 (1.2 by
  /// 0.5 mm), and tooth_and_slot_drawn() finds it.
  static bool same_loss(const std::vector<Polygon2>& after, const std::vector<Polygon2>& before) {
    if (after.size() != before.size()) return false;
    double more = 0;
    for (const Polygon2& p : after) more += std::abs(polygon_area(p));
    for (const Polygon2& p : before) more -= std::abs(polygon_area(p));
    return more >= -0.05 && more <= kMoreLost;
  }

  /// Border \p i (all plain) with a tooth on [s0, s1] instead, kept if one of its sides (of those
  /// \p owners allows) can own it with both parts whole (or, one that fell apart without it,
  /// losing the same pieces), no tooth of theirs bitten and no new thin neck (adds_thin_neck);
  /// otherwise everything as before.
  bool try_tooth(int i, double s0, double s1, StubTrial& t, bool in_bands = false,
                 std::array<bool, 2> owners = {true, true}) {
    BorderJoint& b = out_.borders[i];
    JointKind kind;
    const JointInterval in = interval_on(pieces_[i], s0, s1, kind);
    if (kind == JointKind::kNone || in.offsets.tip - in.offsets.slot < o_.min_depth) return false;
    // The plain intervals around it keep their offsets.
    std::vector<JointInterval> with;
    for (const JointInterval& old : b.intervals) {
      for (const auto& [lo, hi] :
           {std::pair{old.s0, std::min(old.s1, s0)}, std::pair{std::max(old.s0, s1), old.s1}}) {
        if (hi - lo <= 1e-9) continue;
        JointInterval part = old;
        part.s0 = lo, part.s1 = hi;
        with.push_back(part);
      }
    }
    with.push_back(in);
    std::sort(with.begin(), with.end(),
              [](const JointInterval& x, const JointInterval& y) { return x.s0 < y.s0; });
    const std::vector<JointInterval> before = b.intervals;
    const std::array<PartOutline, 2> drawn = {out_.parts[b.patches[0]], out_.parts[b.patches[1]]};
    const std::array<std::vector<Polygon2>, 2> lost = {lost_[b.patches[0]], lost_[b.patches[1]]};
    // Beside a part that fell apart, the bands' rule is no guarantee: checked in 3D too, and the
    // tooth and its slot measured on the parts as drawn.
    const bool fell_apart = drawn[0].repaired || drawn[1].repaired;
    const bool in_3d = in_bands || fell_apart;
    // A part too small to handle owns the tooth if it can: a slot would make it smaller still.
    const bool second_first = too_small(drawn[1]) && !too_small(drawn[0]);
    for (int owner : second_first ? std::array{1, 0} : std::array{0, 1}) {
      if (!owners[owner] || untrimmed_owner(i, in, owner) != owner) continue;
      // Into third parts first: they are drawn already and this tooth does not change them.
      std::vector<Zone> zones;
      if (in_3d) {
        zones = tooth_zones(i, in, owner);
        if (reach_into(b.patches[owner], i, in, zones, nullptr, Into::kThirdParts,
                       kThirdPartReach) > kThirdPartReach)
          continue;
      }
      b.intervals = with;
      for (JointInterval& x : b.intervals)
        if (x.s0 == s0 && x.s1 == s1) x.owner = owner, x.kind = kind;
      ++t.drawings;
      // The part that failed the last trial on this border first, else the part with fewer
      // borders: drawing is what costs, and the second part is not drawn if the first fails.
      std::array<int, 2> order = b.patches;
      if (t.failed_last == order[1] ||
          (t.failed_last != order[0] &&
           rings_[order[1]].edges.size() < rings_[order[0]].edges.size()))
        std::swap(order[0], order[1]);
      // No tooth bitten, whole, and no new thin neck: a tooth hanging on one breaks off. A
      // bitten tooth shows in the part's shapes alone, so it is looked for before the part is
      // drawn: the demo's longest strip (1470 vertices) was drawn for 7 of its 41 candidate stub
      // teeth only to find one bitten. (Looked for in both parts before either is drawn, it cost
      // amo_quad 10 % more time: the first part drawn fails more often than not.)
      bool sound = true;
      for (int k = 0; k < 2 && sound; ++k) {
        const int p = order[k];
        const int side = p == b.patches[0] ? 0 : 1;
        const PartOutline& old = drawn[side];
        sound = bitten_teeth(p).empty();
        if (sound) {
          out_.parts[p] = outline(p);
          // A part that fell apart without the tooth (its slots cut off a piece: the resolve
          // stage lists it) may take one on the piece it keeps: it loses the same pieces, so
          // the tooth and its slot are both on the piece cut.
          sound = !out_.parts[p].repaired || (old.repaired && same_loss(lost_[p], lost[side]));
        }
        // Nor a part left too narrow to handle that was not (a slot of a stub tooth from each
        // side narrowed a 77 mm^2 strip end of Spot's triangle mesh to under 3 mm; the tooth
        // the other way round, or none, leaves it as it was). Refusing teeth that leave a part
        // under the smallest area too gave spot_quadrangulated's one such part a tooth the
        // other way round, beside a notch the laser path passes within 0.5 mm of itself.
        if (sound) sound = !adds_thin_neck(out_.parts[p].designed, old.designed);
        if (sound) sound = !narrow(out_.parts[p]) || narrow(old);
        if (!sound) t.failed_last = p;
      }
      // Into its mate, as both are now drawn (the slot cut).
      if (sound && fell_apart) sound = tooth_and_slot_drawn(i, in, owner, lost);
      if (sound && in_3d)
        sound = reach_into(b.patches[owner], i, in, zones, &out_.parts[b.patches[owner]].designed,
                           Into::kMate, kMateReach) <= kMateReach;
      if (sound) {
        b.free_room = -1;
        ++b.teeth, ++t.teeth;
        t.toothed_length += s1 - s0;
        if (kind == JointKind::kTab) ++b.tabs, ++t.tabs, t.tab_length += s1 - s0;
        return true;
      }
    }
    b.intervals = before;
    for (int k = 0; k < 2; ++k) out_.parts[b.patches[k]] = drawn[k], lost_[b.patches[k]] = lost[k];
    return false;
  }

  /// Where the tooth of interval \p in of border \p i lies on side \p owner's part: per ring
  /// edge it runs along, the stretch of the border line (from, to) and its outward normal.
  struct Zone {
    int k = -1;             // ring edge
    double t0 = 0, t1 = 0;  // stretch of it (0 at its ring start)
    Vec2 from, to, normal;
  };
  std::vector<Zone> tooth_zones(int i, const JointInterval& in, int owner) const {
    const Side& side = pieces_[i].sides[owner];
    const Ring& ring = rings_[side.patch];
    std::vector<Zone> zones;
    for (int k : side.ring_edges) {
      const auto [sa, sb] = s_range(side, k);
      const double lo = std::max(in.s0, sa), hi = std::min(in.s1, sb);
      if (hi - lo <= 1e-12) continue;
      double t0 = (lo - sa) / (sb - sa), t1 = (hi - sa) / (sb - sa);
      if (side.reversed) t0 = 1 - t0, t1 = 1 - t1, std::swap(t0, t1);
      const Vec2 a = ring.start[k], b = ring.end[k];
      zones.push_back({k, t0, t1, a + t0 * (b - a), a + t1 * (b - a), ring.normal[k]});
    }
    return zones;
  }

  /// Which plates reach_into() looks into: those of the parts other than the border's two, or
  /// the tooth's mate's.
  enum class Into { kThirdParts, kMate };

  /// How deep the material a tooth adds to part \p p (the \p zones of interval \p in of border
  /// \p i; only where \p within holds it, if given) reaches into the plates of the parts \p into
  /// names in the assembled position [mm]; <= 0: clear. Sampled on a 0.1 mm grid from the plain
  /// cut-back out to the tip, at three heights through the plate. Once a part's plate is reached
  /// deeper than \p enough [mm], the rest are not looked at (the depth returned is then over
  /// \p enough, not necessarily the deepest).
  double reach_into(int p, int i, const JointInterval& in, const std::vector<Zone>& zones,
                    const Polygon2* within, Into into, double enough) const {
    double deepest = -std::numeric_limits<double>::infinity();
    std::vector<Vec3> points;
    Vec3 bmin = Vec3::Constant(1e300), bmax = Vec3::Constant(-1e300);
    const double lo = std::min(in.plain, 0.0), hi = in.offsets.tip;
    for (const Zone& z : zones) {
      const Vec2 along = z.to - z.from;
      const double length = along.norm();
      if (!(length > 0)) continue;
      const int nu = std::max(2, static_cast<int>(std::ceil(length / 0.1))),
                nv = std::max(2, static_cast<int>(std::ceil((hi - lo) / 0.1)));
      for (int a = 0; a <= nu; ++a)
        for (int b = 0; b <= nv; ++b) {
          const Vec2 v =
              z.from + along * (static_cast<double>(a) / nu) + (lo + (hi - lo) * b / nv) * z.normal;
          if (within && !inside(v, *within)) continue;
          const auto [at, normal] = plates_.place(p, v);
          for (double w : {-0.45, 0.0, 0.45}) {
            const Vec3 q = at + w * thickness_ * normal;
            points.push_back(q);
            bmin = bmin.cwiseMin(q), bmax = bmax.cwiseMax(q);
          }
        }
    }
    if (points.empty()) return deepest;
    const BorderJoint& b = out_.borders[i];
    for (int o : plates_.near(bmin, bmax)) {
      const bool mate = o == b.patches[0] || o == b.patches[1];
      if (o == p || mate != (into == Into::kMate)) continue;
      const border::Plates::Window w = plates_.window(o, bmin, bmax);
      if (w.frames.empty()) continue;
      const auto frozen = mate ? wave_outlines_.end() : wave_outlines_.find(o);
      deepest = std::max(
          deepest,
          plates_.deepest_in(
              w, points, frozen != wave_outlines_.end() ? frozen->second : out_.parts[o].designed));
      if (deepest > enough) break;
    }
    return deepest;
  }

  /// The teeth of part \p p (border, interval) that a cut-back of the part bites into by more
  /// than the fit tolerance (0.05 mm of the tooth's width).
  std::vector<std::pair<int, int>> bitten_teeth(int p) const {
    const Shapes sh = shapes(p);
    // Keyed by the tooth regions and depths in order and the cut-backs: the positions of the
    // bitten ones among the spans are the same wherever those are.
    const OutlineCheck found = checked(
        'B',
        [&](std::string& key) {
          put_polygons(key, sh.cut);
          for (const JointSpan& sp : sh.spans)
            if (sp.tooth && sp.region.size() >= 3)
              put(key, sp.offset), put_polygons(key, {sp.region});
        },
        [&] {
          return OutlineCheck{{}, bitten_spans(sh)};
        });
    std::vector<std::pair<int, int>> bitten;
    for (int k : found.positions) bitten.emplace_back(sh.spans[k].border, sh.spans[k].interval);
    return bitten;
  }
  /// bitten_teeth() of the shapes \p sh: the positions of the bitten teeth in sh.spans.
  std::vector<int> bitten_spans(const auto& sh) const {  // auto: Shapes is declared below
    std::vector<int> bitten;
    auto box_of = [](const Polygon2& poly) {
      std::array<double, 4> box = {1e300, 1e300, -1e300, -1e300};
      for (const Vec2& v : poly)
        box = {std::min(box[0], v.x()), std::min(box[1], v.y()), std::max(box[2], v.x()),
               std::max(box[3], v.y())};
      return box;
    };
    std::vector<std::array<double, 4>> cut_boxes;
    for (const auto& c : sh.cut) cut_boxes.push_back(box_of(c));
    for (std::size_t k = 0; k < sh.spans.size(); ++k) {
      const JointSpan& sp = sh.spans[k];
      if (!sp.tooth || sp.region.size() < 3) continue;
      double lost = 0;
      const auto box = box_of(sp.region);
      for (std::size_t c = 0; c < sh.cut.size(); ++c) {
        const auto& o = cut_boxes[c];
        if (o[0] > box[2] || box[0] > o[2] || o[1] > box[3] || box[1] > o[3]) continue;
        lost += common_area(sp.region, sh.cut[c]);
      }
      if (lost > 0.05 * std::abs(sp.offset)) bitten.push_back(static_cast<int>(k));
    }
    return bitten;
  }

  /// The side that gets the tooth of interval \p in laid out as \p st, or -1: the side whose
  /// turn it is, unless its tooth would be trimmed at a corner; a lone tooth has no neighbours
  /// to alternate with, so the other side is tried as well and kept when it fits.
  int owner_of(int i, const JointInterval& in, const Stretch& st) const {
    if (st.phase < 0) return -1;
    int owner = untrimmed_owner(i, in, st.phase);
    if (st.lone) owner = std::max(owner, untrimmed_owner(i, in, 1 - st.phase));
    return owner;
  }

  /// The stretches of a border piece of \p length where side \p a or \p b forbids teeth, within
  /// [0, length], merged (touching within a nanometre) and in order.
  static std::vector<std::array<double, 2>> blocked(double length,
                                                    const std::vector<std::array<double, 2>>& a,
                                                    const std::vector<std::array<double, 2>>& b) {
    std::vector<std::array<double, 2>> all;
    for (const auto* list : {&a, &b})
      for (const auto& f : *list)
        if (std::min(f[1], length) - std::max(f[0], 0.0) > 1e-9)
          all.push_back({std::max(f[0], 0.0), std::min(f[1], length)});
    std::sort(all.begin(), all.end());
    std::vector<std::array<double, 2>> merged;
    for (const auto& f : all)
      if (!merged.empty() && f[0] <= merged.back()[1] + 1e-9)
        merged.back()[1] = std::max(merged.back()[1], f[1]);
      else
        merged.push_back(f);
    return merged;
  }

  /// The intervals of a border piece of \p length: where neither side forbids teeth, stretches
  /// of about the tooth width (teeth alternate sides); the forbidden stretches between them, and
  /// free ones too short for a tooth, plain. Teeth fill the room that is free instead of a fixed
  /// grid, so a short border between two corners still gets one.
  std::vector<Stretch> tooth_stretches(double length, const std::vector<std::array<double, 2>>& a,
                                       const std::vector<std::array<double, 2>>& b) const {
    std::vector<std::array<double, 2>> merged = blocked(length, a, b);
    // The narrowest tooth that stands: half the tooth width, at least 1 mm.
    const double narrowest = std::max(1.0, 0.5 * o_.tooth_width);
    std::vector<Stretch> out;
    auto free_run = [&](double s0, double s1) {
      if (s1 - s0 <= 1e-9) return;
      if (s1 - s0 < narrowest) {
        out.push_back({s0, s1, -1, false});
        return;
      }
      const int n = std::max(1, static_cast<int>(std::lround((s1 - s0) / o_.tooth_width)));
      for (int j = 0; j < n; ++j)
        out.push_back({s0 + (s1 - s0) * j / n, s0 + (s1 - s0) * (j + 1) / n, j % 2, n == 1});
    };
    // A tooth right at the edge of a forbidden stretch would leave a slit narrower than the
    // laser can cut against the cut-back there: the forbidden stretches grow by the smallest
    // feature on each side.
    const double margin = o_.min_feature;
    for (auto& f : merged) f = {std::max(0.0, f[0] - margin), std::min(length, f[1] + margin)};
    double at = 0;
    for (const auto& f : merged) {
      free_run(at, f[0]);
      if (f[1] > std::max(at, f[0]) + 1e-9) out.push_back({std::max(at, f[0]), f[1], -1, false});
      at = std::max(at, f[1]);
    }
    free_run(at, length);
    if (out.empty()) out.push_back({0.0, length, -1, false});
    return out;
  }

  /// \p preferred if its tooth for interval \p in of piece \p i needs no trimming at a
  /// concave corner of its part, else -1: a trimmed tooth no longer fills its slot (the slot in
  /// the flat mate is not trimmed), so it is not made at all (teeth keep alternating).
  int untrimmed_owner(int i, const JointInterval& in, int preferred) const {
    const int p = pieces_[i].sides[preferred].patch;
    const double e = in.offsets.tip;
    for (const Zone& z : tooth_zones(i, in, preferred)) {
      const Polygon2 tooth = {z.from, z.to, z.to + e * z.normal, z.from + e * z.normal};
      const Polygon2 kept = trim_at_concave_corners(p, z.k, z.t0, z.t1, tooth);
      // Trimmed by more than the fit tolerance (0.05 mm of the tooth's width along the edge).
      if (kept.size() < 3 ||
          std::abs(polygon_area(tooth)) - std::abs(polygon_area(kept)) > 0.05 * std::abs(e))
        return -1;
    }
    return preferred;
  }

  /// A tooth that reaches a concave corner of the outline ends on the corner's bisector, so it
  /// neither overlaps the tooth around the corner nor the part's own body there.
  Polygon2 trim_at_concave_corners(int p, int k, double t0, double t1, Polygon2 poly) const {
    const Ring& ring = rings_[p];
    const int m = static_cast<int>(ring.edges.size());
    auto trim = [&](int before, int after, const Vec2& corner, const Vec2& inside) {
      const Vec2 d0 = ring.end[before] - ring.start[before],
                 d1 = ring.end[after] - ring.start[after];
      if (d0.x() * d1.y() - d0.y() * d1.x() >= 0) return;  // left turn: convex, nothing to do
      const Vec2 bis = (ring.normal[before] + ring.normal[after]).normalized();
      Vec2 n(-bis.y(), bis.x());
      if ((inside - corner).dot(n) > 0) n = -n;
      poly = clip_half_plane(poly, corner, n);
    };
    const Vec2 mid = ring.start[k] + 0.5 * (t0 + t1) * (ring.end[k] - ring.start[k]);
    if (t1 > 1 - 1e-9) trim(k, (k + 1) % m, ring.end[k], mid);
    if (t0 < 1e-9) trim((k + m - 1) % m, k, ring.start[k], mid);
    return poly;
  }

  /// The part's outline: its flattened polygon, plus the tooth regions, minus the cut-back
  /// regions of slots and plain stretches (Clipper Booleans, so the result is a simple polygon
  /// whatever the corners do).
  /// What a part's outline is made of: the body and its teeth (to unite), the cut-backs of
  /// slots, plain stretches and the wedges between them (to subtract), and the spans.
  struct Shapes {
    std::vector<Polygon2> add, cut;
    std::vector<JointSpan> spans;
  };

  Shapes shapes(int p) const {
    const Ring& ring = rings_[p];
    Shapes part;
    const int m = static_cast<int>(ring.edges.size());
    Polygon2 base;
    for (int k = 0; k < m; ++k) base.push_back(ring.start[k]);
    std::vector<Polygon2> add = {base}, cut;
    std::vector<double> first_offset(m, 0.0), last_offset(m, 0.0);
    // Per ring edge: its first and last span in part.spans (-1: none).
    std::vector<int> first_span(m, -1), last_span(m, -1);
    for (int k = 0; k < m; ++k) {
      if (ring.piece[k] < 0) continue;
      const Vec2 a = ring.start[k], b = ring.end[k], n = ring.normal[k];
      auto at = [&](double t, double e) { return Vec2(a + t * (b - a) + e * n); };
      const Piece& piece = pieces_[ring.piece[k]];
      const int side_index = ring.piece_side[k];
      const Side& side = piece.sides[side_index];
      const BorderJoint& joint = out_.borders[ring.piece[k]];
      const auto [sa, sb] = s_range(side, k);
      std::vector<std::array<double, 3>> spans;  // t0, t1, offset, in ring order
      for (std::size_t j = 0; j < joint.intervals.size(); ++j) {
        const auto& in = joint.intervals[j];
        const double lo = std::max(in.s0, sa), hi = std::min(in.s1, sb);
        if (hi - lo <= 1e-12) continue;
        double t0 = (lo - sa) / (sb - sa), t1 = (hi - sa) / (sb - sa);
        if (side.reversed) t0 = 1 - t0, t1 = 1 - t1, std::swap(t0, t1);
        const double e = in.owner < 0             ? in.plain
                         : in.owner == side_index ? in.offsets.tip
                                                  : in.offsets.slot;
        spans.push_back({t0, t1, e});
        JointSpan span{ring.piece[k],
                       static_cast<int>(j),
                       (t1 - t0) * (b - a).norm(),
                       e,
                       in.owner == side_index,
                       JointKind::kNone,
                       {},
                       at(t0, 0),
                       at(t1, 0),
                       n};
        if (span.tooth) {
          span.kind = in.kind;
          span.region =
              trim_at_concave_corners(p, k, t0, t1, {at(t0, 0), at(t1, 0), at(t1, e), at(t0, e)});
        }
        if (t0 < 1e-9) first_span[k] = static_cast<int>(part.spans.size());
        if (t1 > 1 - 1e-9) last_span[k] = static_cast<int>(part.spans.size());
        part.spans.push_back(std::move(span));
      }
      std::sort(spans.begin(), spans.end());
      // Rectangles reach 1 um across the border line so that tooth and body overlap (and cut
      // regions clear the border) instead of merely touching after rounding.
      constexpr double kOverlap = 1e-3;
      for (const auto& [t0, t1, e] : spans) {
        if (e > 0) {
          add.push_back(trim_at_concave_corners(
              p, static_cast<int>(k), t0, t1,
              {at(t0, -kOverlap), at(t1, -kOverlap), at(t1, e), at(t0, e)}));
        } else if (e < 0) {
          cut.push_back({at(t0, kOverlap), at(t1, kOverlap), at(t1, e), at(t0, e)});
        }
      }
      if (!spans.empty()) first_offset[k] = spans.front()[2], last_offset[k] = spans.back()[2];
    }
    add_tab_flares(p, part, add, cut);
    // Where two cut-back stretches meet at a corner, the wedge between them goes too (it lies
    // outside the part at convex corners and would stay as a spur at concave ones).
    for (int k = 0; k < m; ++k) {
      const int j = (k + 1) % m;
      if (last_offset[k] < 0 && first_offset[j] < 0)
        cut.push_back({ring.end[k], ring.end[k] + first_offset[j] * ring.normal[j],
                       ring.end[k] + last_offset[k] * ring.normal[k]});
    }
    // A tooth that runs on across a convex bend of its border line is one piece: the wedge
    // between its rectangles is filled (it would otherwise split the tooth into teeth too narrow
    // to stand).
    for (int k = 0; k < m; ++k) {
      const int j = (k + 1) % m;
      if (last_span[k] < 0 || first_span[j] < 0) continue;
      JointSpan& before = part.spans[last_span[k]];
      const JointSpan& after = part.spans[first_span[j]];
      const Vec2 d0 = ring.end[k] - ring.start[k], d1 = ring.end[j] - ring.start[j];
      if (!before.tooth || !after.tooth || before.border != after.border ||
          before.interval != after.interval || d0.x() * d1.y() - d0.y() * d1.x() <= 0)
        continue;
      const Vec2 corner = ring.end[k];
      const double e = before.offset;
      const Polygon2 wedge = {corner, corner + e * ring.normal[j], corner + e * ring.normal[k]};
      add.push_back(wedge);
      Polygon2 region = before.region;
      make_counter_clockwise(region);
      Polygon2 ccw = wedge;
      make_counter_clockwise(ccw);
      before.region = largest_polygon(polygon_union({region, ccw}));
    }
    // Non-zero filling: every polygon counter-clockwise, or overlaps would cancel out.
    for (auto* list : {&add, &cut})
      for (auto& poly : *list) make_counter_clockwise(poly);
    part.add = std::move(add);
    part.cut = std::move(cut);
    return part;
  }

  /// The dovetail sides of part \p p's tabs: at every leaning boundary the part gains the
  /// triangle between the border-perpendicular and the leaning line beyond its border line (its
  /// tab's head widens) and loses the one below it (the mate's head widens there).
  void add_tab_flares(int p, Shapes& part, std::vector<Polygon2>& add,
                      std::vector<Polygon2>& cut) const {
    constexpr double kOverlap = 1e-3;
    const Ring& ring = rings_[p];
    std::set<std::pair<int, int>> sides;  // (piece, side index) of this part
    for (std::size_t k = 0; k < ring.edges.size(); ++k)
      if (ring.piece[k] >= 0) sides.insert({ring.piece[k], ring.piece_side[k]});
    for (const auto& [i, side_index] : sides) {
      const Side& side = pieces_[i].sides[side_index];
      const BorderJoint& border = out_.borders[i];
      for (int j = 0; j + 1 < static_cast<int>(border.intervals.size()); ++j) {
        const std::optional<TabFlare> flare = flare_between(i, j);
        if (!flare) continue;
        // The ring edge of this side where the boundary lies, and the point on it.
        int k = -1;
        double t = 0;
        for (int e : side.ring_edges) {
          const auto [sa, sb] = s_range(side, e);
          if (flare->s >= sa - 1e-9 && flare->s <= sb + 1e-9) {
            k = e;
            t = sb > sa ? std::clamp((flare->s - sa) / (sb - sa), 0.0, 1.0) : 0.5;
            break;
          }
        }
        if (k < 0) continue;
        if (side.reversed) t = 1 - t;
        const Vec2 a = ring.start[k], b = ring.end[k], n = ring.normal[k];
        if (!((b - a).norm() > 0)) continue;
        const Vec2 point = a + t * (b - a);
        const Vec2 ds = (side.reversed ? a - b : b - a).normalized();  // direction of growing s
        const bool own_below = border.intervals[j].owner == side_index;
        const int own = own_below ? j : j + 1, other = own_below ? j + 1 : j;
        const Vec2 e = own_below ? ds : Vec2(-ds);  // from this part's tab toward the mate's
        const double tip = border.intervals[own].offsets.tip;
        const double slot = border.intervals[other].offsets.slot;
        const double k_ = flare->slope, g = flare->clearance;
        const double v0 = 0.5 * g / std::max(k_, 1e-12);  // where the line crosses the boundary
        auto at = [&](double u, double v) { return Vec2(point + u * e + v * n); };
        Polygon2 gain,
            loss = {at(k_ * slot - 0.5 * g, slot), at(kOverlap, slot), at(kOverlap, v0), at(0, v0)};
        if (k_ * tip - 0.5 * g > 0 && tip > v0)
          gain = {at(-kOverlap, v0), at(k_ * tip - 0.5 * g, tip), at(-kOverlap, tip)};
        make_counter_clockwise(loss);
        cut.push_back(loss);
        if (!gain.empty()) {
          make_counter_clockwise(gain);
          add.push_back(gain);
        }
        // The tab's region: the span of its interval that ends at this boundary.
        JointSpan* best = nullptr;
        double nearest = 1e-3;
        for (JointSpan& sp : part.spans)
          if (sp.tooth && sp.border == i && sp.interval == own)
            for (const Vec2& end : {sp.from, sp.to})
              if ((end - point).norm() < nearest) nearest = (end - point).norm(), best = &sp;
        if (best && best->region.size() >= 3) {
          Polygon2 region = best->region;
          make_counter_clockwise(region);
          std::vector<Polygon2> grown = {region};
          if (!gain.empty()) grown = polygon_union({region, gain});
          best->region = largest_polygon(polygon_difference(grown, {loss}));
        }
      }
    }
  }

  /// The intervals of part \p p's joints whose stretch on it (tooth, slot or cut-back, from
  /// its border line out to its offset) comes within a millimetre of a piece the part lost when
  /// it was cut, made plain; the parts on both sides go into \p changed.
  void plain_where_lost(int p, std::set<int>& changed) { plain_near(p, lost_[p], changed); }

  /// Where part \p p's outline narrows to less than the smallest feature between two of its
  /// pieces (an opening by half the smallest feature falls in two there): the stretches of the
  /// outline the opening takes away that touch two of its pieces. without_thin_features() cuts
  /// off what hangs on such a neck only when it is no larger than a square tooth; a larger piece
  /// it leaves hanging, and it breaks off when cut.
  /// \p mitred: by the mitred opening alone (see thin_necks_drawn).
  std::vector<Polygon2> thin_necks(int p, bool mitred = false) const {
    return thin_necks(out_.parts[p].designed, mitred);
  }
  /// Part \p p's outline without the small corners that hang on a short neck and hold no tooth
  /// (without_hanging_corners()): what the last pass of run() cuts.
  Polygon2 trimmed_outline(int p) const {
    const PartOutline& part = out_.parts[p];
    const std::vector<Polygon2> teeth = tooth_regions(part.spans);
    return std::move(checked(
                         'H',
                         [&](std::string& key) {
                           put_polygons(key, {part.designed});
                           put_polygons(key, teeth);
                         },
                         [&] {
                           return OutlineCheck{
                               {without_hanging_corners(part.designed, teeth, o_.min_feature,
                                                        o_.tooth_width * o_.tooth_width)},
                               {}};
                         })
                         .polygons.front());
  }
  std::vector<Polygon2> thin_necks(const Polygon2& outline, bool mitred = false) const {
    if (outline.size() < 3) return {};
    return checked(
               mitred ? 'M' : 'N', [&](std::string& key) { put_polygons(key, {outline}); },
               [&] {
                 return OutlineCheck{thin_necks_drawn(outline, mitred), {}};
               })
        .polygons;
  }
  /// The opening grows back with mitred corners, which reach up to four times the offset: where
  /// that joins the eroded pieces again (fertility's triangle mesh in 3 mm plywood at 350 mm: a
  /// 3 x 4.8 mm tab on a neck 0.08 mm wide, found only by the auditor), the morphological
  /// opening decides instead (neck_cores()), each piece of its erosion grown back on
  /// its own. It is taken only there: the mitred erosion, inside the round one,
  /// falls in two first.
  std::vector<Polygon2> thin_necks_drawn(const Polygon2& outline, bool mitred) const {
    const double r = 0.5 * o_.min_feature;
    if (!(r > 0)) return {};
    std::vector<Polygon2> eroded;
    for (auto& c : polygon_offset({outline}, -r))
      if (polygon_area(c) > 0) eroded.push_back(std::move(c));
    if (eroded.size() < 2) return {};
    std::vector<Polygon2> opened;
    for (auto& c : polygon_offset(eroded, r))
      if (polygon_area(c) > 0) opened.push_back(std::move(c));
    if (opened.size() < 2) {
      if (mitred) return {};
      opened.clear();
      const std::vector<Polygon2> cores = neck_cores(outline, o_.min_feature);
      if (cores.size() < 2) return {};
      for (const Polygon2& core : cores)
        for (auto& c : polygon_offset_round({core}, r - kNeckSlack, kOpeningArc))
          if (polygon_area(c) > 0) opened.push_back(std::move(c));
    }
    std::vector<Polygon2> necks;
    for (auto& piece : polygon_difference({outline}, opened)) {
      if (!(polygon_area(piece) > 0)) continue;
      int touched = 0;
      for (const Polygon2& ring : opened) touched += touches(piece, ring) ? 1 : 0;
      if (touched >= 2) necks.push_back(std::move(piece));
    }
    return necks;
  }

  /// True when part \p p falls in two or more pieces under the mitred erosion by half the
  /// smallest feature and under the morphological one (as thin_necks_drawn()), whether or not
  /// a neck between them is found: the part is named where the pass could not mend it.
  bool splits_apart(int p) const { return splits_apart(out_.parts[p].designed); }
  bool splits_apart(const Polygon2& outline) const {
    const double r = 0.5 * o_.min_feature;
    if (outline.size() < 3 || !(r > 0)) return false;
    const OutlineCheck found = checked(
        'E', [&](std::string& key) { put_polygons(key, {outline}); },
        [&] {
          int eroded = 0;
          for (const auto& c : polygon_offset({outline}, -r)) eroded += polygon_area(c) > 0;
          const int cores = eroded > 1 ? round_cores(outline) : 0;
          return OutlineCheck{{}, {cores}};
        });
    return found.positions.front() > 1;
  }

  /// True when outline \p after (a part drawn with one joint changed) falls in more pieces than
  /// \p before near the change under an opening by half the smallest feature: a tooth that
  /// hangs on a neck narrower than that feature (it breaks off), or a slot that pinches its part
  /// through. Only the neighbourhood of the change is looked at (the opening there depends on the
  /// outline within a feature of it), so a neck elsewhere on the part, or one the change only
  /// splits, does not count, and a large part costs no more than a small one. A thin wedge
  /// between a tooth and another edge of its part joins two pieces that are joined anyway and
  /// does not count either (thin_necks() of the clipped outline would see two pieces there).
  bool adds_thin_neck(const Polygon2& after, const Polygon2& before) const {
    if (after.size() < 3 || !(o_.min_feature > 0)) return false;
    // The box of the vertices either outline has and the other lacks.
    const auto less = [](const Vec2& a, const Vec2& b) {
      return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    };
    Polygon2 sa = after, sb = before, changed;
    std::sort(sa.begin(), sa.end(), less);
    std::sort(sb.begin(), sb.end(), less);
    std::set_symmetric_difference(sa.begin(), sa.end(), sb.begin(), sb.end(),
                                  std::back_inserter(changed), less);
    if (changed.empty()) return false;
    Vec2 lo = changed.front(), hi = changed.front();
    for (const Vec2& v : changed) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    if (more_pieces(clipped(after, lo, hi), clipped(before, lo, hi))) return true;
    // Where the mitred corners join the pieces again, the round erosion of the whole outline,
    // as the final check has it (splits_apart()); only where asked (round_necks_: elsewhere a
    // strip corner so cut off by without_hanging_corners() is the better end).
    return round_necks_ && round_cores(after) > round_cores(before);
  }

  /// \p outline clipped to the box [lo, hi] grown by three smallest features: an opening by half
  /// that feature within a feature of [lo, hi] is the same on the clipped outline as on the whole.
  std::vector<Polygon2> clipped(const Polygon2& outline, Vec2 lo, Vec2 hi) const {
    if (outline.size() < 3) return {};
    const double g = 3 * o_.min_feature;
    lo -= Vec2(g, g), hi += Vec2(g, g);
    return polygon_intersection(outline, {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}});
  }

  /// How many pieces \p outline's round erosion by half the smallest feature less kNeckSlack
  /// leaves (neck_cores()).
  int round_cores(const Polygon2& outline) const {
    return outline.size() < 3 ? 0 : static_cast<int>(neck_cores(outline, o_.min_feature).size());
  }

  /// True when region \p after falls in more pieces than \p before under an opening by half
  /// the smallest feature (both clipped() to the same box).
  bool more_pieces(const std::vector<Polygon2>& after, const std::vector<Polygon2>& before) const {
    return opening(after).size() > opening(before).size();
  }

  /// The outer rings of \p region (disjoint simple polygons) opened by half the smallest
  /// feature: the pieces left where it is at least that wide (none if it is nowhere so wide).
  std::vector<Polygon2> opening(const std::vector<Polygon2>& region) const {
    const double r = 0.5 * o_.min_feature;
    if (region.empty() || !(r > 0)) return {};
    std::vector<Polygon2> opened;
    for (auto& c : polygon_offset(polygon_offset(region, -r), r))
      if (polygon_area(c) > 0) opened.push_back(std::move(c));
    return opened;
  }

  /// Thin necks (thin_necks) that joints made: the intervals whose tooth, slot or cut-back comes
  /// near a neck go plain on both parts (as plain_where_lost does for a part that fell apart),
  /// kept only where that mends the part and makes no part fall apart or gain a neck. Two
  /// passes (\p mitred): first by the mitred opening alone, kept where the part is left without
  /// a neck; then by thin_necks_drawn()'s morphological opening, for the necks the mitred one
  /// joined again, kept where the part has fewer necks and no part has one where it had none.
  /// (The morphological measure alone in one pass: asking it for none left kept no mend on the
  /// quad sphere's raw strips, 31 left pinched; asking it for fewer left horse_quad two pinches
  /// the mitred mends had taken.) Not in the resolve loop's drafts (stub_teeth false): a neck
  /// decides no critical region or part too small, and the final build has the passes (the
  /// demo's resolve stage 2.8-2.9 s before, 2.7 s with both passes). A border that so loses
  /// its last joint gets a tooth elsewhere where one fits
  /// (give_stubs_a_tooth(), which lets no tooth make a neck); where none does, it stays without:
  /// a tooth hanging on a neck narrower than the smallest feature breaks off (Spot's fine quad
  /// mesh had one on a 0.3 mm neck). A neck of the flattened strip itself stays (the auditor
  /// reports it).
  void widen_thin_necks(const std::vector<std::vector<std::array<double, 2>>>& forbidden,
                        bool mitred) {
    std::vector<int> all(out_.parts.size());
    for (std::size_t p = 0; p < all.size(); ++p) all[p] = static_cast<int>(p);
    std::vector<std::vector<Polygon2>> necks(all.size());
    for_each_of(all, [&](int p) { necks[p] = thin_necks(p, mitred); });
    for (int p : all) {
      if (necks[p].empty()) continue;
      Trial before(*this);
      // Twice where the first leaves the neck: the second time the borders left bare take no
      // tooth the round erosion parts, or stay bare where a corner holds them (the demo's part
      // 150: plain, its neck went, and a stub tooth given back made it again, just under 1 mm).
      bool plain_mends = false;
      bool mended = mend_neck(p, necks, before, forbidden, mitred, false, plain_mends);
      if (!mended && plain_mends)
        mended = mend_neck(p, necks, before, forbidden, mitred, true, plain_mends);
      // Last, where the last pass of run() would not cut the neck away as it is: as the second
      // try but with the part's own teeth within a tooth's width of the neck made plain, kept
      // only where the part is then left without a neck as that pass cuts it, without the small
      // corners that hang on a neck and hold no tooth (scripts/shapes.py's terrain at 350 mm: a
      // strip's wedge tip whose last tooth, its root 1.1 mm from the neck, hung on 0.23 mm; the
      // joints within a millimetre made plain left the tooth, so the neck stayed and the tooth
      // was cut to break off).
      if (!mended && !thin_necks(trimmed_outline(p), mitred).empty()) {
        bool unused = false;
        mend_neck(p, necks, before, forbidden, mitred, true, unused, true);
      }
    }
  }

  /// One try of widen_thin_necks() at part \p p: the joints near its necks made plain, the
  /// borders so left bare given a stub tooth again, kept where that is better (\p necks
  /// updated), else \p before put back. \p round: the second try, where no such tooth may be
  /// one the round erosion parts and every such border must get one or be a stub held at a
  /// corner (join_stubs_at_corners()). \p plain_mends (first try): whether making the joints
  /// plain alone had mended the neck, where that left a border bare. \p as_cut (the third
  /// try): the part's own teeth within a tooth's width of the necks are made plain (else every
  /// joint within a millimetre), and the parts judged on their outlines without their hanging
  /// corners (trimmed_outline()).
  bool mend_neck(int p, std::vector<std::vector<Polygon2>>& necks, Trial& before,
                 const std::vector<std::vector<std::array<double, 2>>>& forbidden, bool mitred,
                 bool round, bool& plain_mends, bool as_cut = false) {
    std::set<int> redo, bare;
    plain_near(p, necks[p], redo, as_cut ? o_.tooth_width : 1.0, as_cut);
    if (redo.empty()) return false;
    redraw(redo);
    for (std::size_t b = 0; b < out_.borders.size(); ++b)
      if (out_.borders[b].teeth == 0 && before.borders()[b].teeth > 0 &&
          (redo.contains(out_.borders[b].patches[0]) || redo.contains(out_.borders[b].patches[1])))
        bare.insert(static_cast<int>(b));
    if (!round && !bare.empty()) {
      const std::size_t left = thin_necks(p, mitred).size();
      plain_mends = mitred ? left == 0 : left < necks[p].size();
    }
    round_necks_ = round;
    if (!bare.empty()) give_stubs_a_tooth(forbidden, &bare);
    round_necks_ = false;
    std::map<int, std::vector<Polygon2>> after;
    for (std::size_t q = 0; q < out_.parts.size(); ++q)
      if (redo.contains(static_cast<int>(q)) || before.changed(static_cast<int>(q)))
        after[static_cast<int>(q)] = thin_necks(static_cast<int>(q), mitred);
    // The mitred pass: no neck left on it, none more on the others. The morphological one:
    // fewer on it, none more on the others, and none on any where it had none (by count
    // alone a part with a neck elsewhere may take a new one beside the joints made plain).
    const auto improves = [&](const std::map<int, std::vector<Polygon2>>& left_by_part) {
      const std::vector<Polygon2>& on_p = left_by_part.at(p);
      bool ok =
          !out_.parts[p].repaired &&
          (mitred ? on_p.empty() : on_p.size() < necks[p].size() && only_where(on_p, necks[p]));
      for (const auto& [q, left] : left_by_part)
        if (q != p && ok)
          ok = (!out_.parts[q].repaired || before.part(q).repaired) &&
               left.size() <= necks[q].size() && (mitred || only_where(left, necks[q]));
      return ok;
    };
    bool better = !as_cut && improves(after);
    // As cut (the third try): a small corner with no tooth in it that hangs on the neck goes in
    // the last pass of run(), and the neck with it. Kept only where that leaves the part no
    // neck at all, nor one its round erosion finds (as the run names them), and no more tails
    // or slits narrower than the smallest feature: its teeth made plain narrow it (Spot's
    // control mesh at 500 mm, part 245: a strip end 1 mm wide, one neck of two mended, left a
    // 0.9 mm tail where its tooth was).
    if (as_cut && !out_.parts[p].repaired) {
      std::map<int, std::vector<Polygon2>> trimmed;
      for (const auto& [q, left] : after)
        trimmed[q] = left.empty() ? left : thin_necks(trimmed_outline(q), mitred);
      const Polygon2 cut = trimmed_outline(p);
      const auto thin = [&](const Polygon2& outline) {
        return narrow_tails(outline, o_.min_feature).size() +
               narrow_slits(outline, o_.min_feature).size();
      };
      better = trimmed.at(p).empty() && !splits_apart(cut) &&
               thin(cut) <= thin(before.part(p).designed) && improves(trimmed);
      if (better) after = std::move(trimmed);
    }
    if (round && better) {
      // Each border so left bare has its tooth again, or is a stub its parts' joints at one
      // of its corners hold (spot_quadrangulated's 1.2 mm stubs beside parts 392 and 439,
      // whose only tooth made the neck).
      join_stubs_at_corners(out_, s_, bp_, kStubAtCorner * o_.tooth_width);
      for (int b : bare)
        better = better && (out_.borders[b].teeth > 0 || !out_.borders[b].joined_through.empty());
    }
    if (!better) {
      before.revert();
      return false;
    }
    for (auto& [q, left] : after) necks[q] = std::move(left);
    return true;
  }

  /// True when every neck of \p now lies where one of \p was did (within the smallest feature).
  bool only_where(const std::vector<Polygon2>& now, const std::vector<Polygon2>& was) const {
    if (now.empty()) return true;
    const std::vector<Polygon2> near = polygon_offset(was, o_.min_feature);
    for (const Polygon2& n : now) {
      bool found = false;
      for (const Polygon2& w : near)
        found = found || (polygon_area(w) > 0 && !polygon_intersection(n, w).empty());
      if (!found) return false;
    }
    return true;
  }

  /// The intervals of part \p p's joints whose stretch on it comes within \p reach of one of
  /// \p pieces [mm], made plain (\p own_teeth: only its own teeth, so that its mates only gain
  /// material); the parts on both sides go into \p changed.
  void plain_near(int p, const std::vector<Polygon2>& pieces, std::set<int>& changed,
                  double reach = 1.0, bool own_teeth = false) {
    if (pieces.empty()) return;
    const auto near = polygon_offset(pieces, reach);
    // The spans of the same drawing as the lost pieces; intervals another part has made plain
    // since are skipped by their owner.
    for (const JointSpan& sp : out_.parts[p].spans) {
      BorderJoint& b = out_.borders[sp.border];
      JointInterval& in = b.intervals[sp.interval];
      if (in.owner < 0 || (own_teeth && !sp.tooth)) continue;
      const double e = sp.offset;
      Polygon2 stretch = {sp.from, sp.to, sp.to + e * sp.normal, sp.from + e * sp.normal};
      if (std::abs(polygon_area(stretch)) < 1e-12) continue;
      make_counter_clockwise(stretch);
      bool touches = false;
      for (const Polygon2& n : near)
        if (polygon_area(n) > 0 && !polygon_intersection(stretch, n).empty()) touches = true;
      if (!touches) continue;
      make_plain(b, in);
      changed.insert(b.patches[0]);
      changed.insert(b.patches[1]);
    }
  }

  /// The outlines of \p changed parts (whose joints changed) drawn again, and of the parts
  /// whose teeth that let a cut-back bite into (plain cut-backs where slots were) and their mates.
  /// A part's outline depends on its own borders' intervals only, so no other part changes.
  void redraw(const std::set<int>& changed) {
    if (changed.empty()) return;
    std::set<int> parts = drop_bitten_teeth(changed);
    parts.insert(changed.begin(), changed.end());
    draw(parts);
  }

  /// The outlines of \p parts, drawn on as many threads as the machine has (each part's outline
  /// and lost pieces are its own).
  void draw(const std::set<int>& parts) {
    const std::vector<int> list(parts.begin(), parts.end());
    for_each_of(list, [&](int p) { out_.parts[p] = outline(p); });
  }

  /// work(p) for every p of \p list, spread over the machine's threads; \p work must touch
  /// only what belongs to p.
  template <class Work>
  static void for_each_of(const std::vector<int>& list, const Work& work) {
    for_each_index(static_cast<int>(list.size()), hardware_threads(),
                   [&](int i) { work(list[i]); });
  }

  /// Teeth that a cut-back of their own part bites into (at an acute corner the mitre of the
  /// next border reaches across this one) would no longer fill their slots: such intervals are
  /// made plain, on both parts, until no tooth is bitten. Only the parts in \p check are looked
  /// at (the others' intervals have not changed since they were); returns the parts whose
  /// intervals this changed.
  std::set<int> drop_bitten_teeth(std::set<int> check) {
    std::set<int> touched;
    for (int round = 0; round < 64 && !check.empty(); ++round) {
      const std::vector<int> list(check.begin(), check.end());
      std::vector<std::vector<std::pair<int, int>>> of(rings_.size());  // (border, interval)
      for_each_of(list, [&](int p) { of[p] = bitten_teeth(p); });
      std::set<int> next;
      for (int p : list)
        for (const auto& [border, interval] : of[p]) {
          make_plain(out_.borders[border], out_.borders[border].intervals[interval]);
          next.insert(out_.borders[border].patches[0]);
          next.insert(out_.borders[border].patches[1]);
        }
      touched.insert(next.begin(), next.end());
      check = std::move(next);
    }
    return touched;
  }

  /// Interval \p in of border \p b without its tooth (counted as blocked), if it had one.
  void make_plain(BorderJoint& b, JointInterval& in) {
    if (in.owner < 0) return;
    if (in.kind == JointKind::kTab) --b.tabs, --out_.tabs, out_.tab_length -= in.s1 - in.s0;
    in.owner = -1;
    in.kind = JointKind::kNone;
    --b.teeth, --out_.teeth, ++b.blocked;
    out_.toothed_length -= in.s1 - in.s0;
  }

  /// The leaning line between intervals j and j + 1 of border \p b, if both are tabs owned by
  /// different sides (docs/joints.md): the slope keeps each tab at least two thirds of its width
  /// at the root; the clearance is what the slope turns the out-of-plane overlap of the two
  /// tilted plates into, k (L (1 - cos f) + h/2 sin f) for the longer tip L and the sharper fold.
  std::optional<TabFlare> flare_between(int b, int j) const {
    const BorderJoint& border = out_.borders[b];
    if (j < 0 || j + 1 >= static_cast<int>(border.intervals.size())) return std::nullopt;
    const JointInterval &lo = border.intervals[j], &hi = border.intervals[j + 1];
    if (lo.kind != JointKind::kTab || hi.kind != JointKind::kTab || lo.owner < 0 || hi.owner < 0 ||
        lo.owner == hi.owner)
      return std::nullopt;
    TabFlare f;
    f.s = lo.s1;
    // The flared sides are drawn in the frame of one straight edge of the border line: no
    // corner of it within reach of the flare (the same arc lengths on both sides).
    const double reach = 0.5 * std::min(lo.s1 - lo.s0, hi.s1 - hi.s0);
    for (double at : pieces_[b].sides[0].s)
      if (std::abs(at - f.s) < reach) return std::nullopt;
    const double deepest =
        std::max({lo.offsets.tip, hi.offsets.tip, -lo.offsets.slot, -hi.offsets.slot});
    const double narrowest = std::min(lo.s1 - lo.s0, hi.s1 - hi.s0);
    f.slope = std::min(kTabFlare, narrowest / 6 / std::max(deepest, 1e-9));
    const double fold = std::max({lo.fold, hi.fold, pieces_[b].fold_at(f.s)});
    const double tip = std::max(lo.offsets.tip, hi.offsets.tip);
    f.clearance = f.slope * (tip * (1 - std::cos(fold)) + 0.5 * thickness_ * std::sin(fold));
    return f;
  }

  /// What outline() draws from, as bytes: the options and kerf width it uses, the body and
  /// teeth it adds, the cut-backs it takes away and the tooth regions it keeps (not the spans'
  /// border and interval numbers, which differ between calls).
  std::string outline_key(const Shapes& sh) const {
    std::string key = options_key('O');
    put_polygons(key, sh.add);
    put_polygons(key, sh.cut);
    std::vector<Polygon2> teeth;
    for (const JointSpan& sp : sh.spans)
      if (sp.tooth && sp.region.size() >= 3) teeth.push_back(sp.region);
    put_polygons(key, teeth);
    return key;
  }

  /// The start of a memo key: what it is for (\p kind) and the options every drawing and check
  /// reads.
  std::string options_key(char kind) const {
    std::string key(1, kind);
    for (double v : {o_.tooth_width, o_.min_depth, o_.min_feature, kerf_width_}) put(key, v);
    return key;
  }
  static void put(std::string& key, const auto& value) {
    key.append(reinterpret_cast<const char*>(&value), sizeof(value));
  }
  static void put_polygons(std::string& key, const std::vector<Polygon2>& polygons) {
    put(key, polygons.size());
    for (const Polygon2& poly : polygons) {
      put(key, poly.size());
      for (const Vec2& v : poly) put(key, v.x()), put(key, v.y());
    }
  }

  /// \p compute()'s result, or the memo's where the same check (\p kind, the options and what
  /// \p put_inputs appends to the key) was made before. Without a memo no key is built.
  OutlineCheck checked(char kind, const auto& put_inputs, const auto& compute) const {
    if (!memo_) return compute();
    std::string key = options_key(kind);
    put_inputs(key);
    if (auto hit = memo_->checks.find(key)) return std::move(*hit);
    OutlineCheck found = compute();
    memo_->checks.insert(key, found);
    return found;
  }

  PartOutline outline(int p) {
    if (trial_) trial_->touch(p);
    Shapes sh = shapes(p);
    std::string key;
    if (memo_) {
      key = outline_key(sh);
      if (auto hit = memo_->find(key)) {
        PartOutline part;
        part.spans = std::move(sh.spans);
        part.designed = std::move(hit->designed);
        part.cut = std::move(hit->cut);
        part.repaired = hit->repaired;
        lost_[p] = std::move(hit->lost);
        return part;
      }
    }
    PartOutline part = drawn_outline(p, sh);
    if (memo_) memo_->insert(std::move(key), {part.designed, part.cut, part.repaired, lost_[p]});
    return part;
  }

  /// The outline of part \p p drawn from its shapes \p sh; sets lost_[p].
  PartOutline drawn_outline(int p, Shapes& sh) {
    PartOutline part;
    part.spans = std::move(sh.spans);
    // The body with its teeth, without holes: where teeth close over a notch of the flattened
    // outline (a collapsed strip end), the notch is enclosed by the part's own material and no
    // mate can reach it; left open it would be a cavity the laser path around the part skips.
    std::vector<Polygon2> solid;
    for (auto& c : polygon_union(sh.add))
      if (polygon_area(c) > 0) solid.push_back(std::move(c));
    const auto pieces = polygon_difference(solid, sh.cut);
    // Slivers far smaller than a tooth (left where a tooth corner meets a cut-back wedge) are
    // dropped silently; a second piece of tooth size means the part fell apart.
    const double significant = 0.25 * o_.tooth_width * std::max(o_.min_depth, 0.1);
    int outer = 0;
    for (const auto& c : pieces) outer += polygon_area(c) > significant ? 1 : 0;
    const Polygon2 kept = largest_polygon(pieces);
    const auto left = without_thin_features(kept, part.spans);
    for (const auto& c : left) outer += polygon_area(c) > significant ? 1 : 0;
    part.repaired = outer != 2;  // one piece from the Booleans, one after the cleanup
    // What it lost, for plain_where_lost().
    std::vector<Polygon2>& lost = lost_[p];
    lost.clear();
    if (part.repaired) {
      const Polygon2 rest = largest_polygon(left);
      for (const auto* list : {&pieces, &left})
        for (const auto& c : *list)
          if (polygon_area(c) > significant && c != kept && c != rest) lost.push_back(c);
    }
    // Pinches closed: a cavity joined to the outside only through a slit of zero width (where a
    // widened slit stopped at a tooth) would be skipped by the laser path around the part. And
    // needles taken off: where a slot's cut-back and the wedge beside it nearly share a side,
    // the Booleans left needles of material 3 um at the base and 1.6 mm long (the capped
    // cylinder: three), which the kerf offset below grew into hairs as wide as the beam.
    const auto pinches_closed = [](const Polygon2& ring) {
      return largest_polygon(polygon_offset(polygon_offset({ring}, 1e-3), -1e-3));
    };
    set_outline(part, pinches_closed(largest_polygon(left)));
    // Looked at again as the laser cuts it: the part the path half a kerf outside leaves, with
    // notches narrower than the kerf filled (what the sheet auditor reads back). The test of a
    // tail is an opening whose mitred corners follow the outline's short edges, so a tail can
    // hide from it on the outline as designed and show on the outline as cut (demosthenes from
    // its triangles, 250 mm, 2 mm MDF, feature angle 65 deg: a spike 1.4 mm long, 0.6 mm wide
    // at its root, seen only where the path's offset merged two corners 0.04 mm apart).
    if (!(kerf_width_ > 0)) return part;
    const Polygon2 as_cut = largest_polygon(polygon_offset({part.cut}, -0.5 * kerf_width_));
    if (as_cut.size() < 3) return part;
    const auto again = without_thin_features(as_cut, part.spans);
    if (again.size() == 1 && again.front() == as_cut) return part;
    // What it finds there may be a tail, never a tooth: more tooth material than a sliver
    // taken and the outline as designed stays (the quad sphere's narrow strip near a pole,
    // in pieces before the resolve stage, lost a whole tooth 3 mm wide that way).
    double tooth_taken = 0;
    const auto teeth = tooth_regions(part.spans);
    for (const auto& gone : polygon_difference({as_cut}, again))
      for (const auto& tooth : teeth)
        for (const auto& c : polygon_intersection(gone, tooth)) tooth_taken += polygon_area(c);
    if (tooth_taken > 0.25 * o_.min_feature * o_.min_feature) return part;
    const Polygon2 rest = largest_polygon(again);
    for (const auto& c : again)
      if (polygon_area(c) > significant && c != rest) {
        part.repaired = true;
        lost.push_back(c);
      }
    set_outline(part, pinches_closed(rest));
    return part;
  }

  /// The tooth regions of \p spans, counter-clockwise.
  static std::vector<Polygon2> tooth_regions(const std::vector<JointSpan>& spans) {
    std::vector<Polygon2> teeth;
    for (const JointSpan& sp : spans)
      if (sp.tooth && sp.region.size() >= 3) {
        teeth.push_back(sp.region);
        make_counter_clockwise(teeth.back());
      }
    return teeth;
  }

  /// \p part's outline set to \p designed without needles, and the laser path half the kerf
  /// outside it.
  void set_outline(PartOutline& part, Polygon2 designed) const {
    part.designed = without_needles(std::move(designed), kNeedleWidth);
    part.cut = largest_polygon(polygon_offset({part.designed}, 0.5 * kerf_width_));
  }

  /// True when \p piece, taken away by an opening whose result is \p opened, joined two of its
  /// pieces, one of them no larger than a square tooth, and holds more than a square of the
  /// minimum feature width: a neck with a small corner hanging on it. Its vertices all lie near
  /// the rest (reaches_beyond() sees nothing), but what hangs on it breaks off. A neck between two
  /// large pieces is left: cut, the part would fall in two.
  bool neck(const Polygon2& piece, const std::vector<Polygon2>& opened) const {
    const double w = o_.min_feature;
    if (std::abs(polygon_area(piece)) <= w * w) return false;
    int touched = 0;
    double smallest = std::numeric_limits<double>::infinity();
    for (const Polygon2& ring : opened) {
      const double area = polygon_area(ring);
      if (area > 0 && touches(piece, ring)) ++touched, smallest = std::min(smallest, area);
    }
    return touched >= 2 && smallest <= o_.tooth_width * o_.tooth_width;
  }

  /// True when a vertex of \p piece lies on the boundary of \p ring (within a micrometre): a
  /// piece an opening took away that was joined to that ring.
  static bool touches(const Polygon2& piece, const Polygon2& ring) {
    constexpr double kTouch = 1e-3;
    const auto near = edges_near(piece, {&ring}, kTouch);
    for (const Vec2& v : piece)
      for (const auto& e : near)
        if (distance_to_segment(v, e[0], e[1]) < kTouch) return true;
    return false;
  }

  /// The outline without tails or slits narrower than JointOptions::min_feature (where a tooth
  /// corner meets a cut-back wedge, or two cut-backs nearly meet): such a tail breaks off or
  /// burns away, such a slit is a cut the laser cannot make. Both go by removing material, which
  /// can never collide with a neighbour: a tail is cut off, a slit widened. Teeth are kept, but
  /// for slivers of them (tooth_slivers).
  /// A feature is what an opening (tails) or closing (slits) by half the minimum width changes
  /// and that reaches more than half that width from the rest: the rounding of a corner of 60
  /// degrees or more, or a low wide bump such as a shallow tooth, is no feature.
  /// Returns the pieces left (more than one: the part fell apart).
  std::vector<Polygon2> without_thin_features(const Polygon2& outline,
                                              const std::vector<JointSpan>& spans) const {
    const double r = 0.5 * o_.min_feature;
    if (outline.size() < 3 || !(r > 0)) return {outline};
    const auto opened = polygon_offset(polygon_offset({outline}, -r), r);
    if (opened.empty()) return {outline};  // narrower than a feature everywhere: reported as such
    const std::vector<Polygon2> teeth =
        teeth_kept_by_opening(outline, opened, tooth_regions(spans));
    // Tails: of what the opening takes away (\p taken), the features but for tooth material.
    auto tails = [&](const std::vector<Polygon2>& taken,
                     const std::vector<Polygon2>& opened_shape) {
      std::vector<Polygon2> out;
      for (const auto& piece : taken) {
        if (!reaches_beyond(piece, opened_shape, r) && !neck(piece, opened_shape)) continue;
        for (auto& rest :
             teeth.empty() ? std::vector<Polygon2>{piece} : polygon_difference({piece}, teeth))
          out.push_back(std::move(rest));
      }
      return out;
    };
    // What goes of \p shape, given its opening \p opened_shape: the tails, and a tooth's slivers
    // (tooth_slivers).
    auto thin_bits = [&](const Polygon2& shape, const std::vector<Polygon2>& opened_shape) {
      const std::vector<Polygon2> taken = polygon_difference({shape}, opened_shape);
      std::vector<Polygon2> out = tails(taken, opened_shape);
      for (auto& sliver : tooth_slivers(taken, opened_shape, teeth, o_.min_feature))
        out.push_back(std::move(sliver));
      return out;
    };
    std::vector<Polygon2> remove = thin_bits(outline, opened);
    // Slits: what the closing would fill, widened to the minimum width instead (never into a
    // tooth: the slot it goes into is cut to its width).
    const std::vector<Polygon2> wide =
        slit_widenings(outline, teeth, o_.min_feature, o_.tooth_width * o_.tooth_width);
    remove.insert(remove.end(), wide.begin(), wide.end());
    const bool widened = !wide.empty();
    if (remove.empty()) return {outline};
    std::vector<Polygon2> left = cut_away({outline}, std::move(remove));
    if (left.empty()) return {outline};
    if (!widened) return left;
    // Widened by what it lacked on average, a slit that tapers to its end can stay narrower
    // than the smallest feature there (demosthenes from its triangles at 250 mm in 2 mm MDF: a
    // notch 4.4 mm deep, 0.79 mm wide at its end, which the auditor found): widened again, at
    // most twice more, until none is left.
    for (int again = 0; again < 2; ++again) {
      std::vector<Polygon2> more;
      for (const Polygon2& piece : left)
        for (auto& w :
             slit_widenings(piece, teeth, o_.min_feature, o_.tooth_width * o_.tooth_width))
          more.push_back(std::move(w));
      if (more.empty()) break;
      std::vector<Polygon2> next = cut_away(left, std::move(more));
      if (next.empty()) break;
      left = std::move(next);
    }
    // A widened slit narrows the material beside it: what became a tail there goes too, and
    // so does a sliver of a tooth there (demosthenes from its triangles at 500 mm: a slit
    // widened beside a tooth 0.56 mm deep at a part's corner left it overhanging a stalk 1 mm
    // wide, its overhang under 1 mm thick).
    std::vector<Polygon2> final_pieces;
    for (const Polygon2& piece : left) {
      const auto opened_piece = polygon_offset(polygon_offset({piece}, -r), r);
      auto more = opened_piece.empty() ? std::vector<Polygon2>{} : thin_bits(piece, opened_piece);
      if (more.empty()) {
        final_pieces.push_back(piece);
        continue;
      }
      for (auto& poly : more) make_counter_clockwise(poly);
      for (auto& c : polygon_difference({piece}, more))
        if (polygon_area(c) > 0) final_pieces.push_back(std::move(c));
    }
    return final_pieces.empty() ? left : final_pieces;
  }
};

}  // namespace

bool reaches_beyond(const Polygon2& piece, const std::vector<Polygon2>& region, double r,
                    bool along_edges) {
  std::vector<const Polygon2*> rings;
  for (const Polygon2& ring : region) rings.push_back(&ring);
  const auto near = edges_near(piece, rings, r);
  const auto beyond = [&](const Vec2& v) {
    return std::none_of(near.begin(), near.end(),
                        [&](const auto& e) { return distance_to_segment(v, e[0], e[1]) <= r; });
  };
  // Points r/4 apart along the edges: no stretch reaching r/8 farther than the points found is
  // missed.
  const double step = 0.25 * r;
  for (std::size_t i = 0; i < piece.size(); ++i) {
    const Vec2 &a = piece[i], &b = piece[(i + 1) % piece.size()];
    const int n =
        along_edges ? static_cast<int>(std::clamp(std::ceil((b - a).norm() / step), 1.0, 1e4)) : 1;
    for (int k = 0; k < n; ++k)
      if (beyond(a + (static_cast<double>(k) / n) * (b - a))) return true;
  }
  return false;
}

const char* to_string(JointKind kind) {
  switch (kind) {
    case JointKind::kBox:
      return "box";
    case JointKind::kTab:
      return "tab";
    case JointKind::kGlue:
      return "glue";
    case JointKind::kNone:
      break;
  }
  return "none";
}

std::string BorderJoint::kind() const {
  bool box = false, tab = false;
  for (const JointInterval& in : intervals)
    box |= in.kind == JointKind::kBox, tab |= in.kind == JointKind::kTab;
  if (box || tab || glue > 0) return box && tab ? "box+tab" : box ? "box" : tab ? "tab" : "glue";
  return joined_through.empty() ? "none" : "corner";
}

std::vector<Polygon2> teeth_kept_by_opening(const Polygon2& outline,
                                            const std::vector<Polygon2>& opened,
                                            std::vector<Polygon2> teeth) {
  constexpr double kWhole = 1e-3;  // share of a tooth's material the opening may keep [1]
  std::vector<Polygon2> kept;
  for (Polygon2& tooth : teeth) {
    // Most teeth: the opening keeps their middle. A point test, not two Booleans with the whole
    // outline per tooth (those made the demo's joints stage 5 times slower).
    Vec2 middle = Vec2::Zero();
    for (const Vec2& v : tooth) middle += v;
    if (!tooth.empty() && inside(middle / static_cast<double>(tooth.size()), opened)) {
      kept.push_back(std::move(tooth));
      continue;
    }
    const std::vector<Polygon2> held = polygon_intersection(outline, tooth);
    double in_outline = 0, taken = 0;
    for (const Polygon2& c : held) in_outline += polygon_area(c);
    for (const Polygon2& c : polygon_difference(held, opened)) taken += polygon_area(c);
    if (in_outline > 0 && taken >= (1 - kWhole) * in_outline) continue;
    kept.push_back(std::move(tooth));
  }
  return kept;
}

std::vector<Polygon2> tooth_slivers(const std::vector<Polygon2>& taken,
                                    const std::vector<Polygon2>& opened,
                                    const std::vector<Polygon2>& teeth, double min_feature) {
  std::vector<Polygon2> out;
  if (teeth.empty()) return out;
  const double w = min_feature;
  for (const auto& piece : taken) {
    const bool feature = std::abs(polygon_area(piece)) > w * w || reaches_beyond(piece, opened, w);
    for (const auto& tooth : teeth)
      for (auto& c : polygon_intersection(piece, tooth)) {
        if (!(polygon_area(c) > 0)) continue;
        // Nearer the rest, only tooth material nowhere thicker than kSliverThickness of the
        // feature that hangs more than half a feature from the rest: such a sliver breaks off
        // or burns away however short it is.
        if (feature || (reaches_beyond(c, opened, 0.5 * w) &&
                        polygon_offset({c}, -0.5 * kSliverThickness * w).empty()))
          out.push_back(std::move(c));
      }
  }
  return out;
}

namespace {

/// True when every wall of \p gap (a slit's closing, counter-clockwise: its edges on
/// \p outline, not its mouth) has tooth material beside it: a point a micrometre into the
/// material from each wall's middle lies in one of \p teeth.
bool walls_all_teeth(const Polygon2& gap, const Polygon2& outline,
                     const std::vector<Polygon2>& teeth) {
  constexpr double kOn = 1e-6, kInto = 1e-3;  // [mm]
  bool any = false;
  for (std::size_t i = 0; i < gap.size(); ++i) {
    const Vec2 &a = gap[i], &b = gap[(i + 1) % gap.size()];
    const double len = (b - a).norm();
    if (len < 10 * kInto) continue;
    const Vec2 mid = 0.5 * (a + b);
    if (distance_to_boundary(mid, outline) > kOn) continue;     // the mouth
    const Vec2 out = Vec2(b.y() - a.y(), a.x() - b.x()) / len;  // right of a ccw edge: outside
    if (!inside(mid + kInto * out, teeth)) return false;
    any = true;
  }
  return any;
}

}  // namespace

std::vector<Polygon2> slit_widenings(const Polygon2& outline, const std::vector<Polygon2>& teeth,
                                     double min_feature, double split_area) {
  const double r = 0.5 * min_feature;
  std::vector<Polygon2> out;
  if (outline.size() < 3 || !(r > 0)) return out;
  const Closing closing = closing_of(outline, r);
  const std::vector<Polygon2>& closed = closing.closed;
  for (const auto& gap : closing.gaps) {
    // Its edges looked along too: a stretch that stayed under the width between a step where
    // it was widened and where it widens by itself has its corners all at its ends, by the rest
    // (the cone of scripts/shapes.py at 350 mm in plywood3: 0.996 mm over 2 mm, which the
    // auditor found).
    if (!reaches_beyond(gap, closed, r, true)) continue;
    // Widened by what it lacks: a slit of mean width w (area over half its perimeter) grows
    // by r - w/2 on each side, its end by as much; wider cuts would eat into thin parts.
    double perimeter = 0;
    for (std::size_t i = 0; i < gap.size(); ++i)
      perimeter += (gap[(i + 1) % gap.size()] - gap[i]).norm();
    const double w = 2 * std::abs(polygon_area(gap)) / std::max(perimeter, 1e-9);
    const double grow = std::clamp(r - 0.5 * w, 0.1 * r, r);
    auto widened_by = [&](double d) {
      auto wide = polygon_offset({gap}, d);
      for (auto& poly : wide) make_counter_clockwise(poly);
      return wide;
    };
    auto wide = widened_by(grow);
    if (!teeth.empty()) {
      // A tooth on one side keeps its width: the other side then gives all the slit lacks
      // (grown by half of it on each side, a slit beside a stub tooth stayed 0.7 mm wide).
      auto kept = polygon_difference(wide, teeth);
      double before = 0, after = 0;
      for (const auto& poly : wide) before += polygon_area(poly);
      for (const auto& poly : kept) after += polygon_area(poly);
      if (after < before - 1e-6) kept = polygon_difference(widened_by(2 * grow), teeth);
      // Teeth on both sides (two borders' teeth meeting at a part's corner in a V): nothing
      // but tooth to take, so the teeth give it, each losing a wedge of its flank at the tip;
      // it still fills its mate's slot, less that wedge (demosthenes from its triangles at
      // 500 mm: a V 1.25 mm deep, 0.6 mm wide at its mouth, between two teeth). A V lacks
      // the whole width at its tip, whatever its mean width: each side gives half of it. The
      // part's body beyond the teeth is not cut into, and no tooth gives more than a quarter
      // of itself (a shallow tooth whose top faces the slit would go whole: the slit stays).
      if (walls_all_teeth(gap, outline, teeth)) {
        std::vector<Polygon2> into;
        bool small = true;
        const auto widened = widened_by(r);
        for (const auto& tooth : teeth) {
          double taken = 0, held = 0;
          for (const auto& poly : widened)
            for (auto& in : polygon_intersection(poly, tooth)) {
              if (!(polygon_area(in) > 0)) continue;
              for (const auto& material : polygon_intersection(in, outline))
                taken += polygon_area(material);
              into.push_back(std::move(in));
            }
          if (taken == 0) continue;
          for (const auto& in : polygon_intersection(outline, tooth)) held += polygon_area(in);
          small = small && taken <= 0.25 * held;
        }
        if (small) kept = std::move(into);
      }
      wide = std::move(kept);
    }
    // A widening that cuts the part in two is not made: the slit stays (narrow_slits() names
    // it) instead of a part that falls apart there (fandisk at 250 mm in MDF: part 111 lost 390
    // mm^2 and four joints at a slit found along its edges). One that cuts off a piece no
    // larger than a square tooth is made: what hung there was a tail (as neck() has it).
    int pieces = 0;
    for (const auto& piece : cut_away({outline}, wide))
      pieces += polygon_area(piece) > split_area ? 1 : 0;
    if (pieces > 1) continue;
    out.insert(out.end(), wide.begin(), wide.end());
  }
  return out;
}

namespace {
/// Of \p pieces (what an opening or closing by half \p min_feature [mm] changed, next to the
/// opened or closed \p rest), those that are features: more than a square of that width, or
/// reaching farther than it from the rest along their edges.
std::vector<Polygon2> features_among(std::vector<Polygon2> pieces,
                                     const std::vector<Polygon2>& rest, double min_feature) {
  std::vector<Polygon2> out;
  for (auto& piece : pieces)
    if (std::abs(polygon_area(piece)) > min_feature * min_feature ||
        reaches_beyond(piece, rest, min_feature, true))
      out.push_back(std::move(piece));
  return out;
}
}  // namespace

std::vector<Polygon2> narrow_tails(const Polygon2& outline, double min_feature) {
  const double r = 0.5 * min_feature - kAtTheLimit;
  if (outline.size() < 3 || !(r > 0)) return {};
  const auto opened = polygon_offset(polygon_offset({outline}, -r), r);
  return features_among(polygon_difference({outline}, opened), opened, min_feature);
}

std::vector<Polygon2> narrow_slits(const Polygon2& outline, double min_feature) {
  const double r = 0.5 * min_feature - kAtTheLimit;
  if (outline.size() < 3 || !(r > 0)) return {};
  Closing closing = closing_of(outline, r);
  return features_among(std::move(closing.gaps), closing.closed, min_feature);
}

std::vector<Polygon2> narrow_slits_as_cut(const Polygon2& path, double kerf_width,
                                          double min_feature) {
  if (!(kerf_width > 0)) return narrow_slits(path, min_feature);
  Polygon2 ring = path;
  if (polygon_area(ring) < 0) std::reverse(ring.begin(), ring.end());
  const Polygon2 as_cut = largest_polygon(polygon_offset({ring}, -0.5 * kerf_width));
  return as_cut.size() < 3 ? std::vector<Polygon2>{} : narrow_slits(as_cut, min_feature);
}

Polygon2 without_hanging_corners(const Polygon2& outline, const std::vector<Polygon2>& teeth,
                                 double min_feature, double largest) {
  const double r = 0.5 * min_feature - kNeckSlack;
  if (outline.size() < 3 || !(r > 0)) return outline;
  std::vector<Polygon2> eroded;
  for (auto& c : polygon_offset({outline}, -r))
    if (polygon_area(c) > 1e-6) eroded.push_back(std::move(c));
  if (eroded.size() < 2) return outline;
  std::vector<Polygon2> rest;
  std::vector<bool> small(eroded.size());
  for (std::size_t i = 0; i < eroded.size(); ++i) {
    auto grown = polygon_offset({eroded[i]}, r);
    double area = 0;
    for (const auto& g : grown) area += polygon_area(g);
    small[i] = area <= largest;
    if (!small[i]) rest.insert(rest.end(), grown.begin(), grown.end());
  }
  if (rest.empty()) return outline;
  Polygon2 kept = outline;
  for (auto& piece : polygon_difference({outline}, rest)) {
    if (!(polygon_area(piece) > 0) || polygon_area(piece) > largest) continue;
    bool holds = false;  // a small component's disc centres lie in it
    for (std::size_t i = 0; i < eroded.size() && !holds; ++i)
      if (small[i])
        for (const Vec2& v : eroded[i])
          if (inside(v, piece)) holds = true;
    if (!holds) continue;
    // A piece with any of a tooth in it (more than 0.01 mm2) stays, neck and all: cut, the
    // tooth would no longer fill its mate's slot. Making such joints plain is thin_necks()'
    // business.
    bool tooth = false;
    for (const Polygon2& t : teeth) {
      if (common_area(t, piece) > 0.01) tooth = true;
    }
    if (tooth) continue;
    // Only what hangs at one end goes: a piece between two larger ones is a link of the part,
    // and taking it would cut the part in two.
    make_counter_clockwise(piece);
    std::vector<Polygon2> left;
    for (auto& c : polygon_difference({kept}, polygon_offset({piece}, 1e-4)))
      if (polygon_area(c) > 1e-3) left.push_back(std::move(c));
    if (left.size() == 1) kept = std::move(left.front());
  }
  return kept.size() >= 3 ? kept : outline;
}

std::vector<Polygon2> neck_cores(const Polygon2& outline, double min_feature) {
  std::vector<Polygon2> cores;
  for (auto& c : polygon_offset_round({outline}, -(0.5 * min_feature - kNeckSlack), kOpeningArc))
    if (polygon_area(c) > 0) cores.push_back(std::move(c));
  return cores;
}

double plain_offset(double fold, double thickness) {
  return -0.5 * thickness * std::tan(0.5 * std::min(std::abs(fold), kMaxJointFold));
}

std::size_t OutlineCheck::bytes() const {
  std::size_t n = sizeof(OutlineCheck) + sizeof(int) * positions.size();
  for (const Polygon2& poly : polygons) n += sizeof(Polygon2) + sizeof(Vec2) * poly.size();
  return n;
}

std::size_t OutlineDrawing::bytes() const {
  std::size_t n = sizeof(OutlineDrawing) + sizeof(Vec2) * (designed.size() + cut.size());
  for (const Polygon2& piece : lost) n += sizeof(Vec2) * piece.size();
  return n;
}

void check_joint_options(const Material& material, const Machine& machine,
                         const JointOptions& options) {
  const double h = material.thickness;
  if (!(h >= 0)) throw InvalidInput("--thickness must be >= 0 mm");
  // A laser cutter cuts MDF and plywood up to about this thick; a 40 mm sheet on Spot at 250 mm
  // ran for 107 s, inverted 54 quads in the flattening and ended as if fine.
  if (!(h <= kMaxThickness)) {
    std::ostringstream os;
    os << "--thickness " << h << " mm is thicker than a laser cuts MDF or plywood (at most "
       << kMaxThickness << " mm)";
    throw InvalidInput(os.str());
  }
  if (!(options.protrusion >= 0)) throw InvalidInput("--protrusion must be >= 0 mm");
  // A tooth narrower than 1 mm breaks off when glued (and a micrometre one asks for a billion
  // intervals on an ordinary model).
  if (!(options.tooth_width >= 1.0) || !std::isfinite(options.tooth_width))
    throw InvalidInput("--tooth-width must be >= 1 mm, got " + std::to_string(options.tooth_width));
  // Wider than any border piece of a model: no border got a tooth (--tooth-width 1e6 on Spot:
  // 240 borders without a joint, 68 parts in pieces, and the run ended as if fine).
  if (options.tooth_width > 100)
    throw InvalidInput("--tooth-width must be at most 100 mm, got " +
                       std::to_string(options.tooth_width));
  if (!(options.min_depth >= 0)) throw InvalidInput("--min-tooth-depth must be >= 0 mm");
  if (!(machine.kerf_width >= 0)) throw InvalidInput("--kerf-width must be >= 0 mm");
  if (!(options.max_tip > 0)) throw InvalidInput("joints: max_tip must be > 0 mm");
  if (!(options.min_part_area >= 0)) throw InvalidInput("joints: min_part_area must be >= 0 mm^2");
  if (!(options.min_part_width >= 0)) throw InvalidInput("joints: min_part_width must be >= 0 mm");
  if (!(options.tab_misfit >= 0) || !std::isfinite(options.tab_misfit))
    throw InvalidInput("--tab-misfit must be >= 0 mm");
  if (!(options.glue_tab >= 0) || !std::isfinite(options.glue_tab))
    throw InvalidInput("--glue-tab must be >= 0 mm");
  if (h == 0) return;  // paper: glue tabs, no teeth
  // Sticking out of the shell, or leaving the mate's faces, by more than the sheet is thick, a
  // tooth or tab is no longer inside the shape (--protrusion 1e6 on Spot: 36 borders without a
  // joint, and the teeth stood out of the surface, with exit 0).
  for (const auto& [name, what, value] :
       {std::tuple{"--protrusion", "box tooth", options.protrusion},
        std::tuple{"--tab-misfit", "dovetail tab", options.tab_misfit}})
    if (value > h) {
      std::ostringstream os;
      os << name << " " << value << " mm lets a " << what
         << " stand out of the surface by more than the " << h << " mm sheet is thick; at most "
         << h << " mm";
      throw InvalidInput(os.str());
    }
  // Deeper than the deepest box tooth of any fold (the sharpest one joined, kMaxJointFold): no
  // border gets a tooth (--min-tooth-depth 1e6 on Spot: 443 borders without a joint, exit 0).
  const ToothOffsets deepest = tooth_offsets(kMaxJointFold, h, options.protrusion, options.max_tip);
  if (options.min_depth > deepest.tip - deepest.slot) {
    std::ostringstream os;
    os.precision(4);
    os << "--min-tooth-depth " << options.min_depth << " mm is deeper than any box tooth in a " << h
       << " mm sheet (at most " << deepest.tip - deepest.slot << " mm, at a "
       << std::lround(kMaxJointFold * 180 / M_PI) << " degree fold): no border would get one";
    throw InvalidInput(os.str());
  }
}

Joints make_joints(const Strips& strips, const Flattening& flat, const Material& material,
                   const Machine& machine, const JointOptions& options, OutlineMemo* memo) {
  check_joint_options(material, machine, options);
  if (flat.patches.size() != strips.patches.size())
    throw InvalidInput("joints: flattening does not belong to these strips");
  if (material.thickness == 0 && options.glue_tab > 0)
    return make_glue_tabs(strips, flat, machine, options);
  return Builder(strips, flat, material.thickness, machine.kerf_width, options, memo).run();
}

}  // namespace kerfab
