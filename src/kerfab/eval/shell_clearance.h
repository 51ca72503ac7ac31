#pragma once
/// \file Where the built shell meets itself: two stretches of the strips, far apart along the
/// surface, that come closer in space than the sheets are thick. Every part stands h/2 to either
/// side of its surface, so two such stretches closer than h put two sheets in the same place:
/// a plate thinner than two sheets, an ear lying against a head, the two sides of a thin fin.
/// Folds are not contacts: the joints mitre the parts that meet at one (docs/box-joints.md).
#include <cmath>
#include <vector>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/mesh.h"

namespace kerfab {

struct ClearanceOptions {
  double thickness = 3;  ///< sheet thickness h [mm]; <= 0 (paper): nothing is checked
  /// Samples at most this far apart on every sub-quad [mm]; 0: the thickness.
  double sample_spacing = 0;
  /// Two stretches face each other where their normals are within this of opposite [rad]: a
  /// fold's two sides at a larger angle are the joints' mitres' work, as is what lies within
  /// the mitres' reach of a border (shell_clearance).
  double facing = M_PI / 3;
  /// Folds sharper than this are mitred as if this sharp (the joints' kMaxJointFold) [rad].
  double max_fold = M_PI;
  long max_samples = 2'000'000;  ///< beyond it the spacing is widened [count], > 0
};

/// One pair of parts whose sheets would overlap.
struct ClearanceContact {
  int part_a = -1, part_b = -1;  ///< patches of the strips, part_a <= part_b (equal: a part
                                 ///< that meets itself, e.g. a strip wrapped round a thin edge)
  double gap = 0;                ///< the smallest distance between their surfaces found [mm]
  Vec3 at{0, 0, 0};              ///< where: the sample on one part [mm]
  Vec3 across{0, 0, 0};          ///< and the point of the other it faces [mm]
  double area = 0;  ///< surface of the two parts that faces the other closer than h [mm^2]
  /// Where the target was given: the part of the two that lies inside out there (its faces
  /// turned against the target's: quads folded over their neighbours), -1: neither. Such a
  /// contact is no thinness of the shape, and no size cures it.
  int inside_out = -1;
};

struct ShellClearance {
  double thickness = 0;  ///< the sheets' [mm]
  double spacing = 0;    ///< the samples' spacing used [mm]
  long samples = 0;
  std::vector<ClearanceContact> contacts;  ///< narrowest first
  /// The narrowest gap [mm]; the thickness where there is no contact.
  double min_gap() const { return contacts.empty() ? thickness : contacts.front().gap; }
  /// The narrowest gap of the contacts where the shape is thin (no part inside out) [mm]; the
  /// thickness where there is none.
  double min_thin_gap() const {
    for (const auto& c : contacts)
      if (c.inside_out < 0) return c.gap;
    return thickness;
  }
  /// How much larger the model would have to be for every gap where the shape is thin to reach
  /// the thickness [-] (1: none; 0: a gap of zero, the surface meets itself, no size cures it).
  double size_factor() const {
    const double gap = min_thin_gap();
    return gap > 0 ? thickness / gap : 0;
  }
  double area() const {
    double a = 0;
    for (const auto& c : contacts) a += c.area;
    return a;
  }
};

/// The parts in their places in 3D, as the strips hold them: sub-quads over shared vertices,
/// each of one part, and the chains of vertices along which parts meet (the coarse edges).
struct Shell {
  const std::vector<Vec3>& vertices;             ///< [mm]
  const std::vector<std::array<int, 4>>& faces;  ///< consistently oriented
  const std::vector<int>& face_part;
  const std::vector<std::vector<int>>& lines;
  /// The sub-quads cut in two triangles each, in their order (triangulate(const Strips&)).
  const TriangleMesh& triangles;
};

/// Casts a line along the normal at samples over every sub-quad of \p shell (both ways, out to
/// the thickness) and keeps the nearest sub-quad it meets that is not the sample's own or one
/// beside it, faces it (ClearanceOptions::facing) and is not within the mitres' reach of a line
/// the two parts meet along; per pair of parts, the narrowest such gap. With \p target, each
/// contact says which part, if any, lies inside out there. Runs on all cores.
ShellClearance shell_clearance(const Shell& shell, const ClearanceOptions& options,
                               const TargetSurface* target = nullptr);

}  // namespace kerfab
