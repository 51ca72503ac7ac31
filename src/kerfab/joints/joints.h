#pragma once
/// \file Box joints (paper Sec. 3.3): fold angles along every shared border, tooth depths from
/// tooth_offsets(), collision-free joint regions from offset bands of each flattened part
/// (Clipper), interlocking teeth with a phase shared by both sides of a border, laser-kerf
/// compensation, and each part's closed outline.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "kerfab/adapters/polygon_ops.h"
#include "kerfab/core/material.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/joints/tooth_offsets.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

/// Joint settings; the sheet thickness comes from the Material, the kerf width from the Machine.
struct JointOptions {
  double protrusion = 0.0;       ///< a tooth may leave the mitred shell by this much [mm], >= 0
  double tooth_width = 3.0;      ///< target width of teeth and slots along the border [mm], > 0
  double min_depth = 0.5;        ///< no teeth where tip - slot is below this [mm], >= 0
  double max_tip = 6.0;          ///< longest tooth [mm], > 0 (matters only with a protrusion,
                                 ///< where nearly coplanar parts would get ever longer teeth)
  double sharp_turn = M_PI / 6;  ///< consecutive outline edges turning more than this restrict
                                 ///< each other's teeth [rad]
  double min_feature = 1.0;      ///< tails and slits of the outline narrower than this are
                                 ///< removed (tails cut off, slits widened) [mm], >= 0
};

/// One tooth or slot interval of a border piece (a coarse edge shared by two patch sides).
struct JointInterval {
  double s0 = 0, s1 = 0;  ///< arc length along the piece from its common end [mm]
  int owner = -1;         ///< side (0 or 1) that has the tooth; -1: no tooth (both cut plain)
  double fold = 0;        ///< fold angle at the interval's middle [rad]
  ToothOffsets offsets;   ///< tip and slot for that fold
  double plain = 0;       ///< offset of both sides where there is no tooth [mm]
};

struct BorderJoint {
  int edge = -1;                       ///< coarse edge
  std::array<int, 2> patches{-1, -1};  ///< the two sides (may be one patch twice)
  double length = 0;                   ///< 3D length [mm]
  std::vector<JointInterval> intervals;
  int teeth = 0;
  int blocked = 0;  ///< intervals without teeth because of collisions
  int shallow = 0;  ///< intervals without teeth because tip - slot < min_depth
};

/// Where a part's contour leaves its border line: a tooth (outward) or a cut-back (slot or plain).
struct JointSpan {
  int border = -1;    ///< index into Joints::borders
  int interval = -1;  ///< index into that border's intervals
  double length = 0;  ///< length along the flattened border line [mm]
  double offset = 0;  ///< tip (> 0), slot or plain offset (< 0) [mm]
  bool tooth = false;
  Polygon2 region;            ///< for a tooth: the part of it beyond the border line
  Vec2 from{0, 0}, to{0, 0};  ///< the stretch of the border line it spans [mm]
  Vec2 normal{0, 0};          ///< outward unit normal of the border there
};

struct PartOutline {
  Polygon2 designed;  ///< closed outline with teeth, counter-clockwise [mm], in the patch's
                      ///< flattened frame
  Polygon2 cut;       ///< the same grown by half the kerf width: the path the laser follows
  std::vector<JointSpan> spans;  ///< every stretch of joint contour (a tooth across two outline
                                 ///< edges gives two spans)
  bool repaired = false;  ///< the Booleans or the removal of thin features split the part: only
                          ///< its largest piece is here (the resolve stage rebuilds such parts)
};

struct Joints {
  std::vector<BorderJoint> borders;
  std::vector<PartOutline> parts;  ///< per patch
  int teeth = 0;
  double border_length = 0;   ///< total length of shared borders [mm]
  double toothed_length = 0;  ///< of which covered by tooth intervals [mm]
  int repaired_parts = 0;
};

/// Builds the joints of every shared border and the outline of every part, for sheets of
/// \p material (its thickness) cut on \p machine (outlines grow by half its kerf width).
/// \pre \p flat was computed from \p strips. \throw InvalidInput options out of range.
Joints make_joints(const Strips& strips, const Flattening& flat, const Material& material,
                   const Machine& machine, const JointOptions& options);

/// Folds sharper than this are joined as if they were this sharp [rad]: two parts folded back
/// onto each other (only where a strip's rail collapses to a point) would need a cut-back
/// growing without bound; at 170 degrees it is h/2 tan(85 deg) = 5.7 h.
inline constexpr double kMaxJointFold = 170.0 * M_PI / 180.0;

/// Offset of both parts where a border has no teeth: the edges meet at the inner mitre point,
/// -h/2 tan(min(|fold|, kMaxJointFold)/2) [mm]; never overlapping.
double plain_offset(double fold, double thickness);

}  // namespace kerfab
