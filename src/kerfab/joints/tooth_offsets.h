#pragma once
/// \file Box-joint tooth depths (paper Sec. 3.3.1, derived anew: the printed Eq. 3-4 do not say
/// how their angle is measured and are wrong for part of the range either way). Derivation:
/// docs/box-joints.md.

#include <limits>

namespace kerfab {

/// Where a part's contour runs at a joint, measured in the part's plane perpendicular to the
/// border line (the intersection of the two mid-surfaces): a tooth reaches `tip` beyond it, a
/// slot edge sits at `slot` (negative: cut back into the part). The mating part has a slot where
/// this one has a tooth and the other way round, with the same two values.
struct ToothOffsets {
  double tip = 0;   ///< [mm], >= 0
  double slot = 0;  ///< [mm], < 0 for 0 < fold < pi
};

/// Offsets for two plates of thickness \p thickness centred on their mid-surfaces, meeting at
/// fold angle \p fold between their normals (0 = coplanar, pi/2 = box corner; convex and concave
/// folds alike), such that (1) tooth and slotted edge never overlap in the cross-section,
/// (2) no tooth leaves the mitred shell between the surface offsets +-h/2 by more than
/// \p protrusion, (3) subject to these the glued overlap tip - slot is as large as possible.
/// With protrusion 0:  fold <= pi/2: tip = h/2 tan(fold/2), slot = -h/2 tan(fold/2)(1 + 2 cos fold)
///                     fold >= pi/2: tip = h/2 cot(fold/2), slot = -h/2 tan(fold/2).
/// \p max_tip caps the tip (the slot then follows the capped tip); with a protrusion allowed the
/// uncapped tip grows like protrusion / fold as the parts become coplanar.
/// \pre 0 < |fold| < pi, thickness > 0, protrusion >= 0, max_tip > 0 (radians, millimetres).
ToothOffsets tooth_offsets(double fold, double thickness, double protrusion = 0.0,
                           double max_tip = std::numeric_limits<double>::infinity());

}  // namespace kerfab
