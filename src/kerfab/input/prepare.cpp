#include "kerfab/input/prepare.h"

#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <cmath>
#include <sstream>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

std::string face_size_text(const PolyMesh& mesh) {
  std::ostringstream os;
  bool first = true;
  for (auto [sides, count] : face_size_histogram(mesh)) {
    os << (first ? "" : ", ") << count << " ";
    switch (sides) {
      case 3:
        os << "triangle" << (count > 1 ? "s" : "");
        break;
      case 4:
        os << "quad" << (count > 1 ? "s" : "");
        break;
      default:
        os << sides << "-gon" << (count > 1 ? "s" : "");
        break;
    }
    first = false;
  }
  return os.str();
}

MeshSummary summarize(const PolyMesh& mesh) {
  MeshSummary s;
  int referenced = 0;
  for (auto v : mesh.vertices()) referenced += mesh.is_isolated(v) ? 0 : 1;
  s.vertices = referenced;
  s.faces = static_cast<int>(mesh.n_faces());
  s.edges = static_cast<int>(mesh.n_edges());
  s.boundary_loops = boundary_loop_count(mesh);
  s.euler_characteristic = s.vertices - s.edges + s.faces;
  s.face_sizes = face_size_histogram(mesh);
  s.bbox = bounding_box(mesh);
  return s;
}

void check_geometry(const PolyMesh& mesh, const std::string& what) {
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InvalidInput(what + " vertex " + std::to_string(v.idx()) +
                         " has a NaN or infinite coordinate");
  }
  const double diag = bounding_box(mesh).diagonal();
  if (!(diag > 0.0)) throw InvalidInput(what + " has zero extent (all vertices coincide)");
  const double min_area = 1e-12 * diag * diag;
  for (auto f : mesh.faces()) {
    // Area vector of the polygon (exact for planar faces, a fair measure otherwise).
    OpenMesh::Vec3d area(0, 0, 0);
    auto h0 = mesh.halfedge_handle(f);
    const auto p0 = mesh.point(mesh.from_vertex_handle(h0));
    for (auto h : mesh.fh_range(f)) {
      const auto a = mesh.point(mesh.from_vertex_handle(h)) - p0;
      const auto b = mesh.point(mesh.to_vertex_handle(h)) - p0;
      area += OpenMesh::cross(a, b);
    }
    if (0.5 * area.norm() <= min_area)
      throw InvalidInput(what + " face " + std::to_string(f.idx()) + " has zero area");
  }
}

void scale_mesh(PolyMesh& mesh, double s) {
  for (auto v : mesh.vertices()) mesh.set_point(v, mesh.point(v) * s);
}

double signed_volume(const TriangleMesh& tri) {
  double vol = 0;
  for (const auto& t : tri.triangles)
    vol += tri.vertices[t[0]].dot(tri.vertices[t[1]].cross(tri.vertices[t[2]])) / 6.0;
  return vol;
}

}  // namespace

PolyMesh catmull_clark(const PolyMesh& mesh, int steps) {
  PolyMesh out = mesh;
  if (steps <= 0) return out;
  // The subdivider works on a mesh without deleted elements or isolated vertices.
  for (auto v : out.vertices())
    if (out.is_isolated(v)) out.delete_vertex(v, false);
  out.garbage_collection();
  OpenMesh::Subdivider::Uniform::CatmullClarkT<PolyMesh> subdivider;
  subdivider.attach(out);
  subdivider(static_cast<std::size_t>(steps));
  subdivider.detach();
  return out;
}

PreparedInput prepare_input(const PolyMesh& target_in, const std::optional<PolyMesh>& quad_in,
                            const InputOptions& options) {
  if (target_in.n_faces() == 0) throw InvalidInput("target mesh has no faces");
  if (options.subdivide < 0 || options.subdivide > 4)
    throw InvalidInput("--subdivide must be between 0 and 4, got " +
                       std::to_string(options.subdivide));
  if (!(options.max_quad_distance > 0.0)) throw InvalidInput("maximum quad distance must be > 0");
  check_geometry(target_in, "target mesh");
  if (quad_in) {
    if (quad_in->n_faces() == 0) throw InvalidInput("quad mesh has no faces");
    check_geometry(*quad_in, "quad mesh");
  }

  // Units and scale: decided on the target, applied identically to both meshes.
  const double side = bounding_box(target_in).largest_side();
  double scale = 1.0;
  if (options.size) {
    const double size = *options.size;
    if (!std::isfinite(size) || size < options.min_model_mm || size > options.max_model_mm)
      throw InvalidInput("--size must be between " + fmt(options.min_model_mm) + " and " +
                         fmt(options.max_model_mm) + " mm, got " + fmt(size));
    scale = size / side;
  } else if (side < options.min_model_mm || side > options.max_model_mm) {
    throw InvalidInput("target's largest bounding-box side is " + fmt(side) + " mm, outside " +
                       fmt(options.min_model_mm) + " mm .. " + fmt(options.max_model_mm / 1000.0) +
                       " m; inputs are read as millimetres, so pass --size MM to scale the model");
  }

  // The quad mesh: given, or the target itself.
  const bool from_target = !quad_in.has_value();
  const PolyMesh& quad_source = from_target ? target_in : *quad_in;
  // A triangle target without a quad mesh: the quads stage makes one (make_quad_mesh).
  const bool needs_quads = from_target && is_all_triangles(target_in) && options.subdivide == 0;
  if (!needs_quads && options.subdivide == 0 && !is_all_quads(quad_source))
    throw InvalidInput(std::string(from_target ? "target" : "quad mesh") + " has " +
                       face_size_text(quad_source) +
                       "; kerfab needs all quads: pass --subdivide 1 (Catmull-Clark)");

  PolyMesh target = target_in;
  PolyMesh quads = needs_quads ? PolyMesh() : catmull_clark(quad_source, options.subdivide);
  scale_mesh(target, scale);
  scale_mesh(quads, scale);
  if (!needs_quads && !is_all_quads(quads))
    throw InvalidInput("quad mesh is not all quads after subdivision");

  std::vector<std::string> warnings;
  TriangleMesh tri = triangulate(target);
  if (boundary_loop_count(target) == 0 && signed_volume(tri) < 0) {
    for (auto& t : tri.triangles) std::swap(t[1], t[2]);
    warnings.push_back(
        "target faces point inward (negative volume); flipped them for inside/outside tests");
  }
  PreparedInput out{.target = std::move(target),
                    .quads = std::move(quads),
                    .surface = TargetSurface(tri),
                    .scale = scale,
                    .quads_from_target = from_target && !needs_quads,
                    .needs_quads = needs_quads,
                    .warnings = std::move(warnings)};
  out.target_summary = summarize(out.target);
  out.target_diagonal = bounding_box(out.surface.mesh()).diagonal();
  if (!needs_quads) attach_quads(out, std::move(out.quads), options);
  return out;
}

void attach_quads(PreparedInput& out, PolyMesh quads, const InputOptions& options) {
  out.quads = std::move(quads);
  out.quad_summary = summarize(out.quads);

  // The quad mesh must lie on (near) the target.
  double max_d = 0, sum_d = 0;
  int count = 0;
  for (auto v : out.quads.vertices()) {
    if (out.quads.is_isolated(v)) continue;
    const double d = out.surface.closest(to_eigen(out.quads.point(v))).distance;
    max_d = std::max(max_d, d);
    sum_d += d;
    ++count;
  }
  out.quad_max_distance = max_d;
  out.quad_mean_distance = count ? sum_d / count : 0.0;
  const double diag = out.target_summary.bbox.diagonal();
  if (max_d > options.max_quad_distance * diag)
    throw InvalidInput("quad mesh is far from the target: a vertex lies " + fmt(max_d) +
                       " mm away (" + fmt(100.0 * max_d / diag) + "% of the target's " + fmt(diag) +
                       " mm diagonal, limit " + fmt(100.0 * options.max_quad_distance) +
                       "%); are both meshes in the same frame and units?");
}

}  // namespace kerfab
