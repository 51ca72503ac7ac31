#include "kerfab/output/strip_files.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <string>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

std::ofstream open_for_writing(const std::filesystem::path& path) {
  std::ofstream out(path);
  if (!out) throw IoError("cannot write " + path.string());
  out.precision(10);
  return out;
}

void check_written(const std::ofstream& out, const std::filesystem::path& path) {
  if (!out) throw IoError("cannot write " + path.string());
}

// ASCII PLY of the strip mesh in mm: vertices, and per face its four indices and its strip
// (patch) id followed by the properties declared in `face_properties` (header lines), whose
// values `face_values(out, f)` writes, each after a space.
void write_strip_mesh_ply(const Strips& strips, const std::filesystem::path& path,
                          const std::string& comment, const std::string& face_properties,
                          const std::function<void(std::ostream&, std::size_t)>& face_values) {
  auto out = open_for_writing(path);
  out << "ply\nformat ascii 1.0\ncomment " << comment << "\n"
      << "element vertex " << strips.vertices.size()
      << "\nproperty double x\nproperty double y\nproperty double z\n"
      << "element face " << strips.faces.size()
      << "\nproperty list uchar int vertex_indices\nproperty int strip\n"
      << face_properties << "end_header\n";
  for (const Vec3& v : strips.vertices) out << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (std::size_t f = 0; f < strips.faces.size(); ++f) {
    const auto& q = strips.faces[f];
    out << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << " " << strips.face_patch[f];
    face_values(out, f);
    out << "\n";
  }
  check_written(out, path);
}

}  // namespace

std::array<int, 3> strip_colour(int id) {
  const double golden = 0.618033988749895;
  const double h = std::fmod(0.11 + id * golden, 1.0) * 6.0;
  const double s = id % 2 == 0 ? 0.65 : 0.45, v = id % 3 == 0 ? 0.95 : 0.85;
  const int i = static_cast<int>(h);
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (i % 6) {
    case 1:
      r = q, g = v, b = p;
      break;
    case 2:
      r = p, g = v, b = t;
      break;
    case 3:
      r = p, g = q, b = v;
      break;
    case 4:
      r = t, g = p, b = v;
      break;
    case 5:
      r = v, g = p, b = q;
      break;
    default:
      break;
  }
  return {static_cast<int>(std::lround(255 * r)), static_cast<int>(std::lround(255 * g)),
          static_cast<int>(std::lround(255 * b))};
}

void write_strips_ply(const Strips& strips, const std::filesystem::path& path) {
  write_strip_mesh_ply(strips, path, "kerfab strip mesh, millimetres",
                       "property uchar red\nproperty uchar green\nproperty uchar blue\n",
                       [&](std::ostream& out, std::size_t f) {
                         const auto c = strip_colour(strips.face_patch[f]);
                         out << " " << c[0] << " " << c[1] << " " << c[2];
                       });
}

namespace {
// Viridis at t in [0, 1], from its published 5-stop table, interpolated linearly.
std::array<int, 3> viridis(double t) {
  static const double stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * 4;
  const int i = std::min(3, static_cast<int>(t));
  const double u = t - i;
  std::array<int, 3> c{};
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<int>(std::lround((1 - u) * stops[i][k] + u * stops[i + 1][k]));
  return c;
}
}  // namespace

FaceDensity kerf_density(const Strips& strips, const KerfResult& kerf) {
  FaceDensity d;
  d.density.assign(strips.faces.size(), 0.0);
  d.critical.assign(strips.faces.size(), 0);
  std::vector<double> nonzero;
  for (std::size_t p = 0; p < strips.patches.size() && p < kerf.patches.size(); ++p)
    for (int row = 0; row < strips.patches[p].rows(); ++row)
      for (std::size_t i = 0; i < strips.patches[p].faces.size(); ++i) {
        const int f = strips.patches[p].face(static_cast<int>(i), row);
        d.density[f] = kerf.patches[p].face_density[i];
        d.critical[f] = kerf.patches[p].face_critical[i];
        if (d.density[f] > 0) nonzero.push_back(d.density[f]);
      }
  // Colour scale up to the 95th percentile, so a few dense spots do not darken the rest.
  double top = 0;
  if (!nonzero.empty()) {
    const std::size_t k = static_cast<std::size_t>(0.95 * (nonzero.size() - 1));
    std::nth_element(nonzero.begin(), nonzero.begin() + k, nonzero.end());
    top = nonzero[k];
  }
  for (std::size_t f = 0; f < strips.faces.size(); ++f)
    d.colour.push_back(d.critical[f] ? std::array<int, 3>{230, 20, 20}
                                     : viridis(top > 0 ? d.density[f] / top : 0.0));
  return d;
}

void write_kerf_density_ply(const Strips& strips, const KerfResult& kerf,
                            const std::filesystem::path& path) {
  const FaceDensity d = kerf_density(strips, kerf);
  write_strip_mesh_ply(
      strips, path, "kerfab kerf cut density (cuts/mm), millimetres",
      "property float density\nproperty uchar critical\nproperty uchar red\nproperty uchar "
      "green\nproperty uchar blue\n",
      [&](std::ostream& out, std::size_t f) {
        const auto& c = d.colour[f];
        out << " " << d.density[f] << " " << int(d.critical[f]) << " " << c[0] << " " << c[1]
            << " " << c[2];
      });
}

void write_patch_obj(const Strips& strips, int patch, const std::filesystem::path& path) {
  const Patch& p = strips.patches.at(patch);
  auto out = open_for_writing(path);
  out << "# kerfab patch " << patch << " in 3D (mm): vertex 2*i+r is ruling i, rail r";
  if (p.rows() > 1)
    out << " (r = 1: the last rail), then the inner rails of its " << p.rows() << " rows";
  out << "\n";
  for (int id : p.local_vertices()) {
    const Vec3& v = strips.vertices[id];
    out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  }
  for (const auto& q : p.local_quads())
    out << "f " << q[0] + 1 << " " << q[1] + 1 << " " << q[2] + 1 << " " << q[3] + 1 << "\n";
  check_written(out, path);
}

void write_patch_flat_obj(const Strips& strips, int patch, const std::vector<Vec2>& points,
                          const std::filesystem::path& path) {
  const Patch& p = strips.patches.at(patch);
  if (points.size() != p.local_vertices().size())
    throw IoError("patch " + std::to_string(patch) + ": flattening does not match the patch");
  auto out = open_for_writing(path);
  out << "# kerfab patch " << patch << " flattened (mm, z = 0): vertex 2*i+r is ruling i, rail r\n";
  for (const auto& v : points) out << "v " << v.x() << " " << v.y() << " 0\n";
  for (const auto& q : p.local_quads())
    out << "f " << q[0] + 1 << " " << q[1] + 1 << " " << q[2] + 1 << " " << q[3] + 1 << "\n";
  check_written(out, path);
}

}  // namespace kerfab
