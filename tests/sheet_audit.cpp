#include "sheet_audit.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "kerfab/adapters/polygon_ops.h"

namespace kerfab::test {
namespace {

std::vector<Vec2> path_points(const std::string& d) {
  std::istringstream in(d);
  std::vector<Vec2> pts;
  std::string token;
  while (in >> token)
    if (token == "M" || token == "L") {
      double x, y;
      in >> x >> y;
      pts.emplace_back(x, y);
    }
  return pts;
}

double segment_distance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  auto point_seg = [](const Vec2& p, const Vec2& u, const Vec2& v) {
    const Vec2 e = v - u;
    const double t =
        e.squaredNorm() > 0 ? std::clamp((p - u).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
    return (p - (u + t * e)).norm();
  };
  auto side = [](const Vec2& o, const Vec2& p, const Vec2& q) { return cross2(p - o, q - o); };
  if (side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0) return 0.0;
  return std::min({point_seg(a, c, d), point_seg(b, c, d), point_seg(c, a, b), point_seg(d, a, b)});
}

bool inside(const Vec2& p, const std::vector<Polygon2>& polys) {
  int winding = 0;
  for (const auto& poly : polys)
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
      const double c = cross2(b - a, p - a);
      if (a.y() <= p.y() && b.y() > p.y() && c > 0) ++winding;
      if (a.y() > p.y() && b.y() <= p.y() && c < 0) --winding;
    }
  return winding != 0;
}

/// Where the laser path \p path comes back within \p near of itself, with material between,
/// after running at least \p along on (both measured on points 0.1 mm apart): a hair or a neck
/// of material the beam burns through on its way in and out, however little area it holds (a
/// narrow mouth of open space between two passes burns nothing). A corner's two sides come that
/// close only at a corner sharper than 2 asin(near / along) (19 deg for 0.5 and 3 mm).
std::vector<Vec2> pinches(const Polygon2& path, double near, double along) {
  const std::vector<Polygon2> material = {path};
  std::vector<Vec2> pts;
  std::vector<double> s;
  double total = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Vec2 &a = path[i], &b = path[(i + 1) % path.size()];
    const double len = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.1)));
    for (int k = 0; k < n; ++k) {
      pts.push_back(a + (b - a) * (static_cast<double>(k) / n));
      s.push_back(total + len * k / n);
    }
    total += len;
  }
  std::map<std::pair<long, long>, std::vector<std::size_t>> grid;
  auto cell = [&](const Vec2& v) {
    return std::pair<long, long>(std::lround(std::floor(v.x() / near)),
                                 std::lround(std::floor(v.y() / near)));
  };
  for (std::size_t i = 0; i < pts.size(); ++i) grid[cell(pts[i])].push_back(i);
  std::vector<Vec2> found;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto [cx, cy] = cell(pts[i]);
    bool hit = false;
    for (long dx = -1; dx <= 1 && !hit; ++dx)
      for (long dy = -1; dy <= 1 && !hit; ++dy) {
        const auto it = grid.find({cx + dx, cy + dy});
        if (it == grid.end()) continue;
        for (std::size_t j : it->second) {
          const double gap = std::abs(s[i] - s[j]);
          if (std::min(gap, total - gap) >= along && (pts[i] - pts[j]).norm() < near &&
              inside(0.5 * (pts[i] + pts[j]), material)) {
            hit = true;
            break;
          }
        }
      }
    // One finding per pinch: points of one pinch lie within `along` of the last one found.
    if (hit && (found.empty() || (pts[i] - found.back()).norm() > along)) found.push_back(pts[i]);
  }
  return found;
}

std::string where(const SheetPart& p, const Vec2& at) {
  std::ostringstream os;
  os.precision(4);
  os << p.id << " on sheet " << p.sheet << " at (" << at.x() << ", " << at.y() << ")";
  return os.str();
}

}  // namespace

std::vector<SheetPart> read_sheet_parts(const std::filesystem::path& cut_dir) {
  std::vector<SheetPart> parts;
  for (int sheet = 1;; ++sheet) {
    char name[32];
    std::snprintf(name, sizeof name, "sheet-%03d.svg", sheet);
    std::ifstream in(cut_dir / name);
    if (!in) break;
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    // Plain scanning (std::regex recurses per character and overflows on large sheets).
    const std::string open = "<g class=\"part\" id=\"";
    for (std::size_t at = text.find(open); at != std::string::npos; at = text.find(open, at)) {
      const std::size_t id_end = text.find('"', at + open.size());
      const std::size_t end = text.find("</g>", id_end);
      SheetPart part;
      part.id = text.substr(at + open.size(), id_end - at - open.size());
      part.sheet = sheet;
      const std::string body = text.substr(id_end, end - id_end);
      const std::string path = "<path class=\"";
      for (std::size_t q = body.find(path); q != std::string::npos; q = body.find(path, q + 1)) {
        const std::size_t kind_end = body.find('"', q + path.size());
        const std::string kind = body.substr(q + path.size(), kind_end - q - path.size());
        const std::size_t d = body.find(" d=\"", kind_end);
        const std::size_t d_end = body.find('"', d + 4);
        const auto pts = path_points(body.substr(d + 4, d_end - d - 4));
        auto attribute = [&](const std::string& key) {
          const std::size_t a = body.find(" " + key + "=\"", kind_end);
          if (a == std::string::npos || a > d) return std::string();
          const std::size_t v = a + key.size() + 3;
          return body.substr(v, body.find('"', v) - v);
        };
        if (kind == "outline") {
          part.outline = pts;
        } else if (kind == "fold") {
          part.folds.push_back(
              {pts, attribute("data-fold"), attribute("stroke"), attribute("stroke-dasharray")});
        } else if (kind == "kerf" || kind == "label") {
          auto& list = kind == "kerf" ? part.kerf : part.engraving;
          for (std::size_t k = 0; k + 1 < pts.size(); k += 2) list.push_back({pts[k], pts[k + 1]});
        }
      }
      parts.push_back(std::move(part));
      at = end;
    }
  }
  return parts;
}

SheetAudit audit_sheets(const std::filesystem::path& cut_dir, const AuditLimits& lim) {
  SheetAudit a;
  const auto parts = read_sheet_parts(cut_dir);
  for (const auto& p : parts) a.sheets = std::max(a.sheets, p.sheet);
  a.parts = static_cast<int>(parts.size());
  for (const SheetPart& p : parts) {
    // The part itself: the laser path runs half a kerf outside it.
    Polygon2 path = p.outline;
    if (polygon_area(path) < 0) std::reverse(path.begin(), path.end());
    const auto shrunk = polygon_offset({path}, -0.5 * lim.kerf_width);
    Polygon2 outline = shrunk.empty() ? path : shrunk.front();
    for (const auto& piece : shrunk)
      if (polygon_area(piece) > polygon_area(outline)) outline = piece;
    a.cuts += static_cast<int>(p.kerf.size());
    // Cuts: length and spacing (distance between the segments, within one part).
    for (std::size_t i = 0; i < p.kerf.size(); ++i) {
      const auto& c = p.kerf[i];
      if ((c[1] - c[0]).norm() < lim.min_cut_length - 1e-6) {
        ++a.short_cuts;
        a.findings.push_back("cut " + std::to_string((c[1] - c[0]).norm()) +
                             " mm long: " + where(p, c[0]));
      }
      for (std::size_t j = i + 1; j < p.kerf.size(); ++j) {
        const auto& e = p.kerf[j];
        const double d = segment_distance(c[0], c[1], e[0], e[1]);
        a.closest_cuts = std::min(a.closest_cuts, d);
        if (d < lim.min_cut_spacing - 1e-6) {
          ++a.close_cut_pairs;
          a.findings.push_back("cuts " + std::to_string(d) + " mm apart: " + where(p, c[0]));
        }
      }
    }
    // The part: area, width, tails and slits.
    const double area = polygon_area(outline);
    if (area < lim.min_part_area) {
      ++a.small_parts;
      a.findings.push_back("part of " + std::to_string(area) + " mm^2: " + where(p, outline[0]));
    }
    if (polygon_offset({outline}, -0.5 * lim.min_part_width).empty()) {
      ++a.narrow_parts;
      a.findings.push_back("part narrower than " + std::to_string(lim.min_part_width) +
                           " mm: " + where(p, outline[0]));
    }
    // A feature exactly as wide as the limit is allowed (joints keep teeth exactly the smallest
    // feature clear of the bands beside them: the 400 mm box on a 300 x 200 mm bed keeps a finger
    // 1.000 mm wide as cut at a corner where a seam meets a box-jointed edge). An opening by
    // exactly half that width erodes such a strip to a line of no area and would take it all,
    // so the opening and closing go a micrometre under it: what they find is narrower than the
    // limit by more than the SVG's rounding.
    constexpr double kAtTheLimit = 1e-3;  // [mm]
    const double r = 0.5 * lim.min_feature - kAtTheLimit;
    const auto opened = polygon_offset(polygon_offset({outline}, -r), r);
    const auto closed = polygon_offset(polygon_offset({outline}, r), -r);
    // A feature counts when it holds more than a square of the minimum width, or reaches
    // farther than that width from the rest (a hair or a slit of a tenth of a millimetre holds
    // far less): the rounding of a corner of 40 degrees or more does neither.
    const double significant = lim.min_feature * lim.min_feature;
    auto feature = [&](const Polygon2& piece, const std::vector<Polygon2>& rest) {
      if (std::abs(polygon_area(piece)) > significant) return true;
      double reach = 0;
      for (const Vec2& v : piece) {
        double d = 1e300;
        for (const Polygon2& ring : rest) d = std::min(d, distance_to_boundary(v, ring));
        reach = std::max(reach, d);
      }
      return reach > lim.min_feature;
    };
    for (const auto& piece : polygon_difference({outline}, opened))
      if (feature(piece, opened)) {
        ++a.thin_features;
        a.findings.push_back("tail narrower than " + std::to_string(lim.min_feature) +
                             " mm: " + where(p, piece[0]));
      }
    for (const auto& piece : polygon_difference(closed, {outline}))
      if (feature(piece, closed)) {
        ++a.thin_features;
        a.findings.push_back("slit narrower than " + std::to_string(lim.min_feature) +
                             " mm: " + where(p, piece[0]));
      }
    for (const Vec2& at : pinches(path, 0.5 * lim.min_feature, 3 * lim.min_feature)) {
      ++a.thin_features;
      a.findings.push_back("laser path passes within " + std::to_string(0.5 * lim.min_feature) +
                           " mm of itself: " + where(p, at));
    }
    // Engraving: inside the outline's inset, clear of every cut.
    const auto inset = polygon_offset({outline}, -lim.label_clearance);
    for (const auto& s : p.engraving) {
      bool ok = inside(s[0], inset) && inside(s[1], inset);
      for (const auto& ring : inset)
        for (std::size_t k = 0; ok && k < ring.size(); ++k)
          if (segment_distance(s[0], s[1], ring[k], ring[(k + 1) % ring.size()]) == 0.0) ok = false;
      for (const auto& c : p.kerf)
        if (ok && segment_distance(s[0], s[1], c[0], c[1]) < lim.label_clearance) ok = false;
      if (!ok) {
        ++a.labels_off_part;
        a.findings.push_back("engraving off its part or across a cut: " + where(p, s[0]));
      }
    }
  }
  // Between parts: the laser paths of two parts on one sheet keep min_part_gap apart (closer,
  // the scrap between them burns away and the parts rattle or scorch). Exact segment distances,
  // after a bounding-box test.
  struct Bounds {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  };
  std::vector<Bounds> bounds(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (const Vec2& v : parts[i].outline) {
      bounds[i].x0 = std::min(bounds[i].x0, v.x()), bounds[i].x1 = std::max(bounds[i].x1, v.x());
      bounds[i].y0 = std::min(bounds[i].y0, v.y()), bounds[i].y1 = std::max(bounds[i].y1, v.y());
    }
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (std::size_t j = i + 1; j < parts.size(); ++j) {
      if (parts[i].sheet != parts[j].sheet) continue;
      const Bounds &b = bounds[i], &c = bounds[j];
      const double g = lim.min_part_gap;
      if (b.x0 > c.x1 + g || c.x0 > b.x1 + g || b.y0 > c.y1 + g || c.y0 > b.y1 + g) continue;
      const Polygon2 &p = parts[i].outline, &q = parts[j].outline;
      double d = 1e300;
      Vec2 at = p.empty() ? Vec2(0, 0) : p[0];
      for (std::size_t k = 0; k < p.size(); ++k)
        for (std::size_t m = 0; m < q.size(); ++m) {
          const double e = segment_distance(p[k], p[(k + 1) % p.size()], q[m], q[(m + 1) % q.size()]);
          if (e < d) d = e, at = p[k];
        }
      // One inside the other (a part in another's hole) without touching: still apart.
      a.closest_parts = std::min(a.closest_parts, d);
      if (d < g - 1e-6) {
        ++a.close_part_pairs;
        a.findings.push_back(parts[j].id + " " + std::to_string(d) + " mm from " +
                             where(parts[i], at));
      }
    }
  return a;
}

}  // namespace kerfab::test
