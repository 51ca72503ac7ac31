#pragma once
/// \file Paper (thickness 0): the joints of a paper model (paper Sec. 4's papercraft emulation,
/// made buildable). Every shared border gets glue tabs on one side at each point: trapezoids on
/// the border, their ends leaning in by kGlueTabTaper; borders longer than 1.5 kGlueTabRun
/// alternate sides in runs of about that length, so both parts are held. A tab is folded under
/// the other part and glued to its back; it is clipped so that it stays inside that part, off
/// the tabs already glued there and off its own part and its other tabs on the sheet. Each tab's
/// root is a fold line, mountain or valley as the model's surface folds there; so are the
/// rulings that fold more than kCreaseFold, and every ruling that bends when asked
/// (JointOptions::score_rulings). docs/joints.md, "Paper".
#include "kerfab/joints/joints.h"

namespace kerfab {

/// The ends of a glue tab lean in from the border by this angle [rad]: two tabs glued under one
/// part at a corner of it with an inner angle of 90 degrees or more stay apart by themselves
/// (tabs at sharper corners are clipped against each other).
inline constexpr double kGlueTabTaper = M_PI / 4;
/// Length of a run of tabs on one side of a long border before the other side takes over [mm].
inline constexpr double kGlueTabRun = 40.0;
/// Two tabs of one part stay this far apart on the sheet (a cut between them), and a tab this
/// far inside the edges of the part it is glued under [mm].
inline constexpr double kGlueTabGap = 1.0;
/// A tab smaller than this, or than half of its untrimmed trapezoid, holds nothing [mm^2].
inline constexpr double kMinGlueTabArea = 2.0;
/// Rulings bending less than this are not scored (JointOptions::score_rulings) [rad].
inline constexpr double kMinScoredFold = M_PI / 180;
/// Rulings folding more than this are scored even unasked: paper creases there rather than
/// bends (where a strip of stiff sheet is split by default) [rad].
inline constexpr double kCreaseFold = kStiffSplitAngle;

/// The glue tabs, fold lines and outlines of a paper model; plain borders (and no tabs) where
/// JointOptions::glue_tab is 0. \pre \p flat was computed from \p strips; options checked by
/// make_joints.
Joints make_glue_tabs(const Strips& strips, const Flattening& flat, const Machine& machine,
                      const JointOptions& options);

}  // namespace kerfab
