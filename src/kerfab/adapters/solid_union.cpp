#include "kerfab/adapters/solid_union.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <exception>

namespace kerfab {
namespace {

// Exact constructions: the corefinement computes the crossing points of the two surfaces, and
// with rounded ones its result may cross itself.
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Twice the area under which a triangle of the union counts as none [mm^2].
constexpr double kNoArea = 1e-12;

/// \p mesh as a CGAL surface; nothing where a triangle would make it non-manifold.
std::optional<SurfaceMesh> surface_of(const TriangleMesh& mesh) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vh;
  vh.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) vh.push_back(sm.add_vertex({p.x(), p.y(), p.z()}));
  for (const auto& t : mesh.triangles)
    if (sm.add_face(vh[t[0]], vh[t[1]], vh[t[2]]) == SurfaceMesh::null_face()) return std::nullopt;
  return sm;
}

}  // namespace

bool bounds_solid(const TriangleMesh& solid) {
  const std::optional<SurfaceMesh> sm = surface_of(solid);
  if (!sm || sm->is_empty() || !CGAL::is_closed(*sm)) return false;
  try {
    return !PMP::does_self_intersect(*sm) && PMP::does_bound_a_volume(*sm) &&
           PMP::is_outward_oriented(*sm);
  } catch (const std::exception&) {  // a precondition CGAL found unmet: no solid to unite
    return false;
  }
}

bool solids_meet(const TriangleMesh& a, const TriangleMesh& b) {
  const std::optional<SurfaceMesh> sa = surface_of(a), sb = surface_of(b);
  if (!sa || !sb || !CGAL::is_closed(*sa) || !CGAL::is_closed(*sb)) return false;
  const auto inside_too = PMP::parameters::do_overlap_test_of_bounded_sides(true);
  try {
    return PMP::do_intersect(*sa, *sb, inside_too, inside_too);
  } catch (const std::exception&) {
    return false;
  }
}

std::optional<TriangleMesh> solid_union(const TriangleMesh& a, const TriangleMesh& b) {
  std::optional<SurfaceMesh> sa = surface_of(a), sb = surface_of(b);
  if (!sa || !sb) return std::nullopt;
  SurfaceMesh united;
  try {
    if (!PMP::corefine_and_compute_union(*sa, *sb, united)) return std::nullopt;
  } catch (const std::exception&) {  // CGAL's precondition failures are exceptions
    return std::nullopt;
  }
  TriangleMesh out;
  std::vector<int> index(united.number_of_vertices() + united.number_of_removed_vertices(), -1);
  for (auto v : united.vertices()) {
    const auto& p = united.point(v);
    index[v.idx()] = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()),
                              CGAL::to_double(p.z()));
  }
  for (auto f : united.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : united.vertices_around_face(united.halfedge(f))) {
      if (k == 3) return std::nullopt;  // the union's faces are triangles
      t[k++] = index[v.idx()];
    }
    if (k != 3) return std::nullopt;
    // A crossing point rounded to doubles may leave a sliver of no area, which no closest-point
    // query takes: no union then (the solids are kept as they were).
    const Vec3 &p0 = out.vertices[t[0]], &p1 = out.vertices[t[1]], &p2 = out.vertices[t[2]];
    if (!((p1 - p0).cross(p2 - p0).norm() > kNoArea)) return std::nullopt;
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace kerfab
