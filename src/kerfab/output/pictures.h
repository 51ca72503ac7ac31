#pragma once
/// \file Pictures of a run, drawn by kerfab itself (cairo PNG), into DIR/pictures/:
/// bending.png (the quad mesh, bendable edges red), strips.png (each part in its own colour),
/// kerf_density.png (cuts per mm, viridis; critical regions red), patches.png (the six largest
/// flattened patches: outlines red, rulings grey) and parts.png (the three parts with the most
/// teeth as the laser cuts them: path red, kerf cuts dark, teeth blue). Each is written when the
/// stages it shows ran.
#include <filesystem>

#include "kerfab/output/render3d.h"
#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

struct PictureOptions {
  ViewOptions view;       ///< of the 3D pictures
  int width_3d = 800;     ///< [px]
  int width_flat = 1000;  ///< [px]
};

/// Writes the pictures into \p dir (created). \throw IoError a file cannot be written.
void write_pictures(const RunResult& run, const PictureOptions& options,
                    const std::filesystem::path& dir);

/// The strip mesh as faces, each part in its own colour (strip_colour), part borders dark and
/// inner edges faint; \p colour overrides the fill per sub-quad when not empty.
std::vector<Face3> strip_faces(const Strips& strips, const std::vector<Rgb>& colour = {});

/// The same with the sub-quads of each coarse quad merged into one polygon (about a quarter of
/// the faces, for small pictures), part borders dark; each face tagged with its part.
std::vector<Face3> coarse_strip_faces(const Strips& strips);

}  // namespace kerfab
