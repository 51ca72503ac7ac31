#include "kerfab/eval/shell_clearance.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/parallel.h"

namespace kerfab {
namespace {

/// What one sample found: the nearest other stretch within the thickness.
struct Found {
  int part_a = -1, part_b = -1;
  double gap = 0, area = 0;
  Vec3 at, across;
  int inside_out = -1;  ///< at the narrowest gap: the part whose face is turned against the target
};

/// Samples along each side of a sub-quad at \p spacing: at least one.
std::pair<int, int> sample_grid(const std::array<Vec3, 4>& c, double spacing) {
  const double u = std::max((c[1] - c[0]).norm(), (c[2] - c[3]).norm());
  const double v = std::max((c[3] - c[0]).norm(), (c[2] - c[1]).norm());
  return {std::max(1, static_cast<int>(std::ceil(u / spacing))),
          std::max(1, static_cast<int>(std::ceil(v / spacing)))};
}

}  // namespace

ShellClearance shell_clearance(const Shell& shell, const ClearanceOptions& options,
                               const TargetSurface* target) {
  ShellClearance out;
  out.thickness = options.thickness;
  const double h = options.thickness;
  if (!(h > 0) || shell.faces.empty()) return out;
  const auto& v = shell.vertices;
  const auto& faces = shell.faces;
  const int nf = static_cast<int>(faces.size());
  auto corners = [&](int f) {
    return std::array<Vec3, 4>{v[faces[f][0]], v[faces[f][1]], v[faces[f][2]], v[faces[f][3]]};
  };

  // The sub-quads' triangles of positive area, each knowing its sub-quad.
  TriangleMesh mesh;
  mesh.vertices = v;
  std::vector<int> triangle_face;
  for (std::size_t t = 0; t < shell.triangles.triangles.size(); ++t) {
    const auto& tri = shell.triangles.triangles[t];
    if ((v[tri[1]] - v[tri[0]]).cross(v[tri[2]] - v[tri[0]]).norm() > 1e-12) {
      mesh.triangles.push_back(tri);
      triangle_face.push_back(static_cast<int>(t / 2));
    }
  }
  if (mesh.triangles.empty()) return out;
  const TargetSurface surface(mesh);

  std::vector<Vec3> normal(nf, Vec3::Zero());
  for (int f = 0; f < nf; ++f) {
    const auto c = corners(f);
    const Vec3 n = (c[2] - c[0]).cross(c[3] - c[1]);
    if (n.norm() > 0) normal[f] = n.normalized();
  }
  std::vector<std::vector<int>> vertex_faces(v.size());
  for (int f = 0; f < nf; ++f)
    for (int k : faces[f]) vertex_faces[k].push_back(f);

  // The borders between two parts, piece by piece along each coarse edge, with how far the
  // joints' mitres cut the parts back there: (h/2) / tan(theta/2) for the angle theta between
  // the two parts' faces (180 degrees flat), i.e. (h/2) tan(fold/2), the fold capped as the
  // joints cap it. A line from a point of one part meets the other
  // part within h only inside that reach (it meets it at x tan theta from a point x from the
  // fold, under h where x < h / tan theta = (h/2)(1/T - T) < (h/2)/T, T = tan(theta/2)): those
  // places are the mitres' work, not contacts.
  struct BorderPiece {
    Vec3 a, b;
    double reach = 0;
  };
  std::map<std::pair<int, int>, std::vector<BorderPiece>> borders;
  for (const auto& along : shell.lines) {
    std::map<int, Vec3> side;  // patch -> sum of its faces' normals at this coarse edge
    // Pairs of patches with a face at one and the same vertex of it: only those meet here. (A
    // wall as short as a sample joins the patches at its two ends without their meeting: a
    // slab 1 mm thick swept from its faces, each one plate, had its faces' overlap counted only
    // farther than 17 mm from every corner, h/2 tan(85 deg), as if they met there folded by
    // 180 degrees.)
    std::set<std::pair<int, int>> meet;
    for (int k : along) {
      if (k < 0 || k >= static_cast<int>(v.size())) continue;
      std::set<int> here;
      for (int f : vertex_faces[k]) {
        side.try_emplace(shell.face_part[f], Vec3::Zero()).first->second += normal[f];
        here.insert(shell.face_part[f]);
      }
      for (auto i = here.begin(); i != here.end(); ++i)
        for (auto j = std::next(i); j != here.end(); ++j) meet.insert({*i, *j});
    }
    if (side.size() < 2) continue;
    for (auto i = side.begin(); i != side.end(); ++i)
      for (auto j = std::next(i); j != side.end(); ++j) {
        if (!meet.contains({i->first, j->first})) continue;
        const double cos_fold =
            std::clamp(i->second.normalized().dot(j->second.normalized()), -1.0, 1.0);
        const double fold = std::min(std::acos(cos_fold), options.max_fold);
        const double reach = 0.5 * h * std::tan(0.5 * fold);
        auto& list = borders[{i->first, j->first}];
        for (std::size_t n = 0; n + 1 < along.size(); ++n)
          list.push_back({v[along[n]], v[along[n + 1]], reach});
      }
  }
  auto segment_distance = [](const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + s * ab)).norm();
  };
  // Inside the mitres' reach of a border between parts a and b [mm of slack: half a sample].
  auto mitred = [&](int a, int b, const Vec3& p, double slack) {
    if (a == b) return false;
    const auto it = borders.find({std::min(a, b), std::max(a, b)});
    if (it == borders.end()) return false;
    for (const BorderPiece& piece : it->second)
      if (segment_distance(p, piece.a, piece.b) <= piece.reach + slack) return true;
    return false;
  };

  // The spacing: the asked one, widened until the samples fit the budget.
  double spacing = options.sample_spacing > 0 ? options.sample_spacing : h;
  for (;;) {
    long count = 0;
    for (int f = 0; f < nf; ++f) {
      const auto [nu, nv] = sample_grid(corners(f), spacing);
      count += static_cast<long>(nu) * nv;
    }
    out.samples = count;
    if (count <= std::max(1L, options.max_samples)) break;
    spacing *= 1.25;
  }
  out.spacing = spacing;

  const double min_facing = std::cos(options.facing);
  std::vector<std::vector<Found>> found(nf);
  for_each_index(nf, hardware_threads(), [&](int f) {
    const auto c = corners(f);
    const auto [nu, nv] = sample_grid(c, spacing);
    const double area = 0.5 * (c[2] - c[0]).cross(c[3] - c[1]).norm() / (nu * nv);
    auto touches = [&](int g) {  // shares a corner with f
      for (int k : faces[f])
        for (int w : faces[g])
          if (k == w) return true;
      return false;
    };
    std::vector<Found>& mine = found[f];
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const double s = (i + 0.5) / nu, t = (j + 0.5) / nv;
        const Vec3 p =
            (1 - s) * (1 - t) * c[0] + s * (1 - t) * c[1] + s * t * c[2] + (1 - s) * t * c[3];
        const Vec3 du = (1 - t) * (c[1] - c[0]) + t * (c[2] - c[3]);
        const Vec3 dv = (1 - s) * (c[3] - c[0]) + s * (c[2] - c[1]);
        const Vec3 n = du.cross(dv);
        if (!(n.norm() > 1e-12)) continue;
        const Vec3 dir = n.normalized();
        for (const RayHit& hit : surface.hits_along_line(p, dir, h)) {
          const double gap = std::abs(hit.t);
          if (gap >= h) break;
          const int g = triangle_face[hit.triangle];
          // Its own sub-quad and those round it; a face not turned towards this one (a fold's
          // other side, seen at an angle); a border's mitred reach.
          if (g == f || touches(g) || dir.dot(normal[g]) > -min_facing) continue;
          const int a = shell.face_part[f], b = shell.face_part[g];
          if (mitred(a, b, p, 0.5 * spacing)) continue;
          // Per pair of parts: the area of the samples that meet the other, the narrowest gap.
          const int lo = std::min(a, b), hi = std::max(a, b);
          auto it = std::find_if(mine.begin(), mine.end(),
                                 [&](const Found& x) { return x.part_a == lo && x.part_b == hi; });
          if (it == mine.end()) it = mine.insert(mine.end(), Found{lo, hi, gap + 1, 0.0, p, p});
          if (gap < it->gap) {
            it->gap = gap, it->at = p, it->across = hit.point;
            it->inside_out = -1;
            if (target && dir.dot(target->closest(p).normal) < 0)
              it->inside_out = a;
            else if (target && normal[g].dot(target->closest(hit.point).normal) < 0)
              it->inside_out = b;
          }
          it->area += area;
          break;
        }
      }
  });

  std::map<std::pair<int, int>, ClearanceContact> pairs;
  for (const auto& list : found)
    for (const Found& x : list) {
      auto [it, added] = pairs.try_emplace({x.part_a, x.part_b});
      ClearanceContact& c = it->second;
      c.part_a = x.part_a;
      c.part_b = x.part_b;
      c.area += x.area;
      if (added || x.gap < c.gap)
        c.gap = x.gap, c.at = x.at, c.across = x.across, c.inside_out = x.inside_out;
    }
  for (const auto& [key, c] : pairs) out.contacts.push_back(c);
  std::stable_sort(out.contacts.begin(), out.contacts.end(),
                   [](const auto& a, const auto& b) { return a.gap < b.gap; });
  return out;
}

}  // namespace kerfab
