#pragma once
/// \file The sheet material and the laser: the one home of the thickness and the kerf width,
/// read by every stage that needs them (joints, kerf cuts, cutting time).
#include <string>
#include <vector>

namespace kerfab {

/// Sheet material. Lengths mm, stresses MPa.
struct Material {
  std::string name = "mdf";
  double thickness = 3.0;       ///< h [mm], >= 0 (0: paper)
  double shear_modulus = 1600;  ///< G [MPa], > 0
  double yield_strength = 18;   ///< tau_yield [MPa], > 0; infinity: never yields (paper)
  double safety = 1.125;        ///< divides tau_yield [-], >= 1 (MDF: G / (tau/s) = 100)
};

/// Presets: "mdf" (3 mm, G 1.6 GPa, tau 18 MPa, G/tau_eff = 100 as in the paper), "mdf2" (the
/// same board 2 mm thick), "plywood" (4 mm birch, G 620 MPa, tau 9.5 MPa, safety 1.5),
/// "plywood3" (the same 3 mm thick), "paper" (h = 0, tau = infinity: no cuts).
/// \throw InvalidInput unknown name.
Material material_preset(const std::string& name);

/// The sheet presets (not paper), thinnest first: mdf2, plywood3, mdf, plywood.
std::vector<Material> sheet_presets();

/// The laser cutter: its kerf, and a simple model for time estimates (constant cutting speed
/// plus a fixed overhead per separate cut: pierce, travel, acceleration).
struct Machine {
  double kerf_width = 0.15;  ///< width of the laser cut [mm], >= 0; outlines grow by half of it
  double speed = 15.0;       ///< cutting speed in 3 mm MDF [mm/s], > 0 (40-60 W CO2: 10-20)
  double per_cut = 0.3;      ///< overhead per separate cut path [s], >= 0
};

/// Minutes to cut \p length millimetres in \p paths separate paths.
double cutting_minutes(double length, int paths, const Machine& machine);

}  // namespace kerfab
