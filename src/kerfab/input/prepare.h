#pragma once
/// \file Input stage: validation, Catmull-Clark subdivision of the quad mesh, units and scale,
/// and the query structure on the target.
#include <optional>
#include <string>
#include <vector>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/mesh.h"

namespace kerfab {

struct InputOptions {
  std::optional<double> size;      ///< scale so the target's largest bbox side is this [mm],
                                   ///< in [min_model_mm, max_model_mm]; unset: input is in mm
  int subdivide = 0;               ///< Catmull-Clark steps applied to the quad mesh [-], 0..4
  double min_model_mm = 10.0;      ///< smallest accepted largest bbox side [mm]
  double max_model_mm = 10000.0;   ///< largest accepted largest bbox side [mm]
  double max_quad_distance = 0.1;  ///< quad vertices farther from the target than this
                                   ///< fraction of the target's bbox diagonal are an error [-]
};

/// Summary of one mesh as used.
struct MeshSummary {
  int vertices = 0;
  int faces = 0;
  int edges = 0;
  int boundary_loops = 0;
  int euler_characteristic = 0;
  std::vector<std::pair<int, int>> face_sizes;  ///< (sides, count)
  BoundingBox bbox;                             ///< after scaling [mm]
};

struct PreparedInput {
  PolyMesh target;                 ///< target as read, scaled [mm]
  PolyMesh quads;                  ///< all-quad mesh (after subdivision), scaled [mm]
  TargetSurface surface;           ///< queries on the triangulated target
  double scale = 1.0;              ///< factor applied to both input meshes [-]
  bool quads_from_target = false;  ///< the target itself served as the quad mesh
  bool needs_quads = false;        ///< a target not all quads and no quad mesh: `quads` is empty
                                   ///< until the quads stage makes one (attach_quads)
  MeshSummary target_summary;
  double target_diagonal = 0;  ///< the scaled target's bbox diagonal [mm]
  MeshSummary quad_summary;
  double quad_max_distance = 0;   ///< max distance of a quad vertex to the target [mm]
  double quad_mean_distance = 0;  ///< mean distance of the quad vertices to the target [mm]
  /// Solids whose surfaces crossed or touched, joined into their union (0: none) [-], and the
  /// surface that lay inside another solid or on two, gone with it [mm^2].
  int united_solids = 0;
  double united_surface_gone = 0;
  /// Cavities (closed pieces facing inwards inside another: a hollowed model's inner wall) left
  /// out [-], and their surface [mm^2].
  int cavities_left_out = 0;
  double cavity_area = 0;
  std::vector<std::string> warnings;
};

/// Validates and prepares the inputs. Without \p quad, the target must itself be a polygon mesh
/// that is all quads (or becomes so with subdivide >= 1), or any other (needs_quads: the
/// quads stage makes the quad mesh). The target's cracks are zipped first, with a warning
/// giving the count: border vertices at one point become one, and a border vertex lying on a
/// border edge of another face (a T-junction) is put into that face; then its triangles of no
/// area are mended, and its larger faces of no area with two corners at one point (a quad whose
/// opposite corners coincide: a doublet, as general remeshers leave behind) lose that face, the
/// two corners merged (a warning each, with the count).
/// A zero-area quad of \p quad whose opposite corners coincide (a doublet, as general remeshers
/// leave behind) is collapsed along that diagonal, with a warning naming it. Without
/// subdivision, so is a quad folded back onto itself across a diagonal by more than 150 degrees
/// (a dart, as QuadriFlow leaves at sharp edges): its two corners off that diagonal merge at
/// their midpoint, where that leaves the mesh manifold (at most 64 tries; the rest are counted
/// in a warning).
/// Without \p quad and subdivision, the target's cavities are left out (cavities_left_out), and
/// closed pieces of it that bound solids that overlap or touch (their surfaces cross or touch,
/// or one lies inside another) are replaced by the surface of their union (united_solids), each
/// with a warning giving the surface gone (solids meeting along an edge or at a point only,
/// whose union has no manifold surface, are kept as they are); a target of quads so mended is
/// then meshed anew (needs_quads), with a warning.
/// \throw InvalidInput empty mesh, NaN/inf coordinates, other zero-area faces, non-quad faces
///        without subdivision, a model outside the accepted size range without `size`, pieces
///        of the target lying on one another that were not united (solids touching face to
///        face: the area and where named), or a quad mesh far from the target (distance named).
PreparedInput prepare_input(const PolyMesh& target, const std::optional<PolyMesh>& quad,
                            const InputOptions& options);

/// Takes \p quads (scaled, on the target) as the quad mesh of \p in: its summary and its
/// distance to the target. \throw InvalidInput a vertex farther than the allowed distance.
void attach_quads(PreparedInput& in, PolyMesh quads, const InputOptions& options);

/// Catmull-Clark subdivision, \p steps times (OpenMesh's subdivider).
PolyMesh catmull_clark(const PolyMesh& mesh, int steps);

}  // namespace kerfab
