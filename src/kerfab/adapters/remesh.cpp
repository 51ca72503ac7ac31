#include "kerfab/adapters/remesh.h"

#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <map>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using EdgeIndex = SurfaceMesh::Edge_index;
namespace PMP = CGAL::Polygon_mesh_processing;

}  // namespace

FeatureTriangleMesh isotropic_remesh(const FeatureTriangleMesh& input, double edge_length,
                                     int iterations) {
  if (!(edge_length > 0)) throw InvalidInput("remeshing: edge length must be > 0 mm");
  SurfaceMesh sm;
  std::vector<VertexIndex> vh;
  vh.reserve(input.mesh.vertices.size());
  for (const Vec3& p : input.mesh.vertices)
    vh.push_back(sm.add_vertex(Point3(p.x(), p.y(), p.z())));
  for (std::size_t t = 0; t < input.mesh.triangles.size(); ++t) {
    const auto& tri = input.mesh.triangles[t];
    if (sm.add_face(vh[tri[0]], vh[tri[1]], vh[tri[2]]) == SurfaceMesh::null_face())
      throw InvalidInput("target triangle " + std::to_string(t) +
                         " makes the surface non-manifold (or repeats a face); repair it first");
  }
  auto constrained = sm.add_property_map<EdgeIndex, bool>("e:kerfab_feature", false).first;
  for (const auto& [a, b] : input.features) {
    const auto h = sm.halfedge(vh[a], vh[b]);
    if (h != SurfaceMesh::null_halfedge()) constrained[sm.edge(h)] = true;
  }
  for (EdgeIndex e : sm.edges())
    if (sm.is_border(e)) constrained[e] = true;
  // Vertices where feature lines meet or end are kept where they are.
  auto corner = sm.add_property_map<VertexIndex, bool>("v:kerfab_corner", false).first;
  for (VertexIndex v : sm.vertices()) {
    int n = 0;
    for (auto h : sm.halfedges_around_target(sm.halfedge(v))) n += constrained[sm.edge(h)] ? 1 : 0;
    corner[v] = n != 0 && n != 2;
  }
  auto given = sm.add_property_map<VertexIndex, bool>("v:kerfab_given_corner", false).first;
  for (int v : input.corners)
    if (v >= 0 && v < static_cast<int>(vh.size())) corner[vh[v]] = given[vh[v]] = true;
  PMP::isotropic_remeshing(sm.faces(), edge_length, sm,
                           PMP::parameters::number_of_iterations(iterations)
                               .edge_is_constrained_map(constrained)
                               .vertex_is_constrained_map(corner)
                               .protect_constraints(false)
                               .relax_constraints(true));
  sm.collect_garbage();

  FeatureTriangleMesh out;
  std::map<VertexIndex, int> id;
  for (VertexIndex v : sm.vertices()) {
    id[v] = static_cast<int>(out.mesh.vertices.size());
    const Point3& p = sm.point(v);
    out.mesh.vertices.emplace_back(p.x(), p.y(), p.z());
    if (given[v]) out.corners.push_back(id[v]);
  }
  for (auto f : sm.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (VertexIndex v : sm.vertices_around_face(sm.halfedge(f))) tri[k++] = id[v];
    out.mesh.triangles.push_back(tri);
  }
  for (EdgeIndex e : sm.edges())
    if (constrained[e]) out.features.push_back({id[sm.vertex(e, 0)], id[sm.vertex(e, 1)]});
  return out;
}

}  // namespace kerfab
