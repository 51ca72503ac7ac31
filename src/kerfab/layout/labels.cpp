#include "kerfab/layout/labels.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

namespace kerfab {
namespace {

// Seven-segment strokes on a 1 x 2 cell: a top, b upper right, c lower right, d bottom,
// e lower left, f upper left, g middle.
const std::array<std::array<double, 4>, 7> kSegments = {{{0, 2, 1, 2},
                                                         {1, 2, 1, 1},
                                                         {1, 1, 1, 0},
                                                         {0, 0, 1, 0},
                                                         {0, 1, 0, 0},
                                                         {0, 2, 0, 1},
                                                         {0, 1, 1, 1}}};

const char* segments_of(char c) {
  switch (c) {
    case '0':
      return "abcdef";
    case '1':
      return "bc";
    case '2':
      return "abged";
    case '3':
      return "abgcd";
    case '4':
      return "fgbc";
    case '5':
      return "afgcd";
    case '6':
      return "afgedc";
    case '7':
      return "abc";
    case '8':
      return "abcdefg";
    case '9':
      return "abcdfg";
    case '-':
      return "g";
    default:
      return "";
  }
}

constexpr double kAdvance = 0.8;  // glyph advance per unit height

}  // namespace

std::vector<std::array<Vec2, 2>> label_strokes(const Label& label) {
  std::vector<std::array<Vec2, 2>> out;
  const Eigen::Rotation2Dd r(label.angle);
  const double u = 0.5 * label.height;  // the cell is 1 x 2 units
  // An underline marks which way is down, so "52" can never be read as "25" however turned.
  const double length = (kAdvance * label.text.size() - 0.3) * label.height;
  out.push_back({label.origin + r * Vec2(0, -0.3 * label.height),
                 label.origin + r * Vec2(length, -0.3 * label.height)});
  for (std::size_t i = 0; i < label.text.size(); ++i) {
    const double x0 = i * kAdvance * label.height;
    for (const char* s = segments_of(label.text[i]); *s; ++s) {
      const auto& seg = kSegments[*s - 'a'];
      const Vec2 a(x0 + u * seg[0], u * seg[1]), b(x0 + u * seg[2], u * seg[3]);
      out.push_back({label.origin + r * a, label.origin + r * b});
    }
  }
  return out;
}

Label upright(const Label& label, double placement_angle) {
  if (std::cos(label.angle + placement_angle) >= -1e-9) return label;
  const double length = (kAdvance * label.text.size() - 0.3) * label.height;
  Label out = label;
  out.angle = label.angle + M_PI;
  // Half a turn about the middle of the label's box [0, length] x [-0.3 h, h].
  out.origin = label.origin + Eigen::Rotation2Dd(label.angle) * Vec2(length, 0.7 * label.height);
  return out;
}

namespace {

constexpr double kClear = 0.4;  // engraving keeps this far inside the outline and off cuts [mm]

/// The label's box in the part's frame: [0, length] x [-0.3 h, h] (digits over the underline),
/// grown by \p grow on every side, as four corners counter-clockwise.
std::array<Vec2, 4> label_box(const Label& l, double grow) {
  const double length = (kAdvance * l.text.size() - 0.3) * l.height;
  const Eigen::Rotation2Dd r(l.angle);
  const double x0 = -grow, x1 = length + grow, y0 = -0.3 * l.height - grow, y1 = l.height + grow;
  return {l.origin + r * Vec2(x0, y0), l.origin + r * Vec2(x1, y0), l.origin + r * Vec2(x1, y1),
          l.origin + r * Vec2(x0, y1)};
}

/// A label of \p text and \p height centred at \p spot, its baseline along \p along.
Label label_at(const std::string& text, double height, const Vec2& spot, const Vec2& along) {
  const double length = (kAdvance * text.size() - 0.3) * height;
  const Vec2 up(-along.y(), along.x());
  Label l;
  l.text = text;
  l.height = height;
  l.angle = std::atan2(along.y(), along.x());
  // The box [0, length] x [-0.3 h, h] (digits over the underline) centred on the spot.
  l.origin = spot - 0.5 * length * along - 0.35 * height * up;
  return l;
}

bool segments_cross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a);
  const double d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

/// Where engraving may go on one part: inside its outline (slots and teeth included) by the
/// clearance, off its kerf cuts by the clearance, and off labels already placed.
/// The inset outline's edges are kept by bands of y: a point's winding number and a box's
/// crossings look only at the edges whose y range reaches the point's band or the box's, the
/// same answers as scanning every edge (a long toothed strip has thousands, and a part's
/// number tries hundreds of spots).
class LabelRoom {
 public:
  LabelRoom(const Polygon2& outline, const std::vector<KerfCut>& cuts) {
    for (const auto& c : cuts) cuts_.push_back({c.a, c.b});
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& poly : polygon_offset({outline}, -kClear))
      for (std::size_t i = 0; i < poly.size(); ++i) {
        edges_.push_back({poly[i], poly[(i + 1) % poly.size()]});
        lo = std::min(lo, poly[i].y()), hi = std::max(hi, poly[i].y());
      }
    if (edges_.empty()) return;
    bands_.resize(std::max<std::size_t>(1, edges_.size() / 8));
    y0_ = lo;
    band_height_ = hi > lo ? (hi - lo) / static_cast<double>(bands_.size()) : 1.0;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const auto& [a, b] = edges_[e];
      for (std::size_t k = band(std::min(a.y(), b.y())); k <= band(std::max(a.y(), b.y())); ++k)
        bands_[k].push_back(static_cast<int>(e));
    }
  }

  bool fits(const Label& l) const {
    const auto box = label_box(l, 0.0);
    const auto grown = label_box(l, kClear);
    for (const Vec2& p : box)
      if (!inside(p)) return false;
    if (!bands_.empty()) {
      const auto [lo, hi] = y_range(box);
      for (std::size_t k = band(lo); k <= band(hi); ++k)
        for (int e : bands_[k])
          if (crosses(box, edges_[e][0], edges_[e][1])) return false;
    }
    const auto [grown_lo, grown_hi] = y_range(grown);
    for (const auto& c : cuts_) {
      // A cut wholly above or below the grown box neither crosses it nor ends in it.
      if (std::max(c[0].y(), c[1].y()) < grown_lo || std::min(c[0].y(), c[1].y()) > grown_hi)
        continue;
      if (crosses(grown, c[0], c[1]) || inside_box(grown, c[0]) || inside_box(grown, c[1]))
        return false;
    }
    for (const auto& other : taken_) {
      for (const Vec2& p : other)
        if (inside_box(grown, p)) return false;
      for (const Vec2& p : grown)
        if (inside_box(other, p)) return false;
      for (int k = 0; k < 4; ++k)
        if (crosses(grown, other[k], other[(k + 1) % 4])) return false;
    }
    return true;
  }
  void take(const Label& l) { taken_.push_back(label_box(l, kClear)); }

 private:
  std::vector<std::array<Vec2, 2>> cuts_;
  std::vector<std::array<Vec2, 4>> taken_;
  /// The outline's edges inset by the clearance, each ring in its order.
  std::vector<std::array<Vec2, 2>> edges_;
  std::vector<std::vector<int>> bands_;     ///< per band of y, the edges reaching it
  double y0_ = 0, band_height_ = 1;

  /// The band of \p y (the first or last one beyond the inset).
  std::size_t band(double y) const {
    const double k = std::floor((y - y0_) / band_height_);
    return static_cast<std::size_t>(std::clamp(k, 0.0, static_cast<double>(bands_.size() - 1)));
  }
  /// The y range of \p box, a thousandth of a millimetre wider either side (far beyond what
  /// rounding moves a crossing by).
  static std::pair<double, double> y_range(const std::array<Vec2, 4>& box) {
    double lo = box[0].y(), hi = box[0].y();
    for (const Vec2& p : box) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
    return {lo - 1e-3, hi + 1e-3};
  }
  /// Whether \p p lies inside the inset outline (non-zero winding over its rings), counting
  /// as kerfab::inside() does the edges that cross the horizontal through \p p, from its band.
  bool inside(const Vec2& p) const {
    if (bands_.empty()) return false;
    int w = 0;
    for (int e : bands_[band(p.y())]) w += winding_step(edges_[e][0], edges_[e][1], p);
    return w != 0;
  }
  static bool crosses(const std::array<Vec2, 4>& box, const Vec2& a, const Vec2& b) {
    for (int k = 0; k < 4; ++k)
      if (segments_cross(box[k], box[(k + 1) % 4], a, b)) return true;
    return false;
  }
  static bool inside_box(const std::array<Vec2, 4>& box, const Vec2& p) {
    for (int k = 0; k < 4; ++k)
      if (cross2(box[(k + 1) % 4] - box[k], p - box[k]) < 0) return false;
    return true;
  }
};

/// The part's flattened outline as edges in 2D, with the coarse edge each lies on.
struct FlatEdge {
  Vec2 a, b;
  int coarse_edge;
};
std::vector<FlatEdge> flat_edges(const Strips& strips, const Flattening& flat, int patch) {
  std::vector<FlatEdge> out;
  const auto& x = flat.patches[patch].points;
  auto ring = strips.patches[patch].outline();
  double area = 0;
  for (const auto& e : ring) area += cross2(x[e.v[0]], x[e.v[1]]);
  for (const auto& e : ring)
    out.push_back(area >= 0 ? FlatEdge{x[e.v[0]], x[e.v[1]], e.coarse_edge}
                            : FlatEdge{x[e.v[1]], x[e.v[0]], e.coarse_edge});
  return out;
}

}  // namespace

std::optional<Label> part_label(const Strips& strips, const Flattening& flat,
                                const KerfResult& kerf, const Polygon2& outline, int patch,
                                double max_height) {
  const LabelRoom room(outline, kerf.patches[patch].cuts);
  const std::string text = std::to_string(patch);
  const Patch& p = strips.patches[patch];
  // Candidate spots and directions: along a ladder, the middles of the kerf-free stretches
  // (and of every sub-quad); on a facet, a grid over it, along its long side.
  std::vector<std::pair<Vec2, Vec2>> spots;
  Vec2 centre(0, 0);
  if (!p.flat) {
    const StripFrame frame(flat.patches[patch].points, static_cast<int>(p.faces.size()));
    std::vector<double> stops = {0.0};
    for (const auto& c : kerf.patches[patch].cuts) stops.push_back(c.position);
    stops.push_back(frame.s.back());
    std::sort(stops.begin(), stops.end());
    std::vector<double> at;
    for (std::size_t k = 0; k + 1 < stops.size(); ++k)
      at.push_back(0.5 * (stops[k] + stops[k + 1]));
    for (int f = 0; f < frame.n; ++f) at.push_back(0.5 * (frame.s[f] + frame.s[f + 1]));
    for (double a : at) {
      const auto [r0, r1] = frame.section(a);
      const Vec2 along = frame.along(a);
      spots.push_back({0.5 * (r0 + r1), along});
      spots.push_back({0.5 * (r0 + r1), Vec2(-along.y(), along.x())});  // across, between cuts
    }
    centre = frame.mid(frame.n / 2);
  } else {
    Polygon2 poly = outline;
    double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
    for (const Vec2& v : poly) {
      centre += v / static_cast<double>(poly.size());
      min_x = std::min(min_x, v.x()), max_x = std::max(max_x, v.x());
      min_y = std::min(min_y, v.y()), max_y = std::max(max_y, v.y());
    }
    Vec2 along(1, 0);  // the outline's longest edge
    double longest = 0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 d = poly[(i + 1) % poly.size()] - poly[i];
      if (d.norm() > longest) longest = d.norm(), along = d.normalized();
    }
    for (double y = min_y; y <= max_y; y += 0.5)
      for (double x = min_x; x <= max_x; x += 0.5) spots.push_back({Vec2(x, y), along});
  }
  std::sort(spots.begin(), spots.end(), [&](const auto& a, const auto& b) {
    return (a.first - centre).squaredNorm() < (b.first - centre).squaredNorm();
  });
  for (double height = max_height; height >= 1.0 - 1e-9; height -= 0.25)
    for (const auto& [spot, along] : spots) {
      const Label l = label_at(text, height, spot, along);
      if (room.fits(l)) return l;
    }
  return std::nullopt;
}

std::vector<Label> border_labels(const Strips& strips, const Flattening& flat,
                                 const KerfResult& kerf, const Joints& joints,
                                 const Polygon2& outline, int patch,
                                 const std::optional<Label>& part_label) {
  LabelRoom room(outline, kerf.patches[patch].cuts);
  if (part_label) room.take(*part_label);
  // Per neighbour, the outline edges on borders with it.
  std::map<int, std::vector<FlatEdge>> along_border;
  std::map<int, std::vector<int>> neighbours_of_edge;
  for (const BorderJoint& b : joints.borders)
    for (int k = 0; k < 2; ++k)
      if (b.patches[k] == patch && b.patches[1 - k] != patch)
        for (int e : b.edges) neighbours_of_edge[e].push_back(b.patches[1 - k]);
  for (const FlatEdge& e : flat_edges(strips, flat, patch)) {
    const auto it = neighbours_of_edge.find(e.coarse_edge);
    if (it == neighbours_of_edge.end()) continue;
    for (int n : it->second) along_border[n].push_back(e);
  }
  std::vector<Label> out;
  for (const auto& [neighbour, edges] : along_border) {
    std::string text = std::to_string(neighbour);  // built in place: GCC 12 warns falsely on a +
    text.insert(text.begin(), '-');
    // Points along the border, the middle of its length first, then outwards.
    double total = 0;
    for (const auto& e : edges) total += (e.b - e.a).norm();
    std::vector<std::pair<double, std::pair<Vec2, Vec2>>> spots;  // distance from the middle
    double walked = 0;
    for (const auto& e : edges) {
      const double len = (e.b - e.a).norm();
      if (len <= 0) continue;
      const Vec2 d = (e.b - e.a) / len;
      for (double t = 0.5; t < len; t += 1.0) {
        const double from_middle = std::abs(walked + t - 0.5 * total);
        if (from_middle <= 40) spots.push_back({from_middle, {e.a + t * d, d}});
      }
      walked += len;
    }
    std::sort(spots.begin(), spots.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    bool placed = false;
    for (double height = 3.0; height >= 1.0 - 1e-9 && !placed; height -= 0.5)
      for (const auto& [distance, where] : spots) {
        const auto& [point, d] = where;
        const Vec2 inward(-d.y(), d.x());       // the outline runs counter-clockwise
        for (double depth : {0.9, 1.6, 2.5}) {  // label box half-height plus a margin
          const Label l = label_at(text, height, point + (depth * height + kClear) * inward, d);
          if (!room.fits(l)) continue;
          room.take(l);
          out.push_back(l);
          placed = true;
          break;
        }
        if (placed) break;
      }
  }
  return out;
}

}  // namespace kerfab
