#pragma once
/// \file The assembly order: in which order a maker glues the parts together. A greedy growth
/// of one connected shell (docs/assembly.md): start from the largest part; each next part is the
/// one held best by what is already built, i.e. with the longest shared border to the placed
/// parts (toothed border counting fully, plain border by AssemblyOptions::plain_weight); a part
/// whose whole outline would be bordered by placed parts closes a hole and waits until no other
/// part can go on (the holes let a hand reach inside to hold joints while the glue sets).
#include <vector>

#include "kerfab/joints/joints.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

/// The rule in words, for the report and the guide (with the default plain_weight).
inline constexpr const char* kAssemblyRule =
    "Start with the largest part. Each next part is the one with the longest border to the "
    "parts already placed (border with teeth, tabs or glue tabs counting fully, plain border half), so "
    "the piece stays one connected shell and each new part is held along as much of its "
    "border as possible. A part whose whole outline would meet placed parts fills a hole; such parts wait "
    "until the end, and the holes let a hand reach inside to hold the joints while the glue "
    "sets.";

struct AssemblyOptions {
  double plain_weight = 0.5;  ///< weight of a border without teeth against a toothed one [-],
                              ///< in [0, 1]
};

/// What the order needs to know of a part besides its borders.
struct PartShape {
  double area = 0;       ///< [mm^2] (the largest part starts a piece)
  double perimeter = 0;  ///< its outline's 3D length [mm]: the border it shares with no other
                         ///< part is perimeter minus the shared length (free, not a hole's rim)
};

/// Two parts that share a border.
struct PartContact {
  int part = -1;
  double length = 0;   ///< shared border [mm] (3D)
  double toothed = 0;  ///< of which with teeth or tabs [mm]
};

/// One step: the part added and the placed parts it joins.
struct AssemblyStep {
  int part = -1;
  std::vector<PartContact> joins;  ///< placed parts it shares a border with, longest first
  double held = 0;                 ///< shared border with the placed parts [mm]
  bool new_piece = false;  ///< nothing placed touches it: it starts a separate piece (the first
                           ///< step, and each first part of a piece not joined to the others)
  bool closing = false;    ///< its whole outline meets placed parts: it fills a hole
};

struct AssemblyPlan {
  std::vector<AssemblyStep> steps;  ///< one per part, in order
  std::vector<std::vector<PartContact>> contacts;  ///< per part: its neighbours, longest first
  int pieces = 0;  ///< separate pieces (1 when every part is joined to the rest)
};

/// Per part: the parts it shares a border with, longest first (a part closing on itself after a
/// loop cut is not its own neighbour here).
std::vector<std::vector<PartContact>> part_contacts(const Joints& joints, int parts);

/// Per patch of \p strips: its outline's 3D length [mm].
std::vector<double> part_perimeters(const Strips& strips);

/// Orders the parts of \p joints for assembly; \p shapes per part.
/// \throw InvalidInput options out of range or \p shapes of the wrong size.
AssemblyPlan plan_assembly(const Joints& joints, const std::vector<PartShape>& shapes,
                           const AssemblyOptions& options);

}  // namespace kerfab
