#pragma once
/// \file Internal to the joints stage: the parts in their assembled 3D position as plates of the
/// material's thickness centred on the strip surface, to check a joint directly in 3D where the
/// bands of paper Fig. 6 are too coarse (short borders between corners). Each sub-quad of a part
/// carries the affine map from its flattened corners to its 3D corners (least squares; exact for
/// a planar sub-quad, which every bent strip's sub-quad nearly is); a flat point goes to 3D
/// through the sub-quad that holds it (the nearest one beyond the outline), a 3D point into a
/// part's flat frame through the part's nearest sub-quad.
#include <array>
#include <utility>
#include <vector>

#include "kerfab/core/geometry2d.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/strips/strips.h"

namespace kerfab::border {

class Plates {
 public:
  Plates(const Strips& strips, const Flattening& flat, double thickness);

  /// Point \p v of part \p p's flat frame on its mid-surface in 3D [mm], and the unit normal
  /// there (NaN if the part has no sub-quad).
  std::pair<Vec3, Vec3> place(int p, const Vec2& v) const;
  /// Part \p p's sub-quads whose centre lies within a sub-quad's size (and the thickness) of the
  /// box [lo, hi]: all that local() needs for points in that box.
  struct Window {
    int part = -1;
    std::vector<int> frames;
    std::vector<Vec3> centres;  ///< per frame, its 3D centre (local() scans these in a row)
  };
  Window window(int p, const Vec3& lo, const Vec3& hi) const;
  /// 3D point \p q in the flat frame of the window's part: (x, y, height off the mid-surface)
  /// [mm]; NaN if the window is empty.
  Vec3 local(const Window& w, const Vec3& q) const;
  /// Parts whose plate's bounding box (grown by the thickness) meets the box [lo, hi].
  std::vector<int> near(const Vec3& lo, const Vec3& hi) const;
  /// How deep the deepest of 3D points \p qs lies inside the window's part's plate cut as
  /// \p outline: the smaller of its distance to the outline and to the plate's faces, distances
  /// to the outline counted up to 1 mm; <= 0: all outside [mm]. Only the outline's edges near the
  /// points are looked at (inside or not relative to one reference point).
  double deepest_in(const Window& w, const std::vector<Vec3>& qs, const Polygon2& outline) const;

 private:
  struct Frame {
    Vec2 centre2;             // centroid of the flat corners
    Vec3 origin, e1, e2, n;   // 3D = origin + x e1 + y e2 + w n
    Vec3 centre3;             // centroid of the 3D corners
    Polygon2 flat;            // the flat sub-quad
    Vec2 flat_lo, flat_hi;    // its bounding box: a point outside it is not inside it
    /// True when the flat sub-quad holds \p v (its box tested first).
    bool holds(const Vec2& v) const {
      return (flat_lo.array() <= v.array()).all() && (v.array() <= flat_hi.array()).all() &&
             inside(v, flat);
    }
    double radius = 0;        // largest distance of a 3D corner from centre3
    Eigen::Matrix3d inverse;  // 3D offset from origin -> (x, y, w)
  };
  std::vector<std::vector<Frame>> frames_;  // per part
  std::vector<std::array<Vec3, 2>> boxes_;  // per part: 3D bounding box of the plate
  double thickness_;
};

}  // namespace kerfab::border
