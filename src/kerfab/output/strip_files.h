#pragma once
/// \file Files of the strips stage: the coloured strip mesh (model/strips.ply) and one OBJ per
/// patch (stages/patches/NNN_3d.obj).
#include <array>
#include <filesystem>

#include "kerfab/kerf/kerf.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

/// A distinct, saturated colour for strip \p id (golden-ratio hue steps), RGB 0..255.
std::array<int, 3> strip_colour(int id);

/// ASCII PLY: vertices (mm), quads with per-face `int strip` and `uchar red green blue`.
/// \throw IoError the file cannot be written.
void write_strips_ply(const Strips& strips, const std::filesystem::path& path);

/// Per sub-quad: kerf cut density [cuts/mm], critical, and its colour (viridis from 0 to the
/// 95th percentile of the non-zero densities, critical faces red), RGB 0..255.
struct FaceDensity {
  std::vector<double> density;
  std::vector<char> critical;
  std::vector<std::array<int, 3>> colour;
};
FaceDensity kerf_density(const Strips& strips, const KerfResult& kerf);

/// ASCII PLY of the strip mesh coloured by kerf cut density (viridis, 0 to the 95th percentile;
/// per-face `float density` in cuts/mm) with critical faces red (`uchar critical`).
/// \throw IoError the file cannot be written.
void write_kerf_density_ply(const Strips& strips, const KerfResult& kerf,
                            const std::filesystem::path& path);

/// OBJ of one patch over its own vertices 2 * ruling + rail (see Patch::local_quads).
/// \throw IoError the file cannot be written.
void write_patch_obj(const Strips& strips, int patch, const std::filesystem::path& path);

/// OBJ of one flattened patch: the same vertices (z = 0) and faces as write_patch_obj.
/// \throw IoError the file cannot be written.
void write_patch_flat_obj(const Strips& strips, int patch, const std::vector<Vec2>& points,
                          const std::filesystem::path& path);

}  // namespace kerfab
