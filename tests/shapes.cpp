#include "shapes.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <stdexcept>

namespace kerfab::test {
namespace {
constexpr double kPi = std::numbers::pi;
}

PolyMesh grid_mesh(int nu, int nv, bool periodic_u, bool periodic_v,
                   const std::function<Vec3(double, double)>& f) {
  PolyMesh mesh;
  const int cu = periodic_u ? nu : nu + 1;
  const int cv = periodic_v ? nv : nv + 1;
  std::vector<PolyMesh::VertexHandle> vh(cu * cv);
  for (int j = 0; j < cv; ++j)
    for (int i = 0; i < cu; ++i)
      vh[j * cu + i] = mesh.add_vertex(to_openmesh(f(double(i) / nu, double(j) / nv)));
  auto at = [&](int i, int j) { return vh[(j % cv) * cu + (i % cu)]; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  return mesh;
}

PolyMesh cube_grid_mesh(int n, const std::function<Vec3(const Vec3&)>& f) {
  PolyMesh mesh;
  std::map<std::array<int, 3>, PolyMesh::VertexHandle> index;
  auto vertex = [&](std::array<int, 3> g) -> PolyMesh::VertexHandle {
    auto it = index.find(g);
    if (it != index.end()) return it->second;
    const Vec3 p(2.0 * g[0] / n - 1.0, 2.0 * g[1] / n - 1.0, 2.0 * g[2] / n - 1.0);
    auto h = mesh.add_vertex(to_openmesh(f(p)));
    index.emplace(g, h);
    return h;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side <= 1; ++side) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          std::array<PolyMesh::VertexHandle, 4> q;
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> g{};
            g[axis] = side * n;
            g[a] = i + di[k];
            g[b] = j + dj[k];
            q[k] = vertex(g);
          }
          // Orientation: (a, b, axis) is right-handed, so this order faces +axis.
          if (side == 1)
            mesh.add_face(q[0], q[1], q[2], q[3]);
          else
            mesh.add_face(q[3], q[2], q[1], q[0]);
        }
      }
    }
  }
  return mesh;
}

Shape quad_plane(double size, int n, int refine) {
  auto f = [size](double u, double v) { return Vec3(size * u, size * v, 0.0); };
  return {"plane", grid_mesh(n, n, false, false, f),
          triangulate(grid_mesh(n * refine, n * refine, false, false, f)),
          [](const Vec3& p) { return p.z(); }};
}

Shape open_cylinder(double r, double height, int around, int along, int refine) {
  auto f = [=](double u, double v) {
    return Vec3(r * std::cos(2 * kPi * u), r * std::sin(2 * kPi * u), height * v);
  };
  return {"open_cylinder", grid_mesh(around, along, true, false, f),
          triangulate(grid_mesh(around * refine, along * refine, true, false, f)),
          [r](const Vec3& p) { return std::hypot(p.x(), p.y()) - r; }};
}

namespace {
// Square [-1,1]^2 -> unit disk (elliptical grid mapping); the square's border maps onto the circle.
Vec3 square_to_cylinder(const Vec3& p, double r, double height) {
  const double x = p.x(), y = p.y();
  const double u = x * std::sqrt(1.0 - y * y / 2.0), v = y * std::sqrt(1.0 - x * x / 2.0);
  return {r * u, r * v, 0.5 * height * p.z()};
}
}  // namespace

Shape closed_cylinder(double r, double height, int n, int refine) {
  auto f = [=](const Vec3& p) { return square_to_cylinder(p, r, height); };
  return {"closed_cylinder", cube_grid_mesh(n, f), triangulate(cube_grid_mesh(n * refine, f)),
          [=](const Vec3& p) {
            const double dr = std::hypot(p.x(), p.y()) - r;
            const double dz = std::abs(p.z()) - 0.5 * height;
            const double outside = std::hypot(std::max(dr, 0.0), std::max(dz, 0.0));
            return outside + std::min(std::max(dr, dz), 0.0);
          }};
}

Shape sphere(double r, int n, int refine) {
  auto f = [r](const Vec3& p) { return Vec3(r * p.normalized()); };
  return {"sphere", cube_grid_mesh(n, f), triangulate(cube_grid_mesh(n * refine, f)),
          [r](const Vec3& p) { return p.norm() - r; }};
}

Shape torus(double R, double r, int nu, int nv, int refine) {
  auto f = [=](double u, double v) {
    const double a = 2 * kPi * u, b = 2 * kPi * v;
    return Vec3((R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a),
                r * std::sin(b));
  };
  return {"torus", grid_mesh(nu, nv, true, true, f),
          triangulate(grid_mesh(nu * refine, nv * refine, true, true, f)),
          [=](const Vec3& p) { return std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) - r; }};
}

PolyMesh poly_mesh(const TriangleMesh& t) {
  PolyMesh m;
  for (const auto& p : t.vertices) m.add_vertex(to_openmesh(p));
  for (const auto& f : t.triangles)
    m.add_face(m.vertex_handle(f[0]), m.vertex_handle(f[1]), m.vertex_handle(f[2]));
  return m;
}

PolyMesh box_cut_differently(const std::array<int, 6>& n) {
  PolyMesh m;
  std::map<std::array<double, 3>, OpenMesh::VertexHandle> corners;
  const double s = 100;
  const std::array<std::array<Vec3, 3>, 6> sides = {{
      {Vec3(0, 0, 0), Vec3(0, s, 0), Vec3(s, 0, 0)},  // origin, u, v: u x v faces out
      {Vec3(0, 0, s), Vec3(s, 0, 0), Vec3(0, s, 0)},
      {Vec3(0, 0, 0), Vec3(s, 0, 0), Vec3(0, 0, s)},
      {Vec3(0, s, 0), Vec3(0, 0, s), Vec3(s, 0, 0)},
      {Vec3(0, 0, 0), Vec3(0, 0, s), Vec3(0, s, 0)},
      {Vec3(s, 0, 0), Vec3(0, s, 0), Vec3(0, 0, s)},
  }};
  for (int k = 0; k < 6; ++k) {
    const int g = n[k];
    std::vector<OpenMesh::VertexHandle> grid((g + 1) * (g + 1));
    for (int i = 0; i <= g; ++i)
      for (int j = 0; j <= g; ++j) {
        const Vec3 p = sides[k][0] + sides[k][1] * i / g + sides[k][2] * j / g;
        const bool corner = (i == 0 || i == g) && (j == 0 || j == g);
        auto& h = grid[i * (g + 1) + j];
        if (!corner) {
          h = m.add_vertex(to_openmesh(p));
          continue;
        }
        const auto [it, fresh] = corners.try_emplace({p.x(), p.y(), p.z()});
        if (fresh) it->second = m.add_vertex(to_openmesh(p));
        h = it->second;
      }
    for (int i = 0; i < g; ++i)
      for (int j = 0; j < g; ++j)
        m.add_face(std::vector<OpenMesh::VertexHandle>{
            grid[i * (g + 1) + j], grid[(i + 1) * (g + 1) + j], grid[(i + 1) * (g + 1) + j + 1],
            grid[i * (g + 1) + j + 1]});
  }
  return m;
}

TriangleMesh drum(double r, double height, int n, bool bottom, bool top, double draft_deg) {
  return lathe({{r, 0.0}, {r - height * std::tan(draft_deg * kPi / 180), height}}, n, bottom, top);
}

TriangleMesh lathe(const std::vector<std::array<double, 2>>& profile, int n, bool bottom,
                   bool top) {
  TriangleMesh m;
  for (const auto& [r, z] : profile)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      m.vertices.push_back({r * std::cos(a), r * std::sin(a), z});
    }
  const int last = static_cast<int>(profile.size()) - 1;
  for (int k = 0; k < last; ++k)
    for (int i = 0; i < n; ++i) {
      const int a = k * n + i, b = k * n + (i + 1) % n;
      m.triangles.push_back({a, b, b + n});
      m.triangles.push_back({a, b + n, a + n});
    }
  if (bottom) {
    m.vertices.push_back({0, 0, profile.front()[1]});
    const int c = static_cast<int>(m.vertices.size()) - 1;
    for (int i = 0; i < n; ++i) m.triangles.push_back({c, (i + 1) % n, i});
  }
  if (top) {
    m.vertices.push_back({0, 0, profile.back()[1]});
    const int c = static_cast<int>(m.vertices.size()) - 1, o = last * n;
    for (int i = 0; i < n; ++i) m.triangles.push_back({c, o + i, o + (i + 1) % n});
  }
  return m;
}

std::vector<std::array<double, 2>> vase_profile() {
  std::vector<std::array<double, 2>> profile;
  for (int k = 0; k <= 20; ++k) profile.push_back({60 + 25 * std::sin(kPi * k / 20), 10.0 * k});
  return profile;
}

TriangleMesh scripts_vase() {
  constexpr int nu = 64, nv = 40;
  constexpr double h = 200;
  TriangleMesh m;
  for (int j = 0; j <= nv; ++j) {
    const double z = h * j / nv;
    const double r = 50 + 25 * std::sin(1.5 * kPi * z / h) + 10 * std::cos(3 * kPi * z / h);
    for (int i = 0; i < nu; ++i) {
      const double a = 2 * kPi * i / nu;
      m.vertices.push_back({r * std::cos(a), r * std::sin(a), z});
    }
  }
  auto index = [](int i, int j) { return j * nu + i % nu; };
  for (int i = 0; i < nu; ++i)  // column by column, as the script's ring_faces
    for (int j = 0; j < nv; ++j) {
      const int a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  const int centre = static_cast<int>(m.vertices.size());
  m.vertices.push_back({0, 0, 0});
  for (int i = 0; i < nu; ++i) m.triangles.push_back({centre, index(i + 1, 0), index(i, 0)});
  return m;
}

TriangleMesh scripts_cone() {
  constexpr int nu = 64, nv = 30;
  constexpr double radius = 80, h = 150;
  TriangleMesh m;
  m.vertices.push_back({0, 0, h});
  for (int j = 1; j <= nv; ++j) {
    const double r = radius * j / nv, z = h - h * j / nv;
    for (int i = 0; i < nu; ++i) {
      const double a = 2 * kPi * i / nu;
      m.vertices.push_back({r * std::cos(a), r * std::sin(a), z});
    }
  }
  auto index = [](int i, int j) { return 1 + (j - 1) * nu + i % nu; };
  for (int i = 0; i < nu; ++i) m.triangles.push_back({0, index(i, 1), index(i + 1, 1)});
  for (int j = 1; j < nv; ++j)  // ring by ring, facing inward as the script's ring_faces
    for (int i = 0; i < nu; ++i) {
      const int a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
      m.triangles.push_back({a, d, c});
      m.triangles.push_back({a, c, b});
    }
  const int centre = static_cast<int>(m.vertices.size());
  m.vertices.push_back({0, 0, 0});
  for (int i = 0; i < nu; ++i) m.triangles.push_back({centre, index(i + 1, nv), index(i, nv)});
  return m;
}

TriangleMesh height_grid(int n, double extent,
                         const std::function<double(double, double)>& height) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -extent + 2 * extent * i / n, y = -extent + 2 * extent * j / n;
      m.vertices.push_back({x, y, height(x, y)});
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = j * (n + 1) + i, b = a + 1, c = (j + 1) * (n + 1) + i + 1, d = c - 1;
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

TriangleMesh scripts_terrain() {
  return height_grid(60, 100, [](double x, double y) {
    return 25 * std::sin(x / 30) * std::cos(y / 40) + 10 * std::exp(-(x * x + y * y) / 800);
  });
}

void write_obj(const TriangleMesh& mesh, const std::filesystem::path& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path.string());
  for (const Vec3& v : mesh.vertices) std::fprintf(f, "v %.6f %.6f %.6f\n", v.x(), v.y(), v.z());
  for (const auto& t : mesh.triangles)
    std::fprintf(f, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
  std::fclose(f);
}

TriangleMesh c_bench(double r_in, double r_out, double height, int n) {
  TriangleMesh m;
  const double a0 = 0.3, a1 = 2 * kPi - 0.3;
  // Per z: the outer arc's n + 1 points, then the inner arc's.
  for (const double z : {0.0, height})
    for (const double r : {r_out, r_in})
      for (int i = 0; i <= n; ++i) {
        const double a = a0 + (a1 - a0) * i / n;
        m.vertices.push_back({r * std::cos(a), r * std::sin(a), z});
      }
  const int k = n + 1;
  const auto at = [&](int level, int ring, int i) { return level * 2 * k + ring * k + i; };
  for (int i = 0; i < n; ++i) {
    // Caps: the band between the arcs, facing down at z = 0 and up at the top.
    m.triangles.push_back({at(0, 0, i), at(0, 1, i), at(0, 1, i + 1)});
    m.triangles.push_back({at(0, 0, i), at(0, 1, i + 1), at(0, 0, i + 1)});
    m.triangles.push_back({at(1, 0, i), at(1, 0, i + 1), at(1, 1, i + 1)});
    m.triangles.push_back({at(1, 0, i), at(1, 1, i + 1), at(1, 1, i)});
    // The outer wall facing out, the inner one facing the axis.
    m.triangles.push_back({at(0, 0, i), at(0, 0, i + 1), at(1, 0, i + 1)});
    m.triangles.push_back({at(0, 0, i), at(1, 0, i + 1), at(1, 0, i)});
    m.triangles.push_back({at(0, 1, i), at(1, 1, i + 1), at(0, 1, i + 1)});
    m.triangles.push_back({at(0, 1, i), at(1, 1, i), at(1, 1, i + 1)});
  }
  // The two flat ends.
  for (const auto& [i, flip] : {std::pair{0, false}, std::pair{n, true}}) {
    const std::array<int, 4> q = {at(0, 0, i), at(0, 1, i), at(1, 1, i), at(1, 0, i)};
    if (flip) {
      m.triangles.push_back({q[0], q[1], q[2]});
      m.triangles.push_back({q[0], q[2], q[3]});
    } else {
      m.triangles.push_back({q[0], q[2], q[1]});
      m.triangles.push_back({q[0], q[3], q[2]});
    }
  }
  return m;
}

}  // namespace kerfab::test
