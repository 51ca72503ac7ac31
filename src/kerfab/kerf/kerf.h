#pragma once
/// \file Adaptive kerf cuts (paper Sec. 3.4), with width, twist and spacing referring to one
/// and the same stretch of strip (derivation: docs/kerf-cuts.md). Alternating cuts turn the
/// strip into beams that twist; a beam of width w between two cuts, twisted by the normal
/// rotation phi between them, carries tau = G phi r / l with r = sqrt(h^2 + w^2) / 2 (paper
/// Eq. 5, 10) and l the strip's width there. Cuts are placed along the strip so that every beam
/// stays within tau_yield / safety, with as few cuts as that allows and the largest stress as
/// low as that count allows; where the bend would need cuts closer than the laser can make, or
/// the strip is too narrow for a cut, the stretch is a critical region.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "kerfab/core/material.h"
#include "kerfab/core/memo.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/joints/joints.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

struct KerfOptions {
  /// Width of the tent kernel averaging the twist rate along the strip [mm], >= 0. The folds
  /// between sub-quads sample the target's facets (a rail crossing a facet edge kinks by the
  /// facet's dihedral), so the rate is averaged over that scale; unset: twice the target's
  /// facet size (Strips::target_facet_size), so fine targets keep their true peaks (a kernel
  /// wider than needed lowers them: 5 mm on the elliptic tube of the tests gives 0.4 % less).
  std::optional<double> smoothing;
  double min_cut_spacing = 0.9;  ///< no two cuts closer: the laser's limit [mm], > 0
  double min_cut_length = 2.0;   ///< shorter cuts are not made [mm], > 0
  double bridge = 2.0;           ///< material left at alternating ends of each cut [mm], >= 0
  double margin = 1.0;           ///< cuts keep this far from the part outline [mm], >= 0
  std::optional<int> constant_cuts_per_quad;  ///< set: N cuts per coarse quad (baseline)
};

/// The smoothing kernel's width as used [mm]: KerfOptions::smoothing, or twice the target's
/// facet size.
double smoothing_width(const Strips& strips, const KerfOptions& options);

/// Shear stress at the surface of a beam of width \p width, height \p thickness and length
/// \p length twisted by \p twist (paper Eq. 5 and 10): G phi r / l, r = sqrt(h^2 + w^2) / 2
/// [MPa with G in MPa].
double beam_stress(double twist, double width, double length, double thickness,
                   double shear_modulus);

/// Number of beams a stretch of strip \p width wide needs so that twisting by \p angle (over
/// that same stretch) with beams of length \p length and height \p thickness stays at the yield
/// stress (paper Eq. 7-8, positive root): n = sqrt(z), z = A h^2/8 + sqrt(A^2 h^4/64 + A w^2/4),
/// A = (angle G / (length tau))^2.
double beams_needed(double angle, double width, double length, double thickness,
                    double shear_over_yield);

struct KerfCut {
  Vec2 a, b;            ///< the cut segment in the patch's flattened frame [mm]
  double position = 0;  ///< along the strip [mm]
  int face = -1;        ///< sub-quad (index into Patch::faces) it crosses
};

/// Why a stretch cannot be cut bendable enough.
enum class CriticalCause {
  kTooDense,   ///< the bend needs beams narrower than the minimum cut spacing (a larger model,
               ///< a thinner sheet or longer beams cure it)
  kTooNarrow,  ///< a cut the bend needs does not fit the part there (the strip is too narrow)
  kFan,        ///< the bend could be cut, but the cut lines converge across the strip and
               ///< their narrow ends would come closer than the minimum spacing
};

std::string to_string(CriticalCause cause);

/// A stretch of a strip that the cuts cannot make bendable enough in this material. Cuts there
/// keep the minimum spacing and the minimum length; the beams are overstressed.
struct CriticalRegion {
  int patch = -1;
  double start = 0, end = 0;  ///< along the strip [mm]
  double spacing = 0;         ///< narrowest beam the bend needs there [mm]
  int cuts = 0;               ///< cuts placed in the stretch
  double stress_ratio = 0;    ///< largest beam stress there over the allowed stress [-], > 1
  CriticalCause cause = CriticalCause::kTooDense;
  /// kTooNarrow: the factor on the model's size from which the cuts skipped there fit, to first
  /// order (the strip's width grows with the model; its joints' depths, the margins, the
  /// bridge and the shortest cut do not) [-]; 0: unknown (a cut's middle outside the part)
  double fit_factor = 0;
  std::vector<int> quads;      ///< quad-mesh faces under the stretch (every row)
  Vec3 centre = Vec3::Zero();  ///< middle of the stretch on the 3D strip [mm]
};

struct PatchKerf {
  std::vector<double> twist;  ///< per internal ruling: the fold it takes (after smoothing) [rad]
  std::vector<double> positions;  ///< along the strip, per internal ruling [mm]
  std::vector<KerfCut> cuts;
  double min_spacing = 0;    ///< smallest distance between neighbouring cuts [mm] (0: < 2)
  double stress_ratio = 0;   ///< largest beam stress over the allowed stress [-]
  double tightest_bend = 0;  ///< smallest 2 l / kappa over its stretches (l its width, kappa
                             ///< its twist per length) [mm^2]; 0: it does not bend
  std::vector<double> face_density;  ///< cuts per mm at each sub-quad: 1 / spacing of the cuts
                                     ///< around its middle (0 outside the first and last cut)
  std::vector<char> face_critical;   ///< sub-quad holds a critical region
  int skipped = 0;                   ///< planned cuts that did not fit the part (too narrow there)
  /// Of those, the ones that would fit with the default --bridge, --kerf-margin and
  /// --min-cut-length (KerfOptions{}): left out by the options asked, not by the shape
  int skipped_by_options = 0;
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
  int skipped = 0;             ///< planned cuts that did not fit their parts (PatchKerf::skipped)
  int skipped_by_options = 0;  ///< of which the defaults would have fitted
  double cut_length = 0;       ///< [mm]
  double smoothing = 0;        ///< width of the smoothing kernel as used [mm]
  /// The tightest bend of all strips, as 2 l / kappa [mm^2] (0: nothing bends). Beams at
  /// spacing d hold in a material of thickness h and G / tau_eff = g where
  /// g d sqrt(h^2 + d^2) <= C; scaling the model by s scales C by s^2 (bend_scale()).
  double tightest_bend = 0;
  CuttingEstimate cutting;  ///< outlines (from the joints) and kerf cuts on \p machine
};

/// The smallest scale of the model at which its tightest bend (KerfResult::tightest_bend) needs
/// no beam narrower than \p spacing in \p material [-] (1 when nothing bends).
double bend_scale(double tightest_bend, const Material& material, double spacing);

/// What placing a patch's cuts gave: its cuts and its critical regions (their patch number is
/// the caller's to set).
struct PatchPlacement {
  PatchKerf kerf;
  std::vector<CriticalRegion> critical;
  std::size_t bytes() const;
};

/// Patches' cuts placed by earlier place_kerf_cuts calls, for calls on strips that share most
/// patches (the resolve stage rebuilds the whole model many times, changing a few regions each
/// time). A patch's cuts follow from its own sub-quads alone (their 3D corners and how they
/// join), its flattened points and outline, its part's designed outline, the material and the
/// options; where all of these are the same to the bit, the earlier cuts are reused, so the
/// result is identical with or without a memo. It keeps at most `max_bytes` of keys and cuts,
/// the most recently used (Memo); it may be shared between threads.
class KerfMemo : public Memo<PatchPlacement> {
 public:
  explicit KerfMemo(std::size_t max_bytes = std::size_t{32} << 20) : Memo(max_bytes) {}
};

/// Refuses kerf options no cut can be made with: out of range, or a minimum spacing of cuts no
/// wider than the laser's kerf (\p machine: neighbouring cuts would overlap and burn away the
/// beam between them; paper, with no cuts, is not held to it). place_kerf_cuts checks them; a
/// pipeline calls this before any stage runs. \throw InvalidInput naming the option.
void check_kerf_options(const Material& material, const Machine& machine,
                        const KerfOptions& options);

/// Places the kerf cuts of every patch in \p material and estimates the cutting time on
/// \p machine. With a \p memo, patches placed by earlier calls are reused where they are the
/// same (KerfMemo). \throw InvalidInput options or material out of range.
KerfResult place_kerf_cuts(const Strips& strips, const Flattening& flat, const Joints& joints,
                           const Material& material, const Machine& machine,
                           const KerfOptions& options, KerfMemo* memo = nullptr);

}  // namespace kerfab
