#include "kerfab/adapters/target_surface.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using Triangle3 = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point3 to_cgal(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
Vec3 from_cgal(const Point3& p) { return {p.x(), p.y(), p.z()}; }

std::pair<int, int> edge_key(int a, int b) { return a < b ? std::pair{a, b} : std::pair{b, a}; }

}  // namespace

struct TargetSurface::Impl {
  TriangleMesh mesh;
  std::vector<Triangle3> triangles;
  std::vector<Vec3> face_normals;
  std::vector<Vec3> vertex_pseudo_normals;  // angle weighted
  std::vector<Vec3> vertex_smooth_normals;  // area weighted
  std::map<std::pair<int, int>, Vec3> edge_pseudo_normals;
  Tree tree;

  // Barycentric coordinates of q (assumed in the triangle's plane) in triangle t.
  Eigen::Vector3d barycentric(int t, const Vec3& q) const {
    const auto& tri = mesh.triangles[t];
    const Vec3& a = mesh.vertices[tri[0]];
    const Vec3 v0 = mesh.vertices[tri[1]] - a, v1 = mesh.vertices[tri[2]] - a, v2 = q - a;
    const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
    const double d20 = v2.dot(v0), d21 = v2.dot(v1);
    const double den = d00 * d11 - d01 * d01;
    const double v = (d11 * d20 - d01 * d21) / den;
    const double w = (d00 * d21 - d01 * d20) / den;
    return {1.0 - v - w, v, w};
  }

  Vec3 pseudo_normal(int t, const Vec3& q) const {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d b = barycentric(t, q);
    constexpr double kEps = 1e-9;
    int zero_count = 0;
    for (int k = 0; k < 3; ++k) zero_count += b[k] < kEps ? 1 : 0;
    if (zero_count >= 2) {  // at a vertex: the one whose coordinate is not ~0
      int k = 0;
      b.maxCoeff(&k);
      return vertex_pseudo_normals[tri[k]];
    }
    if (zero_count == 1) {  // on the edge opposite the ~0 coordinate
      int k = 0;
      b.minCoeff(&k);
      return edge_pseudo_normals.at(edge_key(tri[(k + 1) % 3], tri[(k + 2) % 3]));
    }
    return face_normals[t];
  }
};

TargetSurface::TargetSurface(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (mesh.triangles.empty()) throw InvalidInput("target surface has no triangles");
  m.mesh = mesh;
  const auto nv = mesh.vertices.size();
  m.vertex_pseudo_normals.assign(nv, Vec3::Zero());
  m.vertex_smooth_normals.assign(nv, Vec3::Zero());
  m.triangles.reserve(mesh.triangles.size());
  m.face_normals.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    const Vec3 cross = (b - a).cross(c - a);
    const double area2 = cross.norm();
    if (!(area2 > 0.0))
      throw InvalidInput("target triangle " + std::to_string(t) + " has zero area");
    const Vec3 n = cross / area2;
    m.face_normals.push_back(n);
    m.triangles.emplace_back(to_cgal(a), to_cgal(b), to_cgal(c));
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.vertices[tri[k]];
      const Vec3 e1 = (mesh.vertices[tri[(k + 1) % 3]] - p).normalized();
      const Vec3 e2 = (mesh.vertices[tri[(k + 2) % 3]] - p).normalized();
      const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
      m.vertex_pseudo_normals[tri[k]] += angle * n;
      m.vertex_smooth_normals[tri[k]] += cross;  // area weighted
      m.edge_pseudo_normals.try_emplace(edge_key(tri[k], tri[(k + 1) % 3]), Vec3::Zero())
          .first->second += n;  // Eigen vectors start uninitialised
    }
  }
  auto normalize_all = [](auto& normals) {
    for (auto& n : normals) {
      const double len = n.norm();
      if (len > 0) n /= len;
    }
  };
  normalize_all(m.vertex_pseudo_normals);
  normalize_all(m.vertex_smooth_normals);
  for (auto& [key, n] : m.edge_pseudo_normals) {
    const double len = n.norm();
    if (len > 0) n /= len;
  }
  m.tree.insert(m.triangles.cbegin(), m.triangles.cend());
  m.tree.build();
  m.tree.accelerate_distance_queries();
}

TargetSurface::~TargetSurface() = default;
TargetSurface::TargetSurface(TargetSurface&&) noexcept = default;
TargetSurface& TargetSurface::operator=(TargetSurface&&) noexcept = default;

const TriangleMesh& TargetSurface::mesh() const { return impl_->mesh; }

SurfacePoint TargetSurface::closest(const Vec3& query) const {
  const auto [point, it] = impl_->tree.closest_point_and_primitive(to_cgal(query));
  SurfacePoint out;
  out.point = from_cgal(point);
  out.triangle = static_cast<int>(it - impl_->triangles.cbegin());
  const Vec3 diff = query - out.point;
  out.distance = diff.norm();
  out.normal = impl_->pseudo_normal(out.triangle, out.point);
  out.signed_distance = diff.dot(out.normal) >= 0.0 ? out.distance : -out.distance;
  return out;
}

Vec3 TargetSurface::smooth_normal(const SurfacePoint& at) const {
  const auto& tri = impl_->mesh.triangles[at.triangle];
  const Eigen::Vector3d b = impl_->barycentric(at.triangle, at.point).cwiseMax(0.0);
  Vec3 n = Vec3::Zero();
  for (int k = 0; k < 3; ++k) n += b[k] * impl_->vertex_smooth_normals[tri[k]];
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : impl_->face_normals[at.triangle];
}

std::vector<RayHit> TargetSurface::hits_along_line(const Vec3& origin, const Vec3& direction,
                                                   double max_distance) const {
  const Kernel::Segment_3 segment(to_cgal(origin - max_distance * direction),
                                  to_cgal(origin + max_distance * direction));
  std::vector<Tree::Intersection_and_primitive_id<Kernel::Segment_3>::Type> hits;
  impl_->tree.all_intersections(segment, std::back_inserter(hits));
  std::vector<RayHit> out;
  for (const auto& [object, it] : hits) {
    const Point3* p = boost::get<Point3>(&object);
    if (p == nullptr) continue;  // segment lying in a triangle's plane: ignore
    const Vec3 q = from_cgal(*p);
    out.push_back(
        {q, (q - origin).dot(direction), static_cast<int>(it - impl_->triangles.cbegin())});
  }
  // Ties in the tree's order (the nearest hit has always been the first of them found).
  std::stable_sort(out.begin(), out.end(),
                   [](const RayHit& a, const RayHit& b) { return std::abs(a.t) < std::abs(b.t); });
  // A crossing at an edge or a vertex once, as its first triangle found.
  std::vector<RayHit> once;
  for (const RayHit& hit : out)
    if (std::none_of(once.begin(), once.end(),
                     [&](const RayHit& o) { return (o.point - hit.point).norm() <= 1e-9; }))
      once.push_back(hit);
  return once;
}

std::optional<RayHit> TargetSurface::nearest_hit_along_line(const Vec3& origin,
                                                            const Vec3& direction,
                                                            double max_distance) const {
  const std::vector<RayHit> hits = hits_along_line(origin, direction, max_distance);
  if (hits.empty()) return std::nullopt;
  return hits.front();
}

VertexDistances vertex_distances(const PolyMesh& mesh, const TargetSurface& target) {
  VertexDistances out;
  double sum = 0;
  int count = 0;
  for (auto v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    const double d = target.closest(to_eigen(mesh.point(v))).distance;
    out.max = std::max(out.max, d);
    sum += d;
    ++count;
  }
  out.mean = count ? sum / count : 0.0;
  return out;
}

}  // namespace kerfab
