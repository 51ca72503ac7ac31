#pragma once
/// \file Owning handles for cairo objects and a white raster picture (shared by the writers in
/// output/ that draw with cairo).
#include <cairo.h>

#include <algorithm>
#include <memory>
#include <utility>

namespace kerfab {

using CairoSurface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using CairoContext = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

/// A white RGB picture of \p w x \p h pixels (at least 1 x 1) and a context drawing on it.
inline std::pair<CairoSurface, CairoContext> white_picture(int w, int h) {
  CairoSurface s(cairo_image_surface_create(CAIRO_FORMAT_RGB24, std::max(w, 1), std::max(h, 1)),
                 cairo_surface_destroy);
  CairoContext cr(cairo_create(s.get()), cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  return {std::move(s), std::move(cr)};
}

}  // namespace kerfab
