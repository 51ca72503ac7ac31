#pragma once
/// \file Internal to the joints stage: stubs joined at a corner. A border only a few millimetres
/// long between corners of both its parts (where no tooth, tab or glue tab clears their other
/// joints, or the border is shorter than the narrowest tooth) cannot carry a joint of its own.
/// Where its two parts are each joined to the parts at one of its ends, those joints locate and
/// hold both: placed on them, the stub's two edges meet and are glued (docs/joints.md).
#include "kerfab/joints/border_pieces.h"
#include "kerfab/joints/joints.h"

namespace kerfab {

/// A stub no longer than this many tooth widths may be joined at a corner: over that length the
/// two parts, each held at the stub's end, cannot bow apart (a longer border without a joint stays
/// one without).
inline constexpr double kStubAtCorner = 2.0;

/// Sets BorderJoint::joined_through on every border of \p joints with no tooth, tab or glue tab
/// and at most \p max_length long [mm] whose two parts are joined to each other, at one of its
/// ends, through the parts there (a shortest chain of borders with a joint that end at that
/// corner, or near it, each with its joint within \p max_length of it: in 3D from the corner to
/// the border's end, then along the border; the chain's parts from one side's to the other's);
/// on one up to twice as long where they are so joined at both its ends (no point
/// of it farther from a place where both parts are held), also BorderJoint::joined_through_far
/// (the chain at its other end); and recounts
/// Joints::borders_without_joint and Joints::stubs_joined_at_corners. \pre \p pieces are the pieces
/// \p joints was built on (one border per piece, same order).
void join_stubs_at_corners(Joints& joints, const Strips& strips, const border::Pieces& pieces,
                           double max_length);

/// One end of a border with a joint, at a corner of a border without one.
struct CornerEnd {
  int border = -1;  ///< index into Joints::borders
  int end = 0;      ///< 0: its common end (arc length 0); 1: the other
  bool operator==(const CornerEnd&) const = default;
};

/// Where a joint within \p max_length of a corner would let join_stubs_at_corners() hold a
/// border that has none [mm]: per such border (no tooth, tab or glue tab, two parts, at most
/// twice \p max_length long), the borders with a joint at its corners that link its two parts
/// but have their nearest joint farther than \p max_length from that corner, fewest first: at
/// the one end that needs fewest for a stub up to \p max_length long, at both ends for a longer
/// one. Borders already held, or with no such chain at an end they need, are left out.
std::vector<std::vector<CornerEnd>> joints_wanted_at_corners(const Joints& joints,
                                                             const Strips& strips,
                                                             const border::Pieces& pieces,
                                                             double max_length);

}  // namespace kerfab
