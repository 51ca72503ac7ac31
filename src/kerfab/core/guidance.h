#pragma once
/// \file A user's decisions about the quad mesh (paper Sec. 3.5), as read from a guidance file
/// and used by the stages.

namespace kerfab {

/// A user's decision for one edge of the quad mesh.
struct EdgeGuidance {
  int v0 = -1, v1 = -1;  ///< the edge's two vertex indices in the quad mesh as used
  bool bendable = true;  ///< true: force bendable; false: force stiff
};

}  // namespace kerfab
