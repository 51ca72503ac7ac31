#pragma once
/// \file A user's decisions about the quad mesh (paper Sec. 3.5), as read from a guidance file
/// and used by the stages.
#include <array>
#include <vector>

namespace kerfab {

/// A user's decision for one edge of the quad mesh.
struct EdgeGuidance {
  int v0 = -1, v1 = -1;  ///< the edge's two vertex indices in the quad mesh as used
  bool bendable = true;  ///< true: force bendable; false: force stiff
};

/// Everything a guidance file says; edges are vertex index pairs of the quad mesh as used.
struct Guidance {
  std::vector<EdgeGuidance> edges;        ///< forced bendable or stiff (bending program)
  std::vector<std::array<int, 2>> split;  ///< strip borders to insert (strips)
  std::vector<std::array<int, 2>> merge;  ///< strips to merge sideways across (strips)
  std::vector<std::vector<int>> facets;   ///< quad groups (face indices) cut as flat facets;
                                          ///< set by the resolve step, not read from files
  std::vector<int> omit;  ///< quads (face indices) whose parts are left out (faces folded back
                          ///< thinner than the sheets); set by the resolve step, not read
                          ///< from files
};

}  // namespace kerfab
