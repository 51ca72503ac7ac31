#pragma once
/// \file Pictures of 3D faces drawn with cairo (shared by pictures/ and the assembly steps): an
/// orthographic view of the model, its up axis vertical, turned and tilted, faces flat-shaded
/// (Lambert) and drawn far to near, each followed by its edge strokes.
#include <array>
#include <functional>
#include <vector>

#include "kerfab/core/mesh.h"

struct _cairo;  // cairo_t, from <cairo.h>

namespace kerfab {

using Rgb = std::array<double, 3>;  ///< 0..1

/// A line along a face's side k (corner k to corner k + 1), drawn after the face.
struct SideStroke {
  int side = 0;
  Rgb colour{0, 0, 0};
  double width = 1;      ///< [px]
  double opacity = 1;    ///< [-]
};

struct Face3 {
  std::vector<Vec3> corners;  ///< [mm]
  Rgb fill{0.8, 0.8, 0.8};
  std::vector<SideStroke> sides;
  int tag = -1;  ///< the caller's (e.g. the part it belongs to)
};

struct ViewOptions {
  int up = 1;               ///< the model's up axis: 0 x, 1 y, 2 z
  double azimuth = 0.61;    ///< turn about the up axis [rad] (35 degrees)
  double elevation = 0.17;  ///< tilt towards the viewer [rad] (10 degrees)
};

/// The view of a set of points, fitted into a box of the picture.
class View3 {
 public:
  /// Fits \p points (at least one) into the box at (x, y) of w x h picture units, leaving 5 %.
  View3(const std::vector<Vec3>& points, const ViewOptions& options, double x, double y, double w,
        double h);
  /// Picture position of a model point (y down).
  std::array<double, 2> screen(const Vec3& p) const { return screen_of_turned(turn(p)); }
  /// The model point turned into view coordinates (x right, y depth: larger is farther, z up).
  Vec3 turn(const Vec3& p) const;
  /// Picture position of a point already turned (turn()).
  std::array<double, 2> screen_of_turned(const Vec3& t) const;
  /// Height over width of the points' view (for sizing a picture).
  static double aspect(const std::vector<Vec3>& points, const ViewOptions& options);

 private:
  ViewOptions options_;
  double scale_ = 1, cx_ = 0, cz_ = 0, ox_ = 0, oy_ = 0;
};

/// Draws \p faces into \p cr in \p view: far to near, lit from the upper left front; faces seen
/// from behind are drawn darker.
void draw_faces(_cairo* cr, const View3& view, const std::vector<Face3>& faces);

/// Faces turned, shaded and sorted far to near once, for drawing many pictures of subsets of them
/// in one view (the assembly steps: a picture per step of the parts placed so far).
class FacePainter {
 public:
  FacePainter(const View3& view, const std::vector<Face3>& faces);
  /// The fill of face \p f in this picture, or false to leave it out.
  using Fill = std::function<bool(const Face3& f, Rgb& fill)>;
  /// Draws the faces that \p fill keeps, far to near, each followed by its side strokes (widths
  /// times \p line_scale). Smooth: antialiased, each face stroked with a hairline over the seams
  /// to its neighbours. Flat (for thumbnails of many faces): without antialiasing, so that
  /// neighbours meet without seams and need no hairline; far cheaper, meant to be drawn large
  /// and scaled down.
  void draw(_cairo* cr, const Fill& fill, bool flat = false, double line_scale = 1) const;

 private:
  struct Drawn {
    double depth;
    std::size_t face;
    double shade;
    std::size_t first;  // its corners on the picture, from screen_[first] on
  };
  const std::vector<Face3>& faces_;
  std::vector<Drawn> order_;
  std::vector<std::array<double, 2>> screen_;
};

/// Every corner of \p faces (to fit a view).
std::vector<Vec3> corners_of(const std::vector<Face3>& faces);

}  // namespace kerfab
