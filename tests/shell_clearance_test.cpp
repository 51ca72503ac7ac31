// Where the built shell meets itself: parts closer than the sheets are thick, measured on
// strips built by hand with exact answers.
#include "kerfab/eval/shell_clearance.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/strips/strips.h"

namespace kerfab {
namespace {

ShellClearance clearance(const Strips& s, const ClearanceOptions& o,
                         const TargetSurface* target = nullptr) {
  const TriangleMesh triangles = triangulate(s);
  return shell_clearance({s.vertices, s.faces, s.face_patch, s.edge_vertices, triangles}, o,
                         target);
}

/// Adds an n x n grid of sub-quads over the parallelogram origin + s u + t w, s, t in [0, 1],
/// as patch \p patch, oriented so that its normal is u x w (w x u with \p flip); the vertices
/// at s = 0 are \p first_column where given (shared with another grid); returns its vertex ids.
std::vector<int> add_grid(Strips& s, const Vec3& origin, const Vec3& u, const Vec3& w, int n,
                          int patch, const std::vector<int>& first_column = {}, bool flip = false) {
  std::vector<int> id((n + 1) * (n + 1));
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      if (i == 0 && !first_column.empty()) {
        id[j] = first_column[j];
        continue;
      }
      id[i * (n + 1) + j] = static_cast<int>(s.vertices.size());
      s.vertices.push_back(origin + (double(i) / n) * u + (double(j) / n) * w);
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      std::array<int, 4> q{id[i * (n + 1) + j], id[(i + 1) * (n + 1) + j],
                           id[(i + 1) * (n + 1) + j + 1], id[i * (n + 1) + j + 1]};
      if (flip) std::swap(q[1], q[3]);
      s.faces.push_back(q);
      s.face_patch.push_back(patch);
      s.face_quad.push_back(patch);
    }
  return id;
}

TEST(ShellClearance, TwoPlatesFacingCloserThanTheSheetsAreOneContactAtTheirGap) {
  for (const double gap : {1.25, 2.9, 3.2}) {
    Strips s;
    // Plate 0 at z = 0 facing up, plate 1 at z = gap facing down: 30 x 30 mm each.
    add_grid(s, Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3(0, 30, 0), 6, 0);
    add_grid(s, Vec3(0, 0, gap), Vec3(0, 30, 0), Vec3(30, 0, 0), 6, 1);
    const ShellClearance c = clearance(s, {.thickness = 3});
    if (gap >= 3) {
      EXPECT_TRUE(c.contacts.empty()) << gap;
      EXPECT_DOUBLE_EQ(c.size_factor(), 1.0);
      continue;
    }
    ASSERT_EQ(c.contacts.size(), 1u) << gap;
    const ClearanceContact& k = c.contacts[0];
    EXPECT_EQ(k.part_a, 0);
    EXPECT_EQ(k.part_b, 1);
    EXPECT_NEAR(k.gap, gap, 1e-9);
    EXPECT_NEAR((k.across - k.at).norm(), gap, 1e-9);
    // Both plates face the other all over: twice 900 mm^2.
    EXPECT_NEAR(k.area, 1800, 1e-6);
    EXPECT_NEAR(c.size_factor(), 3 / gap, 1e-9);
    EXPECT_EQ(k.inside_out, -1);
  }
}

TEST(ShellClearance, PlatesSideBySideOrAtAnAngleAreNoContact) {
  // Side by side in one plane, 1 mm apart: no line along a normal meets the other.
  Strips flat;
  add_grid(flat, Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3(0, 30, 0), 6, 0);
  add_grid(flat, Vec3(31, 0, 0), Vec3(30, 0, 0), Vec3(0, 30, 0), 6, 1);
  EXPECT_TRUE(clearance(flat, {.thickness = 3}).contacts.empty());
  // Plate 1 standing 1 mm above plate 0 at 70 degrees to it, facing it: the lines along plate
  // 0's normal meet it within 3 mm, but the two faces are 70 degrees from facing each other.
  Strips tilted;
  const double a = 70 * M_PI / 180;
  add_grid(tilted, Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3(0, 30, 0), 6, 0);
  add_grid(tilted, Vec3(-1, 0, 1), Vec3(0, 30, 0), Vec3(30 * std::cos(a), 0, 30 * std::sin(a)), 6,
           1);
  EXPECT_TRUE(clearance(tilted, {.thickness = 3}).contacts.empty());
}

TEST(ShellClearance, AFoldIsTheMitresWorkNotAContact) {
  // Two parts meeting along the y axis, the angle between their faces theta: lines along a
  // face's normal meet the other face within 3 mm for points under 3 / tan(theta) from the
  // fold, all within the mitres' reach 1.5 / tan(theta / 2). Down to 20 degrees (folded back
  // 160): no contact. The same plates 1 mm apart along x, no border between them: a contact.
  for (const double deg : {20.0, 40.0, 60.0, 89.0}) {
    const double theta = deg * M_PI / 180;
    for (const bool joined : {true, false}) {
      Strips s;
      const auto a = add_grid(s, Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3(0, 30, 0), 6, 0);
      const Vec3 dir(std::cos(theta), 0, std::sin(theta));
      std::vector<int> column;
      if (joined) column.assign(a.begin(), a.begin() + 7);  // the fold's vertices, x = 0
      // Facing plate 0's upper side, as a folded sheet does: normal (sin, 0, -cos).
      add_grid(s, joined ? Vec3(0, 0, 0) : Vec3(-1, 0, 0), 30 * dir, Vec3(0, 30, 0), 6, 1, column,
               true);
      if (joined) s.edge_vertices.push_back(column);
      const ShellClearance c = clearance(s, {.thickness = 3});
      if (joined) {
        EXPECT_TRUE(c.contacts.empty()) << deg << " deg, gap " << c.min_gap();
      } else if (deg < 55) {
        ASSERT_EQ(c.contacts.size(), 1u) << deg << " deg apart";
        EXPECT_LT(c.contacts[0].gap, 3.0);
      }
    }
  }
}

TEST(ShellClearance, APartTurnedAgainstTheTargetIsInsideOut) {
  // The target: one plate facing up. Part 0 lies on it; part 1 lies 0.5 mm above it facing
  // down, as a quad folded over its neighbour does.
  Strips s;
  add_grid(s, Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3(0, 30, 0), 6, 0);
  add_grid(s, Vec3(5, 5, 0.5), Vec3(0, 20, 0), Vec3(20, 0, 0), 4, 1);
  TriangleMesh plate;
  plate.vertices = {Vec3(-10, -10, 0), Vec3(40, -10, 0), Vec3(40, 40, 0), Vec3(-10, 40, 0)};
  plate.triangles = {{0, 1, 2}, {0, 2, 3}};
  const TargetSurface target(plate);
  const ShellClearance c = clearance(s, {.thickness = 3}, &target);
  ASSERT_EQ(c.contacts.size(), 1u);
  EXPECT_EQ(c.contacts[0].inside_out, 1);
  EXPECT_NEAR(c.contacts[0].gap, 0.5, 1e-9);
  // No thin place of the shape: no size is asked for.
  EXPECT_DOUBLE_EQ(c.min_thin_gap(), 3.0);
  EXPECT_DOUBLE_EQ(c.size_factor(), 1.0);
}

TEST(ShellClearance, PaperHasNoThicknessToCheck) {
  Strips s;
  add_grid(s, Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3(0, 30, 0), 6, 0);
  add_grid(s, Vec3(0, 0, 0.1), Vec3(0, 30, 0), Vec3(30, 0, 0), 6, 1);
  const ShellClearance c = clearance(s, {.thickness = 0});
  EXPECT_TRUE(c.contacts.empty());
  EXPECT_EQ(c.samples, 0);
}

}  // namespace
}  // namespace kerfab
