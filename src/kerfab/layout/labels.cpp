#include "kerfab/layout/labels.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

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

std::optional<Label> part_label(const Strips& strips, const Flattening& flat,
                                const KerfResult& kerf, int patch, double max_height) {
  const Patch& p = strips.patches[patch];
  const auto& x = flat.patches[patch].points;
  const int n = static_cast<int>(p.faces.size());
  auto mid = [&](int i) { return Vec2(0.5 * (x[2 * i] + x[2 * i + 1])); };
  std::vector<double> s(n + 1, 0.0);
  for (int i = 0; i < n; ++i) s[i + 1] = s[i] + (mid(i + 1) - mid(i)).norm();
  // Free stretches along the strip: between consecutive cuts (and the strip's ends).
  std::vector<double> stops = {0.0};
  for (const auto& c : kerf.patches[patch].cuts) stops.push_back(c.position);
  stops.push_back(s[n]);
  std::sort(stops.begin(), stops.end());
  const std::string text = std::to_string(patch);
  const double length_per_height = kAdvance * text.size() - 0.3;  // along the strip
  // (the underline sits 0.3 h below the digits: the label is 1.3 h tall across the strip)
  std::optional<Label> best;
  for (std::size_t k = 0; k + 1 < stops.size(); ++k) {
    const double a = stops[k] + 0.6, b = stops[k + 1] - 0.6;  // clear of the cut's kerf
    if (b <= a) continue;
    const double centre = 0.5 * (a + b);
    const int f = std::clamp(
        static_cast<int>(std::upper_bound(s.begin(), s.end(), centre) - s.begin()) - 1, 0, n - 1);
    const double u = s[f + 1] > s[f] ? (centre - s[f]) / (s[f + 1] - s[f]) : 0.5;
    const Vec2 r0 = (1 - u) * x[2 * f] + u * x[2 * (f + 1)];
    const Vec2 r1 = (1 - u) * x[2 * f + 1] + u * x[2 * (f + 1) + 1];
    const double width = (r1 - r0).norm();  // across the strip
    const double height =
        std::min({max_height, 0.3 * width, (b - a) / std::max(length_per_height, 0.5)});
    if (height < 1.5 || (best && height <= best->height)) continue;
    // Baseline along the strip, centred on the strip's middle line.
    Vec2 along = mid(std::min(f + 1, n)) - mid(f);
    if (along.norm() <= 0) continue;
    along.normalize();
    Vec2 up(-along.y(), along.x());
    const Vec2 centre_point = 0.5 * (r0 + r1);
    Label l;
    l.text = text;
    l.height = height;
    l.angle = std::atan2(along.y(), along.x());
    l.origin = centre_point - 0.5 * length_per_height * height * along - 0.35 * height * up;
    best = l;
  }
  return best;
}

}  // namespace kerfab
