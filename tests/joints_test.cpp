#include "kerfab/joints/joints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "fixtures.h"
#include "kerfab/core/errors.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

constexpr double kPi = M_PI;
const Material kMdf;   // 3 mm
const Machine kLaser;  // 0.15 mm kerf

struct Case {
  Strips strips;
  Flattening flat;
  Joints joints;
};

// A 100 x 100 mm sheet folded by `fold_deg` along v = 0.5, strips forced across the fold and
// split there (split angle below the fold): every strip meets its other half at the fold.
Case folded_sheet(double fold_deg, const JointOptions& options = {}) {
  const double f = fold_deg * kPi / 180;
  auto sheet = [f](double u, double v) {
    if (v <= 0.5) return Vec3(100 * u, 100 * v, 0);
    const double w = 100 * (v - 0.5);
    return Vec3(100 * u, 50 + w * std::cos(f), w * std::sin(f));
  };
  const PolyMesh quads = test::grid_mesh(6, 6, false, false, sheet);
  const TargetSurface target(triangulate(test::grid_mesh(24, 24, false, false, sheet)));
  const BendingOptions bo = test::force_bendable(
      quads, [](const Vec3& a, const Vec3& b) { return std::abs(b.x() - a.x()) < 1e-9; });
  StripsOptions so;
  so.split_angle = std::min(fold_deg / 2, 60.0) * kPi / 180;
  Case c;
  c.strips = build_strips(quads, choose_bending_edges(quads, target, bo), target, so);
  c.flat = flatten_patches(c.strips, {});
  c.joints = make_joints(c.strips, c.flat, kMdf, kLaser, options);
  return c;
}

std::vector<int> ring(std::size_t n) {
  std::vector<int> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = static_cast<int>(i);
  return r;
}

double overlap_area(const Polygon2& a, const Polygon2& b) {
  double area = 0;
  for (const auto& p : polygon_intersection(a, b)) area += std::abs(polygon_area(p));
  return area;
}

// The checks of the issue: simple outlines, complementary teeth, no tooth on another tooth or on
// the part's own body.
// Parts that fell apart (\p max_repaired: raw real-mesh strips have collapsed strip ends the
// resolve stage removes) are flagged, never silently cut down.
void expect_sound_joints(const Strips& s, const Flattening& f, const Joints& j,
                         int max_repaired = 0) {
  ASSERT_EQ(j.parts.size(), s.patches.size());
  // Per (border, interval, side patch): tooth length or slot length in the plane.
  std::map<std::pair<int, int>, std::map<int, double>> tooth_len, slot_len;
  int repaired = 0;
  for (std::size_t p = 0; p < j.parts.size(); ++p) {
    const PartOutline& part = j.parts[p];
    SCOPED_TRACE("part " + std::to_string(p));
    ASSERT_GE(part.designed.size(), 3u);
    EXPECT_TRUE(is_simple_polygon(part.designed, ring(part.designed.size())));
    EXPECT_TRUE(is_simple_polygon(part.cut, ring(part.cut.size())));
    EXPECT_GT(polygon_area(part.designed), 0);
    repaired += part.repaired ? 1 : 0;
    // Kerf compensation: the laser path encloses the designed part and stays within half a
    // kerf of it (gaps narrower than the kerf close, as they must).
    auto area_of = [](const std::vector<Polygon2>& ps) {
      double a = 0;
      for (const auto& q : ps) a += polygon_area(q);
      return a;
    };
    // (1e-4 mm^2: a 10 um square, far below the beam's resolution; rounding debris is smaller.)
    EXPECT_LT(area_of(polygon_difference({part.designed}, {part.cut})), 1e-4);
    EXPECT_LT(area_of(polygon_difference(
                  {part.cut}, polygon_offset({part.designed}, 0.5 * kLaser.kerf_width + 1e-4))),
              1e-4);
    EXPECT_GT(polygon_area(part.cut), polygon_area(part.designed));
    // The body: the flattened patch.
    const Polygon2 body = flat_outline(s, f, static_cast<int>(p));  // the flattened patch
    std::vector<const JointSpan*> teeth;
    for (const JointSpan& sp : part.spans)
      if (sp.tooth) teeth.push_back(&sp);
    for (std::size_t a = 0; a < teeth.size(); ++a) {
      EXPECT_LT(overlap_area(teeth[a]->region, body), 1e-6) << "tooth " << a << " on the body";
      for (std::size_t b = a + 1; b < teeth.size(); ++b) {
        EXPECT_LT(overlap_area(teeth[a]->region, teeth[b]->region), 1e-6)
            << "teeth " << a << ", " << b << " borders " << teeth[a]->border << "/"
            << teeth[a]->interval << " edge " << j.borders[teeth[a]->border].edge << " patches "
            << j.borders[teeth[a]->border].patches[0] << ","
            << j.borders[teeth[a]->border].patches[1] << " and " << teeth[b]->border << "/"
            << teeth[b]->interval << " edge " << j.borders[teeth[b]->border].edge << " patches "
            << j.borders[teeth[b]->border].patches[0] << ","
            << j.borders[teeth[b]->border].patches[1] << " at " << teeth[a]->region[0].transpose()
            << " / " << teeth[b]->region[0].transpose() << " tips " << teeth[a]->offset << " "
            << teeth[b]->offset;
      }
    }
    for (const JointSpan& sp : part.spans) {
      auto& target = sp.tooth ? tooth_len : slot_len;
      target[{sp.border, sp.interval}][static_cast<int>(p)] += sp.length;
    }
  }
  // Every tooth faces a slot of the same length on the other part (to 0.05 mm).
  int compared = 0;
  for (const auto& [key, by_part] : tooth_len) {
    const BorderJoint& b = j.borders[key.first];
    const JointInterval& in = b.intervals[key.second];
    ASSERT_GE(in.owner, 0);
    for (const auto& [part, length] : by_part) {
      const int other = b.patches[0] == b.patches[1]
                            ? part
                            : (part == b.patches[0] ? b.patches[1] : b.patches[0]);
      ASSERT_TRUE(slot_len.count(key)) << "tooth without slot";
      const auto& slots = slot_len.at(key);
      ASSERT_TRUE(slots.count(other));
      EXPECT_NEAR(length, slots.at(other), 0.05);
      ++compared;
    }
  }
  EXPECT_EQ(compared, j.teeth);
  EXPECT_EQ(repaired, j.repaired_parts);
  EXPECT_LE(repaired, max_repaired);
}

// Length of segment a-b inside (or, with \p outside, outside) polygon \p poly.
double length_inside(const Vec2& a, const Vec2& b, const Polygon2& poly, bool outside = false) {
  std::vector<double> t = {0.0, 1.0};
  const Vec2 d = b - a;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 p = poly[i], e = poly[(i + 1) % poly.size()] - p;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-15) continue;
    const Vec2 w = p - a;
    const double u = (w.x() * e.y() - w.y() * e.x()) / den,
                 v = (w.x() * d.y() - w.y() * d.x()) / den;
    if (u > 0 && u < 1 && v >= 0 && v < 1) t.push_back(u);
  }
  std::sort(t.begin(), t.end());
  double len = 0;
  for (std::size_t k = 0; k + 1 < t.size(); ++k) {
    const Vec2 m = a + 0.5 * (t[k] + t[k + 1]) * d;
    bool in = false;  // even-odd
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
      if ((poly[i].y() > m.y()) != (poly[j].y() > m.y()) &&
          m.x() <
              (poly[j].x() - poly[i].x()) * (m.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) +
                  poly[i].x())
        in = !in;
    if (in != outside) len += (t[k + 1] - t[k]) * d.norm();
  }
  return len;
}

// Every tooth, measured on the final outline at half its height over its interval, is as wide
// as the interval (to 0.05 mm: not trimmed), and the slot it goes into, measured on the mate's
// final outline just above the slot's bottom over the same interval, is open over that width.
void expect_teeth_fit_slots(const Strips& s, const Flattening& f, const Joints& j) {
  std::map<std::pair<int, int>, double> tooth, slot, nominal;  // (border, interval)
  (void)s, (void)f;
  for (std::size_t p = 0; p < j.parts.size(); ++p) {
    for (const JointSpan& sp : j.parts[p].spans) {
      if (sp.border < 0 || sp.offset == 0) continue;
      const double depth = sp.tooth ? 0.5 * sp.offset : 0.9 * sp.offset;
      const Vec2 a = sp.from + depth * sp.normal, b = sp.to + depth * sp.normal;
      const auto key = std::make_pair(sp.border, sp.interval);
      if (sp.tooth) {
        tooth[key] += length_inside(a, b, j.parts[p].designed);
        nominal[key] += sp.length;
      } else if (j.borders[sp.border].intervals[sp.interval].owner >= 0) {
        // The room for the tooth: no material of the part as cut there.
        slot[key] += length_inside(a, b, j.parts[p].designed, true);
      }
    }
  }
  for (const auto& [key, width] : tooth) {
    EXPECT_NEAR(width, nominal[key], 0.05)
        << "tooth of border " << key.first << " interval " << key.second;
    ASSERT_TRUE(slot.count(key)) << "tooth without slot";
    EXPECT_GE(slot[key], width - 0.05)
        << "slot of border " << key.first << " interval " << key.second;
  }
}

TEST(Joints, BoxCornerTeethReachThroughTheOtherPart) {
  const JointOptions o;
  const Case c = folded_sheet(90, o);
  ASSERT_EQ(c.strips.patches.size(), 12u);
  int fold_borders = 0;
  for (const BorderJoint& b : c.joints.borders) {
    const bool at_fold = std::abs(b.intervals.front().fold - kPi / 2) < 1e-6;
    if (!at_fold) {  // borders between neighbouring strips of a flat half: no teeth possible
      for (const auto& in : b.intervals) EXPECT_LT(in.fold, 1e-6);
      EXPECT_EQ(b.teeth, 0);
      continue;
    }
    ++fold_borders;
    EXPECT_NEAR(b.length, 100.0 / 6, 1e-9);
    ASSERT_EQ(b.intervals.size(), 6u);  // 16.7 mm in teeth of about 3 mm
    for (const auto& in : b.intervals) {
      EXPECT_NEAR(in.offsets.tip, kMdf.thickness / 2, 1e-9);
      EXPECT_NEAR(in.offsets.slot, -kMdf.thickness / 2, 1e-9);
    }
    EXPECT_GE(b.teeth, 4);  // at most the intervals at the sheet's edge may be blocked
  }
  EXPECT_EQ(fold_borders, 6);
  expect_sound_joints(c.strips, c.flat, c.joints);
  expect_teeth_fit_slots(c.strips, c.flat, c.joints);
  // Kerf compensation of these rectilinear parts: the area grows by half a kerf times the
  // perimeter plus the square corners.
  for (const PartOutline& part : c.joints.parts) {
    double perimeter = 0;
    for (std::size_t i = 0; i < part.designed.size(); ++i)
      perimeter += (part.designed[(i + 1) % part.designed.size()] - part.designed[i]).norm();
    const double d = 0.5 * kLaser.kerf_width;
    EXPECT_NEAR(polygon_area(part.cut) - polygon_area(part.designed), d * perimeter,
                0.02 * d * perimeter);
  }
}

TEST(Joints, ShallowFoldsGetNoTeethUnlessProtrusionIsAllowed) {
  JointOptions o;
  const Case c = folded_sheet(8, o);  // tip - slot = h * 0.14 = 0.42 mm < 0.5 mm
  EXPECT_EQ(c.joints.teeth, 0);
  int shallow = 0;
  for (const auto& b : c.joints.borders) shallow += b.shallow;
  EXPECT_GT(shallow, 0);
  o.protrusion = 0.2;
  const Case d = folded_sheet(8, o);
  EXPECT_GT(d.joints.teeth, 0);
  expect_sound_joints(d.strips, d.flat, d.joints);
}

TEST(Joints, FoldAnglesAndOffsetsFollowTheSurface) {
  for (double deg : {30.0, 60.0, 120.0}) {
    const Case c = folded_sheet(deg);
    for (const BorderJoint& b : c.joints.borders) {
      if (b.intervals.front().fold < 1e-6) continue;
      for (const auto& in : b.intervals) {
        EXPECT_NEAR(in.fold, deg * kPi / 180, 1e-6);
        const ToothOffsets e = tooth_offsets(deg * kPi / 180, 3.0);
        EXPECT_NEAR(in.offsets.tip, e.tip, 1e-6);
        EXPECT_NEAR(in.offsets.slot, e.slot, 1e-6);
      }
    }
    expect_sound_joints(c.strips, c.flat, c.joints);
    expect_teeth_fit_slots(c.strips, c.flat, c.joints);
  }
}

TEST(Joints, RealMeshesHaveSoundOutlines) {
  for (const test::RealModel& model : {test::spot(), test::fandisk()}) {
    SCOPED_TRACE(model.target);
    const PreparedInput p = test::load(model);
    Strips s = test::real_strips(p);
    Flattening f = flatten_patches(s, {});
    for (std::size_t i = 0; i < f.patches.size(); ++i)  // as the pipeline does
      if (!f.patches[i].outline_simple)
        s = split_patch(s, static_cast<int>(i), s.patches[i].quads.size() / 2);
    f = flatten_patches(s, {});
    const JointOptions o;
    const Joints j = make_joints(s, f, kMdf, kLaser, o);
    EXPECT_GT(j.teeth, 100);
    EXPECT_GT(j.toothed_length, 0.25 * j.border_length);
    expect_sound_joints(s, f, j, 3);
    expect_teeth_fit_slots(s, f, j);
  }
}

// Two parts folded back onto each other (a collapsed strip end) would need an endless
// cut-back: the joint is made as at 170 degrees, h/2 tan(85 deg) deep, never more.
TEST(Joints, FoldsBackOntoEachOtherGetABoundedCutBack) {
  const double h = 3.0, deepest = 0.5 * h * std::tan(85.0 * M_PI / 180.0);
  EXPECT_NEAR(plain_offset(M_PI, h), -deepest, 1e-9);
  EXPECT_NEAR(plain_offset(M_PI - 1e-12, h), -deepest, 1e-9);
  EXPECT_NEAR(plain_offset(M_PI / 2, h), -0.5 * h, 1e-12);  // box corner: the mitre, unclamped
  EXPECT_TRUE(std::isfinite(plain_offset(-M_PI, h)));
}

TEST(Joints, RejectsBadOptions) {
  const Case c = folded_sheet(90);
  Material thin;
  thin.thickness = -1;  // 0 is allowed: paper
  EXPECT_THROW(make_joints(c.strips, c.flat, thin, kLaser, {}), InvalidInput);
  Machine laser;
  laser.kerf_width = -0.1;
  EXPECT_THROW(make_joints(c.strips, c.flat, kMdf, laser, {}), InvalidInput);
  JointOptions bad;
  bad.tooth_width = -1;
  EXPECT_THROW(make_joints(c.strips, c.flat, kMdf, kLaser, bad), InvalidInput);
}

}  // namespace
}  // namespace kerfab
