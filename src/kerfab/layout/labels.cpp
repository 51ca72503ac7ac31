#include "kerfab/layout/labels.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
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

/// Kerf-free stretches along the strip: the positions of the cuts, with the strip's ends.
std::vector<double> cut_stops(const KerfResult& kerf, int patch, double length) {
  std::vector<double> stops = {0.0};
  for (const auto& c : kerf.patches[patch].cuts) stops.push_back(c.position);
  stops.push_back(length);
  std::sort(stops.begin(), stops.end());
  return stops;
}

/// A label of \p text and \p height centred at \p spot, its baseline along the strip.
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

constexpr double kClear = 0.6;  // distance kept from a kerf cut [mm]

}  // namespace

std::optional<Label> part_label(const Strips& strips, const Flattening& flat,
                                const KerfResult& kerf, int patch, double max_height) {
  const StripFrame frame(flat.patches[patch].points,
                         static_cast<int>(strips.patches[patch].faces.size()));
  const auto stops = cut_stops(kerf, patch, frame.s.back());
  const std::string text = std::to_string(patch);
  const double length_per_height = kAdvance * text.size() - 0.3;  // along the strip
  std::optional<Label> best;
  for (std::size_t k = 0; k + 1 < stops.size(); ++k) {
    const double a = stops[k] + kClear, b = stops[k + 1] - kClear;
    if (b <= a) continue;
    const double centre = 0.5 * (a + b);
    const auto [r0, r1] = frame.section(centre);
    const double height =
        std::min({max_height, 0.3 * (r1 - r0).norm(), (b - a) / std::max(length_per_height, 0.5)});
    if (height < 1.5 || (best && height <= best->height)) continue;
    best = label_at(text, height, 0.5 * (r0 + r1), frame.along(centre));
  }
  return best;
}

std::vector<Label> border_labels(const Strips& strips, const Flattening& flat,
                                 const KerfResult& kerf, const Joints& joints, int patch,
                                 const std::optional<Label>& part_label) {
  const Patch& p = strips.patches[patch];
  const StripFrame frame(flat.patches[patch].points, static_cast<int>(p.faces.size()));
  const auto& s = frame.s;
  // Where along the strip, and on which side, each neighbour's border lies.
  std::map<int, std::vector<std::pair<double, int>>> places;  // neighbour -> (s, side)
  for (const OutlineEdge& e : p.outline()) {
    const double at = e.side == 2   ? 0.0
                      : e.side == 3 ? s.back()
                                    : 0.5 * (s[e.face] + s[e.face + 1]);
    for (const BorderJoint& b : joints.borders) {
      if (b.edge != e.coarse_edge) continue;
      for (int k = 0; k < 2; ++k)
        if (b.patches[k] == patch && b.patches[1 - k] != patch)
          places[b.patches[1 - k]].push_back({at, e.side});
    }
  }
  const auto stops = cut_stops(kerf, patch, s.back());
  std::vector<Label> out;
  std::vector<std::array<double, 3>> taken;  // s0, s1, across-position of placed labels
  if (part_label) {
    // The part's number: its middle, found on the strip's middle line, and its length.
    const double length = (kAdvance * part_label->text.size() - 0.3) * part_label->height;
    const Vec2 centre = part_label->origin + Eigen::Rotation2Dd(part_label->angle) *
                                                 Vec2(0.5 * length, 0.35 * part_label->height);
    int nearest = 0;
    for (int i = 0; i <= frame.n; ++i)
      if ((frame.mid(i) - centre).norm() < (frame.mid(nearest) - centre).norm()) nearest = i;
    taken.push_back({s[nearest] - length, s[nearest] + length, 0.5});
  }
  for (const auto& [neighbour, list] : places) {
    // The middle of this neighbour's border stretch, on that side.
    std::vector<std::pair<double, int>> sorted = list;
    std::sort(sorted.begin(), sorted.end());
    const auto [target, side] = sorted[sorted.size() / 2];
    std::string text = std::to_string(neighbour);
    text.insert(text.begin(), '-');
    const double length_per_height = kAdvance * text.size() - 0.3;
    // Kerf-free stretches, nearest to the target first.
    std::vector<std::pair<double, std::size_t>> gaps;
    for (std::size_t k = 0; k + 1 < stops.size(); ++k)
      gaps.push_back({std::abs(0.5 * (stops[k] + stops[k + 1]) - target), k});
    std::sort(gaps.begin(), gaps.end());
    for (const auto& [distance, k] : gaps) {
      if (distance > 40) break;  // too far from its border to be useful
      const double a = stops[k] + kClear, b = stops[k + 1] - kClear;
      if (b <= a) continue;
      const double centre = 0.5 * (a + b);
      const auto [r0, r1] = frame.section(centre);
      const double height =
          std::min({3.0, 0.15 * (r1 - r0).norm(), (b - a) / std::max(length_per_height, 0.5)});
      if (height < 1.0) continue;
      const double across = side == 0 ? 0.2 : side == 1 ? 0.8 : 0.5;
      bool clash = false;  // another label in an overlapping stretch at the same height
      for (const auto& t : taken)
        if (std::abs(t[2] - across) < 0.35 && std::min(t[1], b) > std::max(t[0], a)) clash = true;
      if (clash) continue;
      out.push_back(label_at(text, height, r0 + across * (r1 - r0), frame.along(centre)));
      taken.push_back({a, b, across});
      break;
    }
  }
  return out;
}

}  // namespace kerfab
