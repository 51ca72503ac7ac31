#include "kerfab/joints/glue_tabs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "kerfab/core/geometry2d.h"
#include "kerfab/joints/border_pieces.h"
#include "kerfab/joints/corners.h"

namespace kerfab {
namespace {

using border::Piece;
using border::Ring;
using border::Side;

/// The ends of a stub's glue tab: square to the border line [rad] (glue_tabs.h, kGlueTabTaper).
constexpr double kStubTaper = M_PI / 2;

// Tabs reach this far across their root into the part, so that tab and body overlap instead of
// merely touching after rounding [mm].
constexpr double kOverlap = 1e-3;

/// The share of the glued length a placement with the bare stubs first may give up and still
/// be kept [-].
constexpr double kStubGlueLoss = 0.02;

/// The rounded closing of an outline (without_slits): its arcs within this of a circle [mm].
constexpr double kRoundTolerance = 0.01;
/// A piece of that closing is a slot's end, not a corner's fillet, where it holds more than
/// this many squares of the closing's radius [-]: a concave corner of 90 degrees or more is
/// filled by at most (1 - pi/4) = 0.215 of it.
constexpr double kSlotEnd = 0.25;
/// Pieces of an outline narrower than this all round are hairs, not pieces [mm].
constexpr double kHair = 0.01;
/// Rounds of taking out the fills that close a pocket into a hole (without_slits) [-].
constexpr int kSealingRounds = 3;

Polygon2 ccw(Polygon2 p) {
  make_counter_clockwise(p);
  return p;
}

double total_area(const std::vector<Polygon2>& polys) {
  double a = 0;
  for (const auto& c : polys) a += polygon_area(c);
  return a;
}

/// p -> R p + t, a rotation and a translation.
struct Rigid {
  double c = 1, s = 0;
  Vec2 t{0, 0};
  Vec2 turn(const Vec2& d) const { return {c * d.x() - s * d.y(), s * d.x() + c * d.y()}; }
  Vec2 apply(const Vec2& p) const { return turn(p) + t; }
  Vec2 inverse(const Vec2& q) const {
    const Vec2 d = q - t;
    return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
  }
  Polygon2 apply(const Polygon2& poly) const {
    Polygon2 out;
    for (const Vec2& p : poly) out.push_back(apply(p));
    return out;
  }
  Polygon2 inverse(const Polygon2& poly) const {
    Polygon2 out;
    for (const Vec2& p : poly) out.push_back(inverse(p));
    return out;
  }
};

/// The rotation and translation that best maps points \p a onto \p b (least squares).
Rigid fit_rigid(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  Vec2 ca(0, 0), cb(0, 0);
  for (std::size_t i = 0; i < a.size(); ++i) ca += a[i], cb += b[i];
  ca /= static_cast<double>(a.size());
  cb /= static_cast<double>(b.size());
  double dot = 0, cross = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec2 p = a[i] - ca, q = b[i] - cb;
    dot += p.dot(q);
    cross += p.x() * q.y() - p.y() * q.x();
  }
  const double angle = std::atan2(cross, dot);
  Rigid r{std::cos(angle), std::sin(angle), {0, 0}};
  r.t = cb - (r.apply(ca) - r.t);
  return r;
}

/// How far the ray from \p from (a point on the outline of \p poly) along unit \p dir runs
/// inside \p poly: where it first leaves it more than 0.5 mm out (nearer, it may still be
/// crossing the wiggles of the outline it starts on) [mm]; 0 if it never enters.
double depth(const Polygon2& poly, const Vec2& from, const Vec2& dir) {
  const Vec2 start = from - 0.5 * dir;
  std::vector<double> crossings;  // along the ray from start
  bool inside = false;            // start's even-odd state
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], e = poly[(i + 1) % poly.size()] - a;
    const Vec2 b = a + e;
    if ((a.y() > start.y()) != (b.y() > start.y()) &&
        start.x() < a.x() + (start.y() - a.y()) / (b.y() - a.y()) * e.x())
      inside = !inside;
    const double den = dir.x() * e.y() - dir.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Vec2 w = a - start;
    const double t = (w.x() * e.y() - w.y() * e.x()) / den;    // along the ray
    const double u = (w.x() * dir.y() - w.y() * dir.x()) / den;  // along the edge
    if (t > 0 && u >= 0 && u < 1) crossings.push_back(t);
  }
  std::sort(crossings.begin(), crossings.end());
  for (double t : crossings) {
    inside = !inside;
    if (!inside && t > 1.0) return t - 0.5;
  }
  return 0;
}

/// Where arc length s lies on one side of a border, in its part's plane.
struct SidePoint {
  Vec2 point{0, 0};
  Vec2 normal{0, 0};  // outward
  Vec2 dir{0, 0};     // toward growing s
  int ring_edge = -1;
};

/// One glue tab as placed.
struct Tab {
  Polygon2 region;   // in its part's frame
  Polygon2 under;    // the same in the frame of the part it is glued under
  double s0 = 0, s1 = 0;  // its root along the border [mm]
  double height = 0;
};

class GlueBuilder {
 public:
  /// \p bp: the border pieces of \p s and \p f. \p first: borders to place before all others
  /// (in this order). \p square_stubs: stretches too short to halve may get a tab with square
  /// ends where a leaning one does not fit.
  GlueBuilder(const Strips& s, const Flattening& f, const border::Pieces& bp,
              const Machine& machine, const JointOptions& o, std::vector<int> first = {},
              bool square_stubs = false)
      : s_(s),
        f_(f),
        kerf_width_(machine.kerf_width),
        o_(o),
        bp_(bp),
        first_(std::move(first)),
        square_stubs_(square_stubs) {}

  Joints run() {
    const std::size_t parts = bp_.rings.size();
    for (const Ring& ring : bp_.rings) {
      body_.push_back(ccw(ring.start));
      inner_.push_back(polygon_offset({body_.back()}, -2 * kOverlap));
      std::vector<Polygon2> room;
      for (auto& r : polygon_offset({body_.back()}, -kGlueTabGap))
        if (polygon_area(r) > 0) room.push_back(std::move(r));
      room_.push_back(std::move(room));
    }
    own_.resize(parts);
    clear_.resize(parts);
    under_.resize(parts);
    spans_.resize(parts);
    folds_.resize(parts);
    out_.borders.resize(bp_.pieces.size());
    out_.flares.resize(bp_.pieces.size());
    // After the borders asked for first: long borders first, they hold the model together,
    // and get their tabs before short borders' tabs take the room at the corners.
    std::vector<char> early(bp_.pieces.size(), 0);
    for (int i : first_) early[i] = 1;
    std::vector<int> rest;
    for (int i = 0; i < static_cast<int>(bp_.pieces.size()); ++i)
      if (!early[i]) rest.push_back(i);
    std::stable_sort(rest.begin(), rest.end(),
                     [&](int a, int b) { return bp_.pieces[a].length > bp_.pieces[b].length; });
    for (int i : first_) place(i);
    for (int i : rest) place(i);
    for (std::size_t p = 0; p < parts; ++p) out_.parts.push_back(outline(static_cast<int>(p)));
    for (const BorderJoint& b : out_.borders) {
      out_.border_length += b.length;
      out_.borders_without_joint += b.glue == 0 ? 1 : 0;
    }
    return std::move(out_);
  }

 private:
  const Strips& s_;
  const Flattening& f_;
  const double kerf_width_;
  const JointOptions& o_;
  const border::Pieces& bp_;
  const std::vector<int> first_;
  const bool square_stubs_;
  std::vector<Polygon2> body_;                // per part: its flattened outline
  std::vector<std::vector<Polygon2>> inner_;  // per part: the body 2 um in (a tab's overlap)
  std::vector<std::vector<Polygon2>> room_;   // per part: the body kGlueTabGap in
  std::vector<std::vector<Polygon2>> own_;    // per part: its tabs, in its frame
  std::vector<std::vector<Polygon2>> clear_;  // per part: its tabs grown by kGlueTabGap (kept
                                              // with own_, not grown again per candidate)
  std::vector<std::vector<Polygon2>> under_;  // per part: tabs glued under it, in its frame
  std::vector<std::vector<JointSpan>> spans_;
  std::vector<std::vector<FoldLine>> folds_;
  Joints out_;

  SidePoint at(const Side& side, double s) const {
    const Ring& ring = bp_.rings[side.patch];
    const int j = side.edge_at(s);
    const double len = side.s[j + 1] - side.s[j];
    const double t = len > 0 ? std::clamp((s - side.s[j]) / len, 0.0, 1.0) : 0.5;
    const int k = side.ring_edges[j];
    Vec2 a = ring.start[k], b = ring.end[k];
    if (side.reversed) std::swap(a, b);
    const Vec2 d = b - a;
    return {a + t * d, ring.normal[k], d.norm() > 0 ? Vec2(d.normalized()) : Vec2(0, 0), k};
  }

  /// Arc lengths of the side's polyline from s0 to s1: the ends and the vertices between.
  std::vector<double> stations(const Side& side, double s0, double s1) const {
    std::vector<double> ss = {s0};
    for (double v : side.s)
      if (v > s0 + 1e-9 && v < s1 - 1e-9) ss.push_back(v);
    ss.push_back(s1);
    return ss;
  }

  Vec3 face_centre(int sub_quad) const {
    Vec3 c(0, 0, 0);
    for (int v : s_.faces[sub_quad]) c += s_.vertices[v];
    return c / 4.0;
  }

  /// Signed fold of the border at s, seen from side \p si: > 0 where the surface is convex
  /// (the other part falls away below this part's plane: a mountain fold from outside).
  double signed_fold(const Piece& piece, int si, double s) const {
    const Side &side = piece.sides[si], &mate = piece.sides[1 - si];
    const double f = piece.fold_at(s);
    const int k = at(side, s).ring_edge, km = at(mate, s).ring_edge;
    const Vec3 own = face_centre(bp_.rings[side.patch].edges[k].sub_quad);
    const Vec3 other = face_centre(bp_.rings[mate.patch].edges[km].sub_quad);
    return side.normal_at(s).dot(other - own) < 0 ? f : -f;
  }

  /// The region beyond the border line of side \p si of piece \p i from s0 to s1, up to
  /// \p h from it, its ends at \p taper to the border line (the untrimmed tab; pi/2: square
  /// ends): a rectangle per edge of the side's polyline and a wedge at each bend, each clipped
  /// by the two ends.
  std::vector<Polygon2> trapezoid(const Side& side, double s0, double s1, double h,
                                  double taper = kGlueTabTaper) const {
    const std::vector<double> ss = stations(side, s0, s1);
    std::vector<Vec2> pts;
    for (double v : ss) pts.push_back(at(side, v).point);
    // The ends lean in by the taper: keep (x - end).m <= 0 at both ends.
    const SidePoint first = at(side, std::min(s0 + 1e-6, s1)),
                    last = at(side, std::max(s1 - 1e-6, s0));
    const double ca = std::cos(taper), sa = std::sin(taper);
    const Vec2 m0 = -sa * first.dir + ca * first.normal, m1 = sa * last.dir + ca * last.normal;
    Vec2 lo = pts[0], hi = pts[0];
    for (const Vec2& v : pts) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    lo -= Vec2::Constant(h + 1), hi += Vec2::Constant(h + 1);
    Polygon2 keep = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
    keep = clip_half_plane(keep, pts.front(), m0);
    keep = clip_half_plane(keep, pts.back(), m1);
    if (keep.size() < 3) return {};
    keep = ccw(keep);
    std::vector<Polygon2> pieces;
    Vec2 before(0, 0);
    for (std::size_t j = 0; j + 1 < pts.size(); ++j) {
      const Vec2 a = pts[j], b = pts[j + 1];
      if ((b - a).norm() < 1e-9) continue;
      const Vec2 n = at(side, 0.5 * (ss[j] + ss[j + 1])).normal;
      std::vector<Polygon2> parts = {
          ccw({a - kOverlap * n, b - kOverlap * n, b + h * n, a + h * n})};
      if (before.norm() > 0) {
        const Polygon2 wedge = {a, a + h * before, a + h * n};
        if (std::abs(polygon_area(wedge)) > 1e-9) parts.push_back(ccw(wedge));
      }
      before = n;
      for (const auto& part : parts)
        for (auto& c : polygon_intersection(part, keep)) pieces.push_back(std::move(c));
    }
    return polygon_union(pieces);
  }

  /// The tab of height \p h on side \p si of border \p i from s0 to s1, its ends at \p taper
  /// to the border line, clipped to what is free on the sheet and under the other part; nothing if
  /// too little of it is left.
  std::optional<Tab> candidate(int i, int si, double s0, double s1, double h,
                               double taper = kGlueTabTaper) const {
    const Piece& piece = bp_.pieces[i];
    const Side &side = piece.sides[si], &mate = piece.sides[1 - si];
    const int p = side.patch, q = mate.patch;
    const std::vector<double> ss = stations(side, s0, s1);
    std::vector<Vec2> pts;
    for (double v : ss) pts.push_back(at(side, v).point);
    // Under the other part: inside it, off the tabs already glued there. The frames are related
    // by the rigid motion that lays this side's border onto the other side's.
    std::vector<Vec2> from, to;
    for (int k = 0; k <= 16; ++k) {
      const double v = s0 + (s1 - s0) * k / 16;
      from.push_back(at(side, v).point);
      to.push_back(at(mate, v).point);
    }
    const Rigid onto = fit_rigid(from, to);
    // At most half as tall as the mate is deep there, so that the border across it has room
    // for its tabs too (a stub's tab, placed after the long borders' tabs and clipped against
    // them, may take all of the depth but the gap).
    const bool stub = taper == kStubTaper;
    const SidePoint centre = at(side, 0.5 * (s0 + s1));
    const double deep = depth(body_[q], onto.apply(centre.point), onto.turn(centre.normal));
    h = std::min(h, (stub ? 1.0 : 0.5) * (deep - kGlueTabGap));
    if (!(h > 0)) return std::nullopt;
    std::vector<Polygon2> shape = trapezoid(side, s0, s1, h, taper);
    const double ideal = total_area(shape);
    if (!(ideal > 0)) return std::nullopt;
    // Off its own part (but for the overlap along the root) and its other tabs on the sheet.
    std::vector<Polygon2> remove = inner_[p];
    remove.insert(remove.end(), clear_[p].begin(), clear_[p].end());
    // The band along the root where the tab may come nearer than the gap to its own part and to
    // the mate's edges: as tall as the gap, its ends leaning in by kGlueTabTaper. A stub's tab
    // (square ends) may also take all that lies within the gap of its root, so that a stub
    // between square corners of the mate still has a tab: the band holds it to the stretch of
    // the mate the gap inside its edges. Such a tab keeps the gap from its own part elsewhere
    // (beside a reflex corner of its own part it would join it on the sheet).
    std::vector<Polygon2> band = trapezoid(side, s0, s1, kGlueTabGap + 0.01, kGlueTabTaper);
    if (stub) {
      auto near = trapezoid(side, s0, s1, kGlueTabGap - 0.01, kStubTaper);
      near.insert(near.end(), band.begin(), band.end());
      band = polygon_union(near);
      for (auto& c : polygon_difference(polygon_offset({body_[p]}, kGlueTabGap), band))
        remove.push_back(std::move(c));
    }
    Polygon2 tab = largest_polygon(polygon_difference(shape, remove));
    if (tab.size() < 3) return std::nullopt;
    // The room: the mate kept the gap inside its edges, but for the stretch along this border.
    std::vector<Polygon2> room = room_[q];
    for (const auto& c : band) {
      if (stub)
        for (auto& under : polygon_intersection(onto.apply(c), body_[q]))
          room.push_back(std::move(under));
      else
        room.push_back(onto.apply(c));
    }
    room = polygon_union(room);
    std::vector<Polygon2> inside;
    for (const auto& r : room)
      if (polygon_area(r) > 0)
        for (auto& c : polygon_intersection(onto.apply(tab), r)) inside.push_back(std::move(c));
    inside = polygon_union(inside);
    if (!under_[q].empty()) inside = polygon_difference(inside, under_[q]);
    Polygon2 under = largest_polygon(inside);
    if (under.size() < 3) return std::nullopt;
    // Without spikes and slivers narrower than 0.6 times the gap (what the clipping leaves at
    // corners): they would tear off, and are no cut a blade or laser makes cleanly.
    under = largest_polygon(polygon_offset(polygon_offset({under}, -0.3 * kGlueTabGap), 0.3 * kGlueTabGap));
    if (under.size() < 3) return std::nullopt;
    tab = onto.inverse(under);
    const double area = polygon_area(tab);
    if (area < kMinGlueTabArea || area < ideal / 3) return std::nullopt;
    // Its root: where it still touches the border line.
    double r0 = s1, r1 = s0;
    for (const Vec2& v : tab)
      for (std::size_t j = 0; j + 1 < pts.size(); ++j) {
        const Vec2 a = pts[j], e = pts[j + 1] - a;
        const double t = std::clamp((v - a).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
        if ((a + t * e - v).norm() > 0.01) continue;
        const double at_s = ss[j] + t * (ss[j + 1] - ss[j]);
        r0 = std::min(r0, at_s), r1 = std::max(r1, at_s);
      }
    if (r1 - r0 < 0.5 * (s1 - s0)) return std::nullopt;
    return Tab{tab, under, r0, r1, h};
  }

  void place(int i) {
    const Piece& piece = bp_.pieces[i];
    BorderJoint& b = out_.borders[i];
    b.edge = piece.edge;
    b.edges = piece.edges;
    b.patches = {piece.sides[0].patch, piece.sides[1].patch};
    b.length = piece.length;
    const int n = std::max(1, static_cast<int>(std::lround(piece.length / kGlueTabRun)));
    for (int j = 0; j < n; ++j)
      stretch(i, piece.length * j / n, piece.length * (j + 1) / n, j % 2, n == 1, 0);
  }

  /// Glue tab for the stretch [s0, s1] of border \p i: on the \p preferred side, else the
  /// other, else at half the height; a \p lone tab goes to the side where more of it is left.
  /// Where none fits, the two halves of the stretch are tried (twice at most), so that a tab is
  /// made where there is room (a corner of the other part, or a tab already glued under it, may
  /// block only part of the stretch). A stretch too short to halve that has no room for a
  /// leaning tab gets one with square ends (kStubTaper) where the corners leave it room.
  void stretch(int i, double s0, double s1, int preferred, bool lone, int depth) {
    const double len = s1 - s0;
    const bool halves = depth < 2 && len >= 8.0;
    std::optional<Tab> tab;
    int owner = -1;
    auto place_on_a_side = [&](double height, double taper) {
      if (lone) {
        auto a = candidate(i, 0, s0, s1, height, taper), c = candidate(i, 1, s0, s1, height, taper);
        if (a && (!c || polygon_area(a->region) >= polygon_area(c->region)))
          tab = a, owner = 0;
        else if (c)
          tab = c, owner = 1;
      } else {
        for (int side : {preferred, 1 - preferred})
          if ((tab = candidate(i, side, s0, s1, height, taper))) {
            owner = side;
            break;
          }
      }
    };
    const double h = std::min(o_.glue_tab, 0.4 * len * std::tan(kGlueTabTaper));
    for (double height : {h, 0.5 * h})
      if (!tab) place_on_a_side(height, kGlueTabTaper);
    // A stub where three parts meet: a leaning tab is 0.4 of its length tall (under 2 mm^2 on a
    // 3 mm stub); one with square ends may be up to twice as tall as the stub is long.
    const double square = std::min(o_.glue_tab, std::max(2.0, 2 * len));
    if (square_stubs_ && !halves)
      for (double height : {square, 0.5 * square})
        if (!tab) place_on_a_side(height, kStubTaper);
    if (!tab && halves) {
      const double mid = 0.5 * (s0 + s1);
      stretch(i, s0, mid, preferred, false, depth + 1);
      stretch(i, mid, s1, 1 - preferred, false, depth + 1);
      return;
    }
    JointInterval in;
    in.s0 = s0;
    in.s1 = s1;
    in.fold = bp_.pieces[i].fold_at(0.5 * (s0 + s1));
    BorderJoint& b = out_.borders[i];
    if (!tab) {
      ++b.blocked;
      b.intervals.push_back(in);
      return;
    }
    in.owner = owner;
    in.kind = JointKind::kGlue;
    in.offsets.tip = tab->height;
    in.offsets.slot = 0;
    b.intervals.push_back(in);
    record(i, static_cast<int>(b.intervals.size()) - 1, owner, *tab);
  }

  /// Keeps \p tab, made for interval \p interval of border \p i on side \p owner: on its part
  /// (a span, and its root as a fold line) and under the other part.
  void record(int i, int interval, int owner, const Tab& tab) {
    const Piece& piece = bp_.pieces[i];
    ++out_.borders[i].glue, ++out_.glue_tabs;
    out_.glue_length += tab.s1 - tab.s0;
    out_.toothed_length += tab.s1 - tab.s0;
    const Side& side = piece.sides[owner];
    const int p = side.patch, q = piece.sides[1 - owner].patch;
    own_[p].push_back(tab.region);
    clear_[p] = polygon_offset(own_[p], kGlueTabGap);
    for (auto& c : polygon_offset({tab.under}, 0.5 * kGlueTabGap)) under_[q].push_back(std::move(c));
    FoldLine fold;
    fold.kind = FoldLine::Kind::kTabRoot;
    fold.border = i;
    for (double v : stations(side, tab.s0, tab.s1)) fold.points.push_back(at(side, v).point);
    fold.angle = signed_fold(piece, owner, 0.5 * (tab.s0 + tab.s1));
    JointSpan span;
    span.border = i;
    span.interval = interval;
    for (std::size_t k = 0; k + 1 < fold.points.size(); ++k)
      span.length += (fold.points[k + 1] - fold.points[k]).norm();
    span.offset = tab.height;
    span.tooth = true;
    span.kind = JointKind::kGlue;
    span.region = tab.region;
    span.from = fold.points.front();
    span.to = fold.points.back();
    span.normal = at(side, 0.5 * (tab.s0 + tab.s1)).normal;
    spans_[p].push_back(std::move(span));
    folds_[p].push_back(std::move(fold));
  }

  /// The rulings of patch \p p that bend by \p min_angle or more [rad], as fold lines.
  std::vector<FoldLine> ruling_folds(int p, double min_angle) const {
    std::vector<FoldLine> out;
    const Patch& patch = s_.patches[p];
    if (patch.flat || patch.rulings.size() < 3) return out;
    const auto& x = f_.patches[p].points;
    auto normal = [&](int face) {
      const auto& q = s_.faces[face];
      Vec3 n(0, 0, 0);
      for (int k = 0; k < 4; ++k) n += s_.vertices[q[k]].cross(s_.vertices[q[(k + 1) % 4]]);
      return n.norm() > 0 ? Vec3(n.normalized()) : n;
    };
    for (int i = 1; i + 1 < static_cast<int>(patch.rulings.size()); ++i) {
      double angle = 0, sign = 0;
      for (int row = 0; row < patch.rows(); ++row) {
        const int a = patch.face(i - 1, row), b = patch.face(i, row);
        const Vec3 na = normal(a), nb = normal(b);
        const double f = angle_between(na, nb);
        if (f > angle) {
          angle = f;
          sign = na.dot(face_centre(b) - face_centre(a)) < 0 ? 1 : -1;
        }
      }
      if (angle < min_angle) continue;
      FoldLine fold;
      fold.kind = FoldLine::Kind::kRuling;
      fold.angle = sign * angle;
      for (int k = 0; k <= patch.rows(); ++k) fold.points.push_back(x[patch.local(k, i)]);
      out.push_back(std::move(fold));
    }
    return out;
  }

  /// \p outline with its slits narrower than JointOptions::min_feature filled: where two tabs
  /// meet at a corner of their part, their tapered ends left notches of 0.1-0.5 mm (165 on the
  /// bunny at 250 mm) that a cutter cannot follow and that tear. What a closing by half that
  /// width adds is added; nothing is taken away (a tab's sharp corner stays as it is).
  /// The slits are measured as cut: the cutter's path runs half its kerf outside the part on
  /// both sides of a slit, so a slit of the smallest feature as drawn is one kerf narrower as
  /// cut (bob_tri in paper at 200 mm: a 0.9 mm slit between a tab and its part's corner).
  Polygon2 without_slits(const Polygon2& outline) const {
    const double r = 0.5 * (o_.min_feature + kerf_width_);
    if (outline.size() < 3 || !(r > 0)) return outline;
    std::vector<Polygon2> all;
    for (auto& fill :
         polygon_difference(polygon_offset(polygon_offset({outline}, r), -r), {outline}))
      if (std::abs(polygon_area(fill)) > 0) all.push_back(std::move(fill));
    // The mitred closing gives a V wider than about 29 degrees back as it was (its mitre
    // reaches the tip again), so the tip of every V, where it is narrower than 2r, is filled
    // directly: the triangle from the tip to where its sides are 2r apart (rocker-arm in paper at
    // 200 mm: a 35 degree V between two tabs, 0.9 mm wide 2 mm in).
    const double sign = polygon_area(outline) > 0 ? 1 : -1;
    const std::size_t n = outline.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 &a = outline[(i + n - 1) % n], &b = outline[i], &c = outline[(i + 1) % n];
      const Vec2 u = a - b, v = c - b;
      const double lu = u.norm(), lv = v.norm();
      if (!(lu > 0 && lv > 0)) continue;
      const double turn = sign * cross2(b - a, c - b);
      const double angle = std::acos(std::clamp(u.dot(v) / (lu * lv), -1.0, 1.0));
      if (!(turn < 0) || !(angle < M_PI / 2) || !(angle > 0)) continue;  // a notch under 90 deg
      const double reach = r / std::sin(0.5 * angle);  // along a side to where it is 2r wide
      Polygon2 tip = {b, b + std::min(reach, lu) / lu * u, b + std::min(reach, lv) / lv * v};
      make_counter_clockwise(tip);
      if (!(polygon_area(tip) > 1e-6)) continue;
      // None of it may lie on the part (another edge reaching into the V).
      if (common_area(outline, tip) < 1e-6) all.push_back(std::move(tip));
    }
    // A slot that narrows below 2r toward a flat end, with no vertex of its own under 90
    // degrees, the mitred closing gives back too (its walls, nearly parallel, meet far past its
    // end) and the tips above miss: the rounded closing fills it, as a cutter's circle sees it
    // (the vase of scripts/shapes.py in paper at 180 mm: a slot 1.13 mm wide at its end, two
    // concave corners of about 90 degrees, 0.98 mm as cut). Of its pieces only those holding
    // more than a concave corner's fillet of 90 degrees or more ((1 - pi/4) r^2) are added: the
    // rest are the fillets of the outline's corners, which a cutter rounds anyway.
    std::vector<Polygon2> rounded;
    for (auto& fill : polygon_difference(
             polygon_offset_round(polygon_offset_round({outline}, r, kRoundTolerance), -r,
                                  kRoundTolerance),
             {outline}))
      if (std::abs(polygon_area(fill)) > kSlotEnd * r * r) rounded.push_back(std::move(fill));
    if (all.empty() && rounded.empty()) return outline;
    // Grown by a hair: united exactly, a fill sharing its sides with the outline can come back
    // as a piece of its own touching it, which largest_polygon then drops (the tip of the V
    // between two tabs: Spot in paper at 250 mm kept a 0.9 mm slit so).
    all = polygon_offset(all, 1e-4);
    rounded = polygon_offset(rounded, 1e-4);
    // A fill of the rounded closing across the mouth of a pocket (a slit that opens into a
    // wider space between two arms of the part) would close the pocket into a hole, which the
    // part's outline, one ring, does not keep: the pocket would become paper where the surface
    // has none, bridging a tab to its part (the bunny in paper at 250 mm: 80 mm^2 so, behind a
    // slit 0.1 mm wide). Such fills are left out; the slit into the pocket stays a single cut,
    // as before them. A pocket narrower than twice the smallest feature all round is a slot a
    // cutter can hardly follow itself, and filled (the same bunny: 5.2 mm^2, 1.1-1.3 mm wide,
    // between a part and its own tab, its mouth 0.1 mm, which the auditor found as the cut
    // passing by itself). The mitred closing's fills and the tips close pockets as they did
    // before 2026-12-05 (fertility at 250 mm: one of 20 mm^2 behind a slot 1.1 mm wide).
    for (int round = 0; round <= kSealingRounds; ++round) {
      std::vector<Polygon2> united = all;
      united.insert(united.end(), rounded.begin(), rounded.end());
      united.push_back(outline);
      united = polygon_union(united);
      std::vector<Polygon2> holes;
      for (Polygon2& ring : united)
        if (polygon_area(ring) < -kHair * kHair) {
          make_counter_clockwise(ring);
          // A hole narrower than twice the smallest feature all round is a slot itself: filled.
          if (polygon_offset({ring}, -o_.min_feature).empty()) continue;
          for (auto& grown : polygon_offset({ring}, kHair)) holes.push_back(std::move(grown));
        }
      const Polygon2 outer = largest_polygon(united);
      if (holes.empty()) return outer;
      // What closes a pocket touches both it and the outside (a fill at the tip of a V inside
      // the pocket touches the pocket alone, and stays).
      const std::size_t before = rounded.size();
      std::erase_if(rounded, [&](const Polygon2& fill) {
        bool pocket = false;
        for (const Polygon2& hole : holes) pocket = pocket || common_area(fill, hole) > 0;
        if (!pocket) return false;
        double outside = 0;
        for (const Polygon2& c : polygon_difference(polygon_offset({fill}, kHair), {outer}))
          outside += std::abs(polygon_area(c));
        return outside > kHair * kHair * kHair;
      });
      if (rounded.size() == before) return outer;  // closed by the mitred fills, as before
    }
    all.push_back(outline);  // still closing one: without the rounded closing's fills
    return largest_polygon(polygon_union(all));
  }

  /// \p outline without its tails narrower than JointOptions::min_feature: of what an opening
  /// by half that width takes away, the pieces holding more than a square of it or reaching
  /// farther than it from the rest (the auditor's rule for a tail). Where two tabs meet at a
  /// corner of their part their tapered ends left hooks 0.5 mm wide (bob_tri in paper at
  /// 200 mm) that tear off; a tab glued under its mate misses nothing by losing one. A spike of
  /// the part's body itself (a strip's end at a sharp corner of the model) goes too, down to
  /// where it is that wide, as a cutter burns it away (the joints stage's
  /// without_thin_features does so for wood): rocker-arm in paper kept a spike 0.7 mm wide over
  /// 4 mm so, and the saddle of scripts/shapes.py a 21 degree corner. The body loses nothing but
  /// such tips: where taking them leaves more than one piece (a neck, not a tip), only the tabs'
  /// tails go.
  Polygon2 without_tails(const Polygon2& outline, const Polygon2& body) const {
    const double r = 0.5 * o_.min_feature;
    if (outline.size() < 3 || !(r > 0)) return outline;
    const auto opened = polygon_offset(polygon_offset({outline}, -r), r);
    if (opened.empty()) return outline;
    std::vector<Polygon2> tab_tails, tips;
    for (const auto& piece : polygon_difference({outline}, opened)) {
      if (!(polygon_area(piece) > 0)) continue;
      if (polygon_area(piece) <= o_.min_feature * o_.min_feature &&
          !reaches_beyond(piece, opened, o_.min_feature))
        continue;
      for (auto& off_body : polygon_difference({piece}, {body}))
        if (polygon_area(off_body) > 0) tab_tails.push_back(std::move(off_body));
      for (auto& on_body : polygon_intersection(piece, body))
        if (polygon_area(on_body) > 0) tips.push_back(std::move(on_body));
    }
    // Grown by a hair: taken away exactly, a tail sharing its sides with the outline can come
    // back as a hole touching it.
    auto without = [&](const std::vector<Polygon2>& tails) {
      std::vector<Polygon2> left;
      for (auto& c : polygon_difference({outline}, polygon_offset(tails, 1e-4)))
        if (polygon_area(c) > kHair * kHair) left.push_back(std::move(c));
      return left;
    };
    if (!tips.empty()) {
      std::vector<Polygon2> all = tab_tails;
      all.insert(all.end(), tips.begin(), tips.end());
      if (const std::vector<Polygon2> left = without(all); left.size() == 1) return left.front();
    }
    if (tab_tails.empty()) return outline;
    return largest_polygon(without(tab_tails));
  }

  PartOutline outline(int p) {
    PartOutline part;
    std::vector<Polygon2> all = {body_[p]};
    all.insert(all.end(), own_[p].begin(), own_[p].end());
    const auto united = polygon_union(all);
    part.designed = without_slits(without_tails(largest_polygon(united), body_[p]));
    int pieces = 0;
    for (const auto& c : united) pieces += polygon_area(c) > 0 ? 1 : 0;
    part.repaired = pieces != 1;
    part.cut = largest_polygon(polygon_offset({part.designed}, 0.5 * kerf_width_));
    part.spans = std::move(spans_[p]);
    part.folds = std::move(folds_[p]);
    for (auto& fold : ruling_folds(p, o_.score_rulings ? kMinScoredFold : kCreaseFold))
      part.folds.push_back(std::move(fold));
    const auto& x = f_.patches[p].points;
    for (const Crease& crease : f_.patches[p].creases) {
      FoldLine fold;
      fold.kind = FoldLine::Kind::kDiagonal;
      fold.angle = crease.fold;
      fold.points = {x[crease.ends[0]], x[crease.ends[1]]};
      part.folds.push_back(std::move(fold));
    }
    return part;
  }
};

}  // namespace

Joints make_glue_tabs(const Strips& strips, const Flattening& flat, const Machine& machine,
                      const JointOptions& options) {
  const border::Pieces pieces = border::make_pieces(strips, flat);
  auto bare_in = [](const Joints& j) {
    std::vector<int> bare;
    for (std::size_t i = 0; i < j.borders.size(); ++i)
      if (j.borders[i].glue == 0 && j.borders[i].length > 0) bare.push_back(static_cast<int>(i));
    return bare;
  };
  // A placement replaces the one kept where it leaves fewer borders without a tab and keeps
  // nearly all of the glued length (kStubGlueLoss).
  auto better = [](const Joints& b, const Joints& a) {
    return b.borders_without_joint < a.borders_without_joint &&
           b.glue_length >= (1 - kStubGlueLoss) * a.glue_length;
  };
  // Short borders left without a tab (stubs where three parts meet: the tabs of the long
  // borders beside them, placed first, took the room under their mates) go first once more.
  auto placed = [&](bool square_stubs) {
    Joints out = GlueBuilder(strips, flat, pieces, machine, options, {}, square_stubs).run();
    if (const std::vector<int> bare = bare_in(out); !bare.empty()) {
      Joints again = GlueBuilder(strips, flat, pieces, machine, options, bare, square_stubs).run();
      if (better(again, out)) out = std::move(again);
    }
    return out;
  };
  Joints out = placed(false);
  // Stubs still bare: the same with tabs with square ends where a leaning one has no room
  // (kept only where better: a square tab can take the room a neighbouring stub's leaning tab
  // needed).
  if (out.borders_without_joint > 0) {
    Joints square = placed(true);
    if (better(square, out)) out = std::move(square);
  }
  join_stubs_at_corners(out, strips, pieces, kStubAtCorner * options.tooth_width);
  return out;
}

}  // namespace kerfab
