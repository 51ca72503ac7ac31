#pragma once
/// \file Pictures of 3D faces drawn with cairo (shared by pictures/ and the assembly steps): an
/// orthographic view of the model, its up axis vertical, turned and tilted, faces flat-shaded
/// (Lambert) and drawn far to near, each followed by its edge strokes.
#include <array>
#include <functional>
#include <vector>

#include "kerfab/core/mesh.h"

struct _cairo;          // cairo_t, from <cairo.h>
struct _cairo_surface;  // cairo_surface_t

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

/// Faces turned, shaded and sorted far to near once, for drawing pictures of subsets of them.
class FacePainter {
 public:
  FacePainter(const View3& view, const std::vector<Face3>& faces);
  /// Draws the faces far to near in their fill colours, antialiased, each stroked with a
  /// hairline over the seams to its neighbours and followed by its side strokes.
  void draw(_cairo* cr) const;

  /// A face as drawn: its place in faces, its depth, its shade (Lambert) and its corners on the
  /// picture, screen()[first] on.
  struct Drawn {
    double depth;
    std::size_t face;
    double shade;
    std::size_t first;
  };
  const std::vector<Drawn>& far_to_near() const { return order_; }
  const std::vector<std::array<double, 2>>& screen() const { return screen_; }
  const std::vector<Face3>& faces() const { return faces_; }

 private:
  const std::vector<Face3>& faces_;
  std::vector<Drawn> order_;
  std::vector<std::array<double, 2>> screen_;
};

/// Pictures of a growing set of faces in one view (the assembly steps: the parts placed so far).
/// Each face and each of its side strokes (as a bar of its width, opaque) is rasterised once,
/// when its tag is added, into a buffer keeping per pixel the last item the painter's algorithm
/// would draw there: the picture of FacePainter without antialiasing, in time proportional to
/// the faces plus the pixels of each picture instead of the faces of each picture (which made
/// the steps grow with the square of the model). Draw it larger and scale down for smooth edges.
/// A side stroke is \p line_scale times its width, but no wider than an eighth of the median
/// face on the picture (at least a quarter of its width): on a model of hundreds of thin strips
/// full-width strokes would cover the faces.
class LayeredPicture {
 public:
  /// w x h pixels.
  LayeredPicture(const FacePainter& painter, int w, int h, double line_scale = 1);
  /// Makes the faces tagged \p tag visible.
  void add(int tag);
  /// Writes the picture into \p image (a w x h image surface, RGB24 or ARGB32): white where no
  /// face is, each face in colour(its tag) times its shade, side strokes in their colour.
  void paint(_cairo_surface* image, const std::function<Rgb(int tag)>& colour) const;

 private:
  struct Item {
    std::size_t drawn;  // into painter.far_to_near()
    int side;           // -1: the face itself; else the face's side stroke
  };
  const FacePainter& painter_;
  int w_, h_;
  double line_scale_;
  double widest_ = 0;  // widest side stroke [px]: an eighth of the median face
  std::vector<Item> items_;                  // in the painter's drawing order
  std::vector<std::vector<int>> by_tag_;     // items per tag
  std::vector<int> top_;                     // per pixel, the last item drawn there, or -1
  void fill_polygon(const std::vector<std::array<double, 2>>& corners, int item);
};

/// Every corner of \p faces (to fit a view).
std::vector<Vec3> corners_of(const std::vector<Face3>& faces);

}  // namespace kerfab
