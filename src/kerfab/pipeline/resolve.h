#pragma once
/// \file Buildable by construction: the loop that removes critical kerf regions (stretches the
/// laser cannot make bendable enough in the chosen material) by changing the layout where they
/// are, then rebuilding. The paper leaves these to the user (its limitation 4.1); here each
/// region escalates through the least costly changes that apply, in this order:
///   1. split the strip at the sharpest fold between two of its quads there: a joint takes that
///      fold (one more part, no loss of fidelity); a part that fell apart when cut (the mitres of
///      two sharp folds meeting across it) is split where it came apart, so that a piece it lost
///      that a maker could handle becomes a part of its own;
///   2. merge the strip sideways with an aligned neighbour (paper Sec. 3.5): longer beams need
///      fewer cuts; the inner rail moves onto the straight rulings (fidelity loss measured first
///      and bounded);
///   3. re-solve the bending program with the region's bending edges forced stiff: the strips
///      there turn the other way;
///   4. planar facets: every edge of the region's quads stiff, split at every fold: flat parts
///      joined by box joints.
/// What no change resolves is reported with the smallest model size (and the thinnest material)
/// at which it would need none.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "kerfab/bending/bending.h"
#include "kerfab/core/guidance.h"
#include "kerfab/input/prepare.h"
#include "kerfab/joints/joints.h"
#include "kerfab/kerf/kerf.h"
#include "kerfab/pipeline/cuttable_patches.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

struct ResolveOptions {
  bool enabled = true;  ///< false: only report critical regions (the paper's behaviour)
  int max_rounds = 16;  ///< rounds at most (each up to three rebuilds) [-], >= 1
  /// No round, and no region's facets, start once the loop has run this long; it ends with
  /// the best build it saw, the regions left listed as unresolved [s], > 0. (A round is one to
  /// three rebuilds: about 0.5 s on the demo, 10-40 s at 4000-6000 quads; so the loop may run
  /// over by one rebuild, and a region's facets stop growing once the limit is reached.)
  double time_limit = 120;
  double max_merge_deviation = 0.004;  ///< a merge may move inner rail vertices by at most this
                                       ///< fraction of the target's bbox diagonal [-]
  double facet_flatness = 0.0035;      ///< quads join one flat facet while their corners stay
                                       ///< this close to its plane, as a fraction of the
                                       ///< target's bbox diagonal [-]
  double min_part_area = 50;           ///< parts smaller than this once cut are changed (a facet
                                       ///< takes in its flattest neighbours until it is not)
                                       ///< [mm^2]
  double min_part_width = 3;           ///< parts nowhere this wide are changed too, and slivers
                                       ///< narrower than this across left out (--min-part-width)
                                       ///< [mm]
};

/// Everything the loop rebuilds, as one consistent set.
struct PartsBuild {
  BendingResult bending;
  Strips strips;
  CuttablePatches flat;
  Joints joints;
  KerfResult kerf;
};

/// What the loop did to one critical region.
struct RegionChange {
  Vec3 centre;                ///< where on the model [mm]
  std::vector<int> quads;     ///< quad-mesh faces of the region
  std::string action;         ///< "split", "merge", "restiffen", "facets", "outline" (a facet
                              ///< cut along its outline alone, flatten_facet_by_outline), "omit"
                              ///< (the part left out), "plate" (a flat panel of the model cut
                              ///< as one plate, before the loop), or "unresolved"
  double spacing = 0;         ///< the beam spacing the bend needed there before [mm]
  double stress_ratio = 0;    ///< its largest beam stress over the allowed stress, before [-]
  double size_factor = 1;     ///< the model scale at which the region would need no change [-]
  double local_distance = 0;  ///< after the change: largest distance of the region's strip
                              ///< vertices to the target; for "omit", of its surface to the
                              ///< parts kept [mm]
  std::string reason;         ///< why an "unresolved" region stays (the bend or the part size),
                              ///< why an "omit" part was left out, or an "outline" facet cut so
};

/// A material preset and the smallest model size at which none of the regions would need a
/// change in it.
struct MaterialSize {
  std::string material;
  double thickness = 0;  ///< [mm]
  double size_mm = 0;    ///< smallest largest bbox side [mm]
};

struct ResolveResult {
  int rounds = 0;             ///< rebuilds made
  bool time_limited = false;  ///< the loop stopped at its time limit with regions left
  double seconds = 0;         ///< the loop's wall time [s]
  int critical_before = 0;    ///< critical regions of the first build
  int critical_after = 0;     ///< left at the end (listed in kerf.critical)
  /// Of those, regions where a cut the bend needs does not fit the part (CriticalCause::
  /// kTooNarrow), and the size from which their cuts fit, as far as known (the largest of
  /// their fit factors) [mm]; 0: unknown.
  int narrow_after = 0;
  double narrow_size_mm = 0;
  int small_parts_after = 0;  ///< parts still too small or narrow to handle at the end
  /// Of those, the parts that flatten distorted (an inverted quad, an outline crossing itself, a
  /// corner off by the flattening's limit): their quads' angles do not change with the model's
  /// size, so no --size cures them (they count in no size factor).
  int distorted_parts_after = 0;
  /// Of the others, parts that fell apart at their slots although cut back all round by their
  /// deepest cut-back they are one piece at this size (a tip broke off between two slots): no
  /// size is known for them (size factor 0).
  int unsized_parts_after = 0;
  std::vector<int> unresolved_parts;  ///< which (the parts of the final build), ascending
  int parts_before = 0, parts_after = 0;
  double minutes_before = 0, minutes_after = 0;  ///< estimated cutting time [min]
  std::vector<RegionChange> changes;             ///< one per region changed or left unresolved
  Guidance added;              ///< the guidance the loop added (stiff edges, splits, merges)
  double current_size_mm = 0;  ///< the model's largest bbox side as run [mm]
  double min_size_mm = 0;      ///< smallest size at which no region would need a change [mm]
  /// Smallest size at which every part left too small or narrow, or left out with nothing of it
  /// left once cut, would be one a maker can handle, as far as known (the largest of their size
  /// factors) [mm]; 0: none, or unknown.
  double small_parts_size_mm = 0;
  int gone_parts = 0;  ///< parts left out ("omit") because their joints left nothing of them
  /// Smallest size at which those would hold, as far as known [mm]; 0: none, or unknown.
  double gone_parts_size_mm = 0;
  std::vector<MaterialSize> materials;  ///< the same per material preset, thinnest first
};

/// The stage options the loop rebuilds with.
struct PartsOptions {
  BendingOptions bending;
  StripsOptions strips;
  FlattenOptions flatten;
  LayoutOptions usable;  ///< the sheet less its margins (parts must fit)
  Material material;
  Machine machine;
  JointOptions joints;
  KerfOptions kerf;
};

/// What a run's PartsMemo may hold with \p max_memory_mb for the whole run (0: no budget): a
/// thirty-second of it, between 80 MB (or an eighth of a smaller budget) and 1 GB [bytes]. A
/// rebuild of Spot at 4000 mm draws about 100 MB of outlines; the demo's fewer than 20.
std::size_t parts_memo_bytes(double max_memory_mb);

/// What earlier builds made and later ones may reuse where it is the same: part outlines and
/// patches' kerf cuts (the results never depend on it).
struct PartsMemo {
  /// \p max_bytes: what the two may hold together, three fifths of it outlines [bytes].
  explicit PartsMemo(std::size_t max_bytes = parts_memo_bytes(0))
      : outlines(max_bytes / 5 * 3), kerf(max_bytes / 5 * 2) {}
  OutlineMemo outlines;
  KerfMemo kerf;
};

/// The parts of \p b a maker cannot handle: less than \p min_area as cut [mm^2], nowhere \p
/// min_width wide [mm], fallen apart when cut, or flattened inverted, crossing itself or with a
/// corner \p max_angle_error [rad] or more off (what the loop changes), ascending.
std::vector<int> parts_too_small(const PartsBuild& b, double min_area, double min_width,
                                 double max_angle_error);

/// The parts cut from \p build's flattening: the patches \p guidance omits left out (omit_patches),
/// then joints and kerf cuts. \p memo as in build_parts.
void cut_parts(PartsBuild& build, const Guidance& guidance, const PartsOptions& options,
               PartsMemo* memo);

/// Bending (forced edges of \p guidance added), strips (its splits and merges added),
/// flattening until cuttable, and the parts cut from it (cut_parts). \p reuse: a bending result to
/// keep when \p guidance forces no edge beyond the options'. \p memo: outlines and cuts of earlier
/// builds to reuse where they are the same.
PartsBuild build_parts(const PreparedInput& input, const PartsOptions& options,
                       const Guidance& guidance, const BendingResult* reuse = nullptr,
                       PartsMemo* memo = nullptr);

/// One line per round of the loop (what is left to resolve), for a long run's progress.
using ResolveProgress = std::function<void(const std::string&)>;

/// Rebuilds with more guidance until no critical region remains or nothing more applies;
/// \p build holds the first build (made with \p options) and is replaced by the final one.
/// \p memo: outlines and cuts made before (by the first build's joints and kerf stages),
/// reused by the rebuilds where they are the same; without one the loop keeps its own.
ResolveResult resolve_critical_regions(PartsBuild& build, const PreparedInput& input,
                                       const PartsOptions& options, const ResolveOptions& resolve,
                                       const ResolveProgress& progress = {},
                                       PartsMemo* memo = nullptr);

}  // namespace kerfab
