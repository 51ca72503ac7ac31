#pragma once
/// \file Adaptive kerf cuts (paper Sec. 3.4): per internal ruling the number of beams the strip
/// needs to twist by its fold there without exceeding the material's shear yield (torsion of
/// rectangular beams, paper Eq. 5-17 with the sign of Eq. 7/16 corrected), smoothed along the
/// strip, integrated, and turned into alternating straight cuts across the flattened part.
#include <optional>
#include <string>
#include <vector>

#include "kerfab/core/material.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/joints/joints.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

struct KerfOptions {
  double smoothing = 10.0;       ///< width of the tent kernel smoothing n_e along the strip [mm]
  double min_cut_spacing = 0.9;  ///< closer cuts are a critical region [mm], > 0
  double bridge = 2.0;           ///< material left at alternating ends of each cut [mm], >= 0
  double margin = 1.0;           ///< cuts keep this far from the part outline [mm], >= 0
  std::optional<int> constant_cuts_per_quad;  ///< set: N cuts per coarse quad (baseline)
};

/// Number of beams a segment of width \p width needs so that twisting by \p angle over beams of
/// length \p length and height \p thickness stays at the yield stress (paper Eq. 7-8, positive
/// root): n = sqrt(z), z = A h^2/8 + sqrt(A^2 h^4/64 + A w^2/4), A = (angle G / (length tau))^2.
double beams_needed(double angle, double width, double length, double thickness,
                    double shear_over_yield);

struct KerfCut {
  Vec2 a, b;            ///< the cut segment in the patch's flattened frame [mm]
  double position = 0;  ///< along the strip [mm]
  int face = -1;        ///< sub-quad (index into Patch::faces) it crosses
};

/// A stretch of a strip where consecutive cuts are closer than the allowed spacing.
struct CriticalRegion {
  int patch = -1;
  double start = 0, end = 0;  ///< along the strip, first and last cut of the stretch [mm]
  double spacing = 0;         ///< smallest distance between two of its cuts [mm]
  int cuts = 0;               ///< cuts in the stretch
};

struct PatchKerf {
  std::vector<double> beams;      ///< n_e per internal ruling (after smoothing)
  std::vector<double> positions;  ///< along the strip, per internal ruling [mm]
  std::vector<KerfCut> cuts;
  double min_spacing = 0;            ///< smallest distance between neighbouring cuts [mm] (0: < 2)
  std::vector<double> face_density;  ///< cuts per mm at each sub-quad: 1 / spacing of the cuts
                                     ///< around its middle (0 outside the first and last cut)
  std::vector<char> face_critical;   ///< sub-quad holds a critical region
};

/// What the laser has to do: the parts' outlines and the kerf cuts, and how long it takes.
struct CuttingEstimate {
  double outline_length = 0;  ///< all parts' laser paths [mm]
  double kerf_length = 0;     ///< all kerf cuts [mm]
  int paths = 0;              ///< separate cut paths: kerf cuts and outlines
  double minutes = 0;         ///< estimated cutting time [min] (cutting_minutes)
  double total_length() const { return outline_length + kerf_length; }
};

struct KerfResult {
  std::vector<PatchKerf> patches;
  std::vector<CriticalRegion> critical;
  std::vector<int> quad_cuts;  ///< cuts per coarse quad
  int max_cuts_per_quad = 0;   ///< the constant density that would match the tightest quad
  int cuts = 0;
  double cut_length = 0;    ///< [mm]
  CuttingEstimate cutting;  ///< outlines (from the joints) and kerf cuts on \p machine
};

/// Places the kerf cuts of every patch in \p material and estimates the cutting time on
/// \p machine. \throw InvalidInput options or material out of range.
KerfResult place_kerf_cuts(const Strips& strips, const Flattening& flat, const Joints& joints,
                           const Material& material, const Machine& machine,
                           const KerfOptions& options);

}  // namespace kerfab
