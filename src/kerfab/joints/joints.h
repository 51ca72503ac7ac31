#pragma once
/// \file Joints (paper Sec. 3.3, extended): fold angles along every shared border, tooth depths
/// from tooth_offsets(), collision-free joint regions from offset bands of each flattened part
/// (Clipper), interlocking teeth with a phase shared by both sides of a border, laser-kerf
/// compensation, and each part's closed outline. Where the fold is too shallow for box teeth,
/// the teeth become in-plane dovetail tabs (docs/joints.md): longer, with flared sides that lock
/// the two parts in the sheet's plane, and an out-of-plane misfit of at most
/// JointOptions::tab_misfit.
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "kerfab/adapters/polygon_ops.h"
#include "kerfab/core/material.h"
#include "kerfab/core/memo.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/joints/tooth_offsets.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

/// Joint settings; the sheet thickness comes from the Material, the kerf width from the Machine.
struct JointOptions {
  double protrusion = 0.0;       ///< a tooth may leave the mitred shell by this much [mm], >= 0
  double tooth_width = 3.0;      ///< target width of teeth and slots along the border [mm], > 0
  double min_depth = 0.5;        ///< no teeth where tip - slot is below this [mm], >= 0
  double max_tip = 6.0;          ///< longest tooth [mm], > 0 (matters only with a protrusion,
                                 ///< where nearly coplanar parts would get ever longer teeth)
  double sharp_turn = M_PI / 6;  ///< consecutive outline edges turning more than this restrict
                                 ///< each other's teeth [rad]
  double min_feature = 1.0;      ///< tails and slits of the outline narrower than this are
                                 ///< removed (tails cut off, slits widened) [mm], >= 0
  double tab_misfit = 0.3;       ///< where box teeth would be shallower than min_depth, dovetail
                                 ///< tabs whose tip leaves the other part's faces by at most this
                                 ///< [mm], >= 0; 0: no tabs (such borders stay plain)
  double min_part_area = 50;     ///< a part smaller than this as drawn takes the teeth of its
                                 ///< borders instead of their slots where it can (the size a
                                 ///< maker can handle; ResolveOptions::min_part_area) [mm^2], >= 0
  double min_part_width = 3;     ///< so does a part nowhere this wide as drawn (its outline shrunk
                                 ///< by half of it is empty; ResolveOptions::min_part_width) [mm],
                                 ///< >= 0
  /// Short borders between corners that the usual teeth leave bare get a stub tooth checked in
  /// 3D, both parts drawn for each candidate (the costliest step of the stage). False: left
  /// bare; the resolve loop's rebuilds, which look for critical regions and parts too small,
  /// leave them to its final build.
  bool stub_teeth = true;
  // Paper (thickness 0): glue tabs instead of teeth (joints/glue_tabs.h).
  double glue_tab = 6.0;       ///< height of a glue tab, root to edge [mm], >= 0; 0: no glue
                               ///< tabs (plain borders, the paper's emulation)
  bool score_rulings = false;  ///< paper: the rulings that bend by a degree or more are fold
                               ///< lines too (the strip folds there instead of curving); false:
                               ///< those folding more than kCreaseFold (glue_tabs.h) only
};

/// What holds an interval of a border.
enum class JointKind {
  kNone,  ///< plain on both sides
  kBox,   ///< a box tooth (derived offsets, straight sides)
  kTab,   ///< an in-plane dovetail tab (nearly coplanar parts)
  kGlue,  ///< paper: a glue tab, folded under the other part and glued to its back
};
const char* to_string(JointKind kind);

/// Flare of a dovetail tab's sides: each side leans outward by this much per millimetre of depth
/// (1:6, the woodworker's dovetail slope for hardwood). Narrower where the tab would otherwise be
/// less than two thirds of its width at the root.
inline constexpr double kTabFlare = 1.0 / 6.0;

/// One tooth or slot interval of a border piece (a coarse edge shared by two patch sides).
struct JointInterval {
  double s0 = 0, s1 = 0;  ///< arc length along the piece from its common end [mm]
  int owner = -1;         ///< side (0 or 1) that has the tooth; -1: no tooth (both cut plain)
  JointKind kind = JointKind::kNone;  ///< kind of the tooth (kNone exactly when owner < 0)
  double fold = 0;                    ///< fold angle at the interval's middle [rad]
  ToothOffsets offsets;               ///< tip and slot for that fold
  double plain = 0;                   ///< offset of both sides where there is no tooth [mm]
};

struct BorderJoint {
  int edge = -1;                       ///< its first coarse edge
  std::vector<int> edges;              ///< all its coarse edges (consecutive coarse edges along
                                       ///< which the same two part sides meet), ascending
  std::array<int, 2> patches{-1, -1};  ///< the two sides (may be one patch twice)
  double length = 0;                   ///< 3D length [mm]
  std::vector<JointInterval> intervals;
  int teeth = 0;    ///< box teeth and tabs
  int tabs = 0;     ///< of which dovetail tabs
  int glue = 0;     ///< paper: glue tabs
  int blocked = 0;  ///< intervals without teeth because of collisions
  int shallow = 0;  ///< intervals without teeth because tip - slot < min_depth
  /// For a border left without a joint: its widest stretch clear of the joint bands of its
  /// parts' other borders at its corners [mm] (a tooth needs 1 mm and both parts whole); -1 for
  /// the others
  double free_room = -1;
  /// A stub with no joint of its own, no longer than two tooth widths, whose two parts are joined
  /// to each other at one of its ends by the joints of the parts there: that chain of parts,
  /// from patches[0] to patches[1] (join_stubs_at_corners, joints/corners.h); else empty
  std::vector<int> joined_through;
  /// A border of two to four tooth widths with no joint of its own, whose two parts are so
  /// joined at both of its ends (every point of it within two tooth widths of one): the chain at
  /// its second end (border::piece_ends), joined_through the one at its first; else empty
  std::vector<int> joined_through_far;
  /// "box", "tab", "box+tab", "glue", "corner" (a stub located and held by its parts' joints at
  /// one of its ends, or a short border at both, joined_through) or "none" (nothing locates or
  /// holds the two parts)
  std::string kind() const;
};

/// Where two neighbouring tab intervals of one border meet, the line between the two parts leans
/// (dovetail): in the frame of the part whose tab is on the lower-s side, its contour runs
/// u = s + slope * v - clearance / 2 (u along the border, v outward), the mate's
/// u = s + slope * v + clearance / 2 (docs/joints.md).
struct TabFlare {
  double s = 0;          ///< arc length of the boundary along the border [mm]
  double slope = 0;      ///< lean of the line [mm per mm of depth]
  double clearance = 0;  ///< gap between the two parts' lines that keeps them apart at the
                         ///< fold in 3D [mm]
};

/// Where a part's contour leaves its border line: a tooth (outward) or a cut-back (slot or plain).
struct JointSpan {
  int border = -1;    ///< index into Joints::borders
  int interval = -1;  ///< index into that border's intervals
  double length = 0;  ///< length along the flattened border line [mm]
  double offset = 0;  ///< tip (> 0), slot or plain offset (< 0) [mm]
  bool tooth = false;
  JointKind kind = JointKind::kNone;  ///< of a tooth
  Polygon2 region;            ///< for a tooth: the part of it beyond the border line (with a
                              ///< tab's flared sides)
  Vec2 from{0, 0}, to{0, 0};  ///< the stretch of the border line it spans [mm]
  Vec2 normal{0, 0};          ///< outward unit normal of the border there
};

/// A line the part is folded along (paper: scored or creased before assembly), in the part's
/// flattened frame. Seen from the printed side (the outside of the model), a mountain fold's
/// crease points toward the viewer (the surface is convex there), a valley fold's away.
struct FoldLine {
  /// A glue tab's root, a ruling, or the diagonal of a twisted quad (FlattenOptions::
  /// crease_twisted).
  enum class Kind { kTabRoot, kRuling, kDiagonal };
  Kind kind = Kind::kTabRoot;
  std::vector<Vec2> points;  ///< polyline [mm]
  double angle = 0;          ///< signed fold angle [rad]: > 0 mountain, < 0 valley
  int border = -1;           ///< a tab root: index into Joints::borders
  bool mountain() const { return angle > 0; }
};

struct PartOutline {
  Polygon2 designed;  ///< closed outline with teeth, counter-clockwise [mm], in the patch's
                      ///< flattened frame
  Polygon2 cut;       ///< the same grown by half the kerf width: the path the laser follows
  std::vector<JointSpan> spans;  ///< every stretch of joint contour (a tooth across two outline
                                 ///< edges gives two spans)
  bool repaired = false;  ///< the Booleans or the removal of thin features split the part: only
                          ///< its largest piece is here (the resolve stage rebuilds such parts)
  std::vector<Polygon2> lost;   ///< of a repaired part: the pieces it lost, in the same frame [mm]
  std::vector<FoldLine> folds;  ///< paper: glue-tab roots, and rulings when asked
};

struct Joints {
  std::vector<BorderJoint> borders;
  std::vector<PartOutline> parts;             ///< per patch
  std::vector<std::vector<TabFlare>> flares;  ///< per border: its leaning boundaries
  int teeth = 0;                              ///< box teeth and tabs
  int tabs = 0;                               ///< of which dovetail tabs
  int glue_tabs = 0;                          ///< paper: glue tabs
  double border_length = 0;                   ///< total length of shared borders [mm]
  double toothed_length = 0;                  ///< of which covered by teeth, tabs or glue tabs [mm]
  double tab_length = 0;                      ///< of which by tabs [mm]
  double glue_length = 0;                     ///< of which by glue tabs (their roots) [mm]
  int borders_without_joint = 0;    ///< border pieces with no tooth, tab or glue tab and not
                                    ///< joined at a corner either (kind() "none")
  int stubs_joined_at_corners = 0;  ///< stubs without a joint of their own that their parts'
                                    ///< joints at one of their ends hold (kind() "corner")
  int repaired_parts = 0;
  /// Parts whose outline still narrows to less than JointOptions::min_feature between two of its
  /// pieces (an opening by half that width falls in two there): what hangs on such a neck (a
  /// tooth, a corner) breaks off or burns away. The thin-neck pass makes the joints there plain
  /// where that leaves the parts better; these are the ones it could not mend. Empty in a draft
  /// (no thin-neck pass there, and the resolve loop does not read them).
  std::vector<int> thin_neck_parts;
  /// Parts that keep a slit narrower than JointOptions::min_feature as the laser cuts them
  /// (narrow_slits_as_cut): one the outline cleanup could not widen (where that would cut the part
  /// in two, or into a tooth beside it, or a tapering one still narrow at its end after the last
  /// widening). Empty in a draft.
  std::vector<int> slit_parts;
  double lost_area = 0;           ///< of the pieces the parts that fell apart lost [mm^2]
  double largest_lost_piece = 0;  ///< the largest such piece [mm^2]
  /// Made without stub teeth (JointOptions::stub_teeth false): a draft the resolve loop looks
  /// at, not the joints to cut.
  bool draft = false;
};

/// What drawing an outline gave, apart from its spans (which name that call's borders).
struct OutlineDrawing {
  Polygon2 designed, cut;
  bool repaired = false;
  std::vector<Polygon2> lost;  ///< pieces the part lost, if it fell apart
  std::size_t bytes() const;
};

/// What one check on a drawn part found: polygons (thin necks, an outline) or positions in a
/// list (bitten teeth).
struct OutlineCheck {
  std::vector<Polygon2> polygons;
  std::vector<int> positions;
  std::size_t bytes() const;
};

/// Part outlines drawn by earlier make_joints calls, for calls on strips that share most parts
/// (the resolve stage rebuilds the whole model many times, changing a few regions each time). A
/// part's outline is drawn from its body, its teeth and its cut-backs alone (with the options
/// and the kerf width), so where all of these are the same to the bit the earlier drawing is
/// reused: the joints come out identical with or without a memo. It keeps at most `max_bytes`
/// of keys and drawings, the most recently used (Memo); it may be shared between threads.
class OutlineMemo : public Memo<OutlineDrawing> {
 public:
  explicit OutlineMemo(std::size_t max_bytes = std::size_t{48} << 20)
      : Memo(max_bytes), checks(max_bytes / 4) {}
  /// What the checks on a drawn part found (its thin necks, the teeth its cut-backs bite, its
  /// outline without hanging corners), keyed likewise by everything they read; hits() and
  /// misses() above count the drawings alone.
  Memo<OutlineCheck> checks;
};

/// The thickest sheet kerfab cuts: a laser cuts MDF and plywood up to about this [mm].
inline constexpr double kMaxThickness = 25.0;

/// Refuses options no joint can be made with: out of range, a sheet thicker than kMaxThickness,
/// a protrusion or tab misfit larger than the sheet is thick, a minimum tooth depth deeper than
/// any box tooth of the sheet. make_joints checks them; a pipeline calls this before any stage
/// runs. \throw InvalidInput naming the option.
void check_joint_options(const Material& material, const Machine& machine,
                         const JointOptions& options);

/// Builds the joints of every shared border and the outline of every part, for sheets of
/// \p material (its thickness) cut on \p machine (outlines grow by half its kerf width). Paper
/// (thickness 0) gets glue tabs (make_glue_tabs) unless JointOptions::glue_tab is 0. With a
/// \p memo, outlines drawn by earlier calls are reused where they are the same (OutlineMemo).
/// \pre \p flat was computed from \p strips. \throw InvalidInput options out of range.
Joints make_joints(const Strips& strips, const Flattening& flat, const Material& material,
                   const Machine& machine, const JointOptions& options,
                   OutlineMemo* memo = nullptr);

/// Two parts folded more than this at their border lie back to back: the shape there is thinner
/// than two sheets, and their mitres cut both back by several thicknesses [rad].
inline constexpr double kFoldBackAngle = 150.0 * M_PI / 180.0;

/// Folds sharper than this are joined as if they were this sharp [rad]: two parts folded back
/// onto each other (only where a strip's rail collapses to a point) would need a cut-back
/// growing without bound; at 170 degrees it is h/2 tan(85 deg) = 5.7 h.
inline constexpr double kMaxJointFold = 170.0 * M_PI / 180.0;

/// The tooth regions \p teeth but those whose material in \p outline the opening by half the
/// smallest feature (\p opened) takes all of: such a tooth is narrower than the smallest feature
/// everywhere, a tail the laser burns away like any other, not a tooth the outline cleanup keeps
/// (demosthenes from its triangles at 250 mm: an L of tooth material 0.08 mm wide and 1.8 mm
/// long, what two thin tooth rectangles left round the corner of a tail the cleanup cut off;
/// the auditor found the laser path passing within 0.5 mm of itself there).
std::vector<Polygon2> teeth_kept_by_opening(const Polygon2& outline,
                                            const std::vector<Polygon2>& opened,
                                            std::vector<Polygon2> teeth);

/// Tooth material nowhere thicker than this share of the smallest feature is a sliver
/// wherever it hangs more than half that feature from the rest (tooth_slivers) [-]; thicker,
/// only where it reaches a whole feature, as the sheet auditor's tails do. spot_quadrangulated
/// at 200 mm: two tooth rectangles 0.1 and 0.16 mm thick hanging 0.9 mm over the mouth of a
/// notch, 0.25 mm apart, the laser path into the notch passing within 0.1 mm of itself. A
/// shallow box tooth is thicker (Spot's at 250 mm down to 0.29 mm, one hanging 0.7 mm past its
/// part's corner, and filling its slot with that).
inline constexpr double kSliverThickness = 0.2;

/// The tooth material among \p taken, what an opening by half \p min_feature (\p opened) takes
/// from an outline, in the pieces that reach farther than \p min_feature from the rest or hold
/// more than its square [mm, mm2], and, nearer, where it is thinner than kSliverThickness of
/// \p min_feature and hangs more than half of it from the rest: a sliver of a tooth (where a
/// cut-back at a corner narrowed it, or where a tooth's rectangle runs over a notch) that the
/// laser burns away or that breaks off. The outline cleanup keeps teeth whole otherwise (a
/// tooth fills its mate's slot); without such a sliver the tooth still does, less that corner.
/// The rounding of a tooth's corner of 40 degrees or more is no sliver.
std::vector<Polygon2> tooth_slivers(const std::vector<Polygon2>& taken,
                                    const std::vector<Polygon2>& opened,
                                    const std::vector<Polygon2>& teeth, double min_feature);

/// True when some vertex of \p piece (\p along_edges: some point of its edges, to within r/8)
/// lies farther than \p r from the boundary of \p region [mm]: a piece an opening by half the
/// smallest feature takes away is a feature (a tail, a sliver) where it reaches beyond that
/// feature, not the rounding of a corner; so is what a closing fills (a slit), looked at along
/// its edges, which may run far from the rest between corners that lie by it.
bool reaches_beyond(const Polygon2& piece, const std::vector<Polygon2>& region, double r,
                    bool along_edges = false);

/// The regions to cut away from \p outline so that no slit is narrower than \p min_feature [mm]:
/// what a closing by half that width fills and that reaches more than half of it from the rest,
/// grown by what it lacks on each side, never into \p teeth (counter-clockwise regions; their
/// slots are cut to their width). Where a tooth stops the growth on one side, the other side
/// gives all the slit lacks. One step, by what a slit lacks on average: a slit that tapers can
/// keep its end under the width, so the outline cleanup applies it again until it returns none.
/// A widening that would cut the part in two (two pieces larger than \p split_area [mm^2] left)
/// is not made: that slit stays, and narrow_slits() names it.
std::vector<Polygon2> slit_widenings(const Polygon2& outline, const std::vector<Polygon2>& teeth,
                                     double min_feature, double split_area = 9.0);

/// The slits of \p outline narrower than \p min_feature [mm] that are cuts the laser cannot
/// make: what a closing by half that width fills and that holds more than a square of that width
/// or reaches farther than that width from the rest along its edges (the test the sheet auditor
/// applies; a shallower notch is no slit): what the outline cleanup (slit_widenings) left.
std::vector<Polygon2> narrow_slits(const Polygon2& outline, double min_feature);

/// The same slits in the part the laser path \p path leaves (the path shrunk by half \p
/// kerf_width [mm]: a notch narrower than the kerf is one the path does not enter), as the sheet
/// auditor reads a sheet back; narrow_slits() of \p path itself where the kerf is 0.
std::vector<Polygon2> narrow_slits_as_cut(const Polygon2& path, double kerf_width,
                                          double min_feature);

/// The tails of \p outline narrower than \p min_feature [mm], the same test for material: what
/// an opening by half that width takes away and that holds more than a square of that width or
/// reaches farther than that width from the rest along its edges (what the sheet auditor calls
/// a tail).
std::vector<Polygon2> narrow_tails(const Polygon2& outline, double min_feature);

/// \p outline without the small pieces that hang at one end of a short neck narrower than
/// \p min_feature [mm]: the erosion by half that width (less 10 um) falls in two there, though an
/// opening closes over the neck (the discs on both sides overlap across it). A piece no larger
/// than \p largest [mm2] goes with its neck, since it would break off (amo_quad: a strip's tip
/// of 1.5 mm2 on a neck 0.18 mm wide and as long, left between the mitres of two sharp folds),
/// unless it holds any of one of \p teeth (counter-clockwise regions; more than 0.01 mm2) or
/// taking it would cut the part in two. What goes is what the discs inside the rest of the part
/// cannot reach.
Polygon2 without_hanging_corners(const Polygon2& outline, const std::vector<Polygon2>& teeth,
                                 double min_feature, double largest);

/// The pieces of \p outline's morphological erosion (round corners) by half \p min_feature less
/// 10 um [mm]: two or more where a neck narrower than that feature parts them (what names a part
/// in Joints::thin_neck_parts where the mitred erosion falls in two as well).
std::vector<Polygon2> neck_cores(const Polygon2& outline, double min_feature);

/// Offset of both parts where a border has no teeth: the edges meet at the inner mitre point,
/// -h/2 tan(min(|fold|, kMaxJointFold)/2) [mm]; never overlapping.
double plain_offset(double fold, double thickness);

}  // namespace kerfab
