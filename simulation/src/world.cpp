#include "navaid/simulation/world.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

namespace {


bool finite_pose(const SE3& T) { return T.q.coeffs().allFinite() && T.t.allFinite(); }
bool positive_finite(double v) { return std::isfinite(v) && v > 0.0; }

[[noreturn]] void invalid(const std::string& what) { throw Error("World::add: " + what); }

double signed_area(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0, n = poly.size(); i < n; ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % n];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

double cross2(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// Ear clipping of a counter-clockwise simple polygon; returns index triples (CCW).
std::vector<std::array<std::uint32_t, 3>> ear_clip(const std::vector<Vec2>& poly) {
  std::vector<std::uint32_t> idx(poly.size());
  std::iota(idx.begin(), idx.end(), 0u);
  std::vector<std::array<std::uint32_t, 3>> out;
  std::size_t guard = 0;
  while (idx.size() > 3 && guard < poly.size() * poly.size() + 10) {
    ++guard;
    bool clipped = false;
    const std::size_t n = idx.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t a = idx[(i + n - 1) % n], b = idx[i], c = idx[(i + 1) % n];
      if (cross2(poly[a], poly[b], poly[c]) <= 0.0) continue;  // reflex or degenerate
      bool contains = false;
      for (std::uint32_t k : idx) {
        if (k == a || k == b || k == c) continue;
        if (cross2(poly[a], poly[b], poly[k]) >= 0.0 && cross2(poly[b], poly[c], poly[k]) >= 0.0 &&
            cross2(poly[c], poly[a], poly[k]) >= 0.0) {
          contains = true;
          break;
        }
      }
      if (contains) continue;
      out.push_back({a, b, c});
      idx.erase(idx.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
      break;
    }
    if (!clipped) break;  // numerically degenerate remainder: fan it
  }
  for (std::size_t i = 1; i + 1 < idx.size(); ++i) out.push_back({idx[0], idx[i], idx[i + 1]});
  return out;
}

struct MeshAppender {
  TriangleMesh& mesh;
  std::uint32_t prim;
  std::uint32_t vertex(const Vec3& p) {
    mesh.vertices.push_back(p);
    return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  }
  void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    mesh.triangles.push_back({a, b, c});
    mesh.triangle_primitive.push_back(prim);
  }
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {  // CCW a b c d
    tri(a, b, c);
    tri(a, c, d);
  }
};

void append(const PlanePatch& s, MeshAppender& m) {
  const std::uint32_t a = m.vertex(s.T_W_P * Vec3(-s.half_x, -s.half_y, 0.0));
  const std::uint32_t b = m.vertex(s.T_W_P * Vec3(s.half_x, -s.half_y, 0.0));
  const std::uint32_t c = m.vertex(s.T_W_P * Vec3(s.half_x, s.half_y, 0.0));
  const std::uint32_t d = m.vertex(s.T_W_P * Vec3(-s.half_x, s.half_y, 0.0));
  m.quad(a, b, c, d);
}

void append(const Box& s, MeshAppender& m) {
  std::array<std::uint32_t, 8> v{};
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
    v[static_cast<std::size_t>(i)] = m.vertex(s.T_W_O * corner.cwiseProduct(s.half_extents));
  }
  // Faces CCW seen from outside.
  m.quad(v[0], v[2], v[3], v[1]);  // -z
  m.quad(v[4], v[5], v[7], v[6]);  // +z
  m.quad(v[0], v[1], v[5], v[4]);  // -y
  m.quad(v[2], v[6], v[7], v[3]);  // +y
  m.quad(v[0], v[4], v[6], v[2]);  // -x
  m.quad(v[1], v[3], v[7], v[5]);  // +x
}

void append(const VerticalCylinder& s, MeshAppender& m, int segments) {
  const std::uint32_t bottom_c = m.vertex(s.base_center);
  const std::uint32_t top_c = m.vertex(s.base_center + Vec3(0, 0, s.height));
  std::vector<std::uint32_t> lo, hi;
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * M_PI * i / segments;
    const Vec3 p = s.base_center + Vec3(s.radius * std::cos(a), s.radius * std::sin(a), 0.0);
    lo.push_back(m.vertex(p));
    hi.push_back(m.vertex(p + Vec3(0, 0, s.height)));
  }
  for (std::size_t i = 0, n = lo.size(); i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    m.quad(lo[i], lo[j], hi[j], hi[i]);
    m.tri(top_c, hi[i], hi[j]);
    m.tri(bottom_c, lo[j], lo[i]);
  }
}

void append(const Ellipsoid& s, MeshAppender& m, int slices, int stacks) {
  const std::uint32_t south = m.vertex(s.T_W_O * Vec3(0, 0, -s.radii.z()));
  const std::uint32_t north = m.vertex(s.T_W_O * Vec3(0, 0, s.radii.z()));
  std::vector<std::vector<std::uint32_t>> rings;  // stacks - 1 rings from south to north
  for (int k = 1; k < stacks; ++k) {
    const double theta = -0.5 * M_PI + M_PI * k / stacks;
    std::vector<std::uint32_t> ring;
    for (int i = 0; i < slices; ++i) {
      const double phi = 2.0 * M_PI * i / slices;
      const Vec3 u(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta));
      ring.push_back(m.vertex(s.T_W_O * u.cwiseProduct(s.radii)));
    }
    rings.push_back(std::move(ring));
  }
  const std::size_t n = static_cast<std::size_t>(slices);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    m.tri(south, rings.front()[j], rings.front()[i]);
    m.tri(north, rings.back()[i], rings.back()[j]);
    for (std::size_t r = 0; r + 1 < rings.size(); ++r) m.quad(rings[r][i], rings[r][j], rings[r + 1][j], rings[r + 1][i]);
  }
}

void append(const ExtrudedPolygon& s, MeshAppender& m) {
  std::vector<Vec2> poly = s.polygon;
  if (signed_area(poly) < 0.0) std::reverse(poly.begin(), poly.end());
  const std::uint32_t base = static_cast<std::uint32_t>(m.mesh.vertices.size());
  const auto n = static_cast<std::uint32_t>(poly.size());
  for (const Vec2& p : poly) m.vertex(Vec3(p.x(), p.y(), s.z_min));
  for (const Vec2& p : poly) m.vertex(Vec3(p.x(), p.y(), s.z_max));
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.quad(base + i, base + j, base + n + j, base + n + i);
  }
  for (const auto& t : ear_clip(poly)) {
    m.tri(base + n + t[0], base + n + t[1], base + n + t[2]);  // top, CCW from +z
    m.tri(base + t[0], base + t[2], base + t[1]);              // bottom, CCW from -z
  }
}

}  // namespace

void AxisAlignedBox::extend(const Vec3& p) {
  if (empty) {
    min = max = p;
    empty = false;
  } else {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
}

void AxisAlignedBox::extend(const AxisAlignedBox& b) {
  if (b.empty) return;
  extend(b.min);
  extend(b.max);
}

std::uint32_t World::add(const Shape& shape, const Surface& surface) {
  if (!positive_finite(surface.texture_scale)) invalid("texture_scale must be finite and > 0");
  if (!(surface.albedo > 0.0 && surface.albedo <= 1.0)) invalid("albedo must be in (0, 1]");
  if (!is_valid_semantic_id(static_cast<std::uint8_t>(surface.semantic))) invalid("unknown semantic class id");
  std::visit(
      [](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, PlanePatch>) {
          if (!finite_pose(s.T_W_P) || !positive_finite(s.half_x) || !positive_finite(s.half_y))
            invalid("plane patch needs a finite pose and half sizes > 0");
        } else if constexpr (std::is_same_v<T, Box>) {
          if (!finite_pose(s.T_W_O) || !s.half_extents.allFinite() || (s.half_extents.array() <= 0.0).any())
            invalid("box needs a finite pose and half extents > 0");
        } else if constexpr (std::is_same_v<T, VerticalCylinder>) {
          if (!s.base_center.allFinite() || !positive_finite(s.radius) || !positive_finite(s.height))
            invalid("cylinder needs a finite base centre, radius > 0 and height > 0");
        } else if constexpr (std::is_same_v<T, Ellipsoid>) {
          if (!finite_pose(s.T_W_O) || !s.radii.allFinite() || (s.radii.array() <= 0.0).any())
            invalid("ellipsoid needs a finite pose and radii > 0");
        } else {
          if (s.polygon.size() < 3) invalid("extruded polygon needs >= 3 vertices");
          for (const Vec2& p : s.polygon)
            if (!p.allFinite()) invalid("extruded polygon has a non-finite vertex");
          if (!(std::abs(signed_area(s.polygon)) > 0.0)) invalid("extruded polygon has zero area");
          if (!std::isfinite(s.z_min) || !std::isfinite(s.z_max) || !(s.z_max > s.z_min))
            invalid("extruded polygon needs finite z_min < z_max");
        }
      },
      shape);
  // GCC 12 reports a false -Wmaybe-uninitialized inside std::variant's copy here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
  primitives_.push_back(Primitive{shape, surface});
  images_.emplace_back();
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
  return static_cast<std::uint32_t>(primitives_.size() - 1);
}

std::uint32_t World::add(const Shape& shape, const Surface& surface, ImageTexture image) {
  if (image) {
    const ImageU8& img = *image;
    if (img.width <= 0 || img.height <= 0 || img.channels != 1 ||
        img.pixels.size() != static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height))
      invalid("an image texture needs a non-empty one-channel image");
    if (!std::holds_alternative<PlanePatch>(shape)) invalid("an image texture can only be put on a plane patch");
  }
  const std::uint32_t i = add(shape, surface);
  images_.back() = std::move(image);
  return i;
}

void append_triangles(const Shape& shape, std::uint32_t index, const Tessellation& tess, TriangleMesh& mesh) {
  if (tess.cylinder_segments < 3 || tess.ellipsoid_slices < 3 || tess.ellipsoid_stacks < 2)
    throw Error("Tessellation: cylinder_segments >= 3, ellipsoid_slices >= 3, ellipsoid_stacks >= 2 required");
  MeshAppender m{mesh, index};
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, VerticalCylinder>) {
          append(s, m, tess.cylinder_segments);
        } else if constexpr (std::is_same_v<T, Ellipsoid>) {
          append(s, m, tess.ellipsoid_slices, tess.ellipsoid_stacks);
        } else {
          append(s, m);
        }
      },
      shape);
}

TriangleMesh World::triangulate(const Tessellation& tess) const {
  if (tess.cylinder_segments < 3 || tess.ellipsoid_slices < 3 || tess.ellipsoid_stacks < 2)
    throw Error("Tessellation: cylinder_segments >= 3, ellipsoid_slices >= 3, ellipsoid_stacks >= 2 required");
  TriangleMesh mesh;
  for (std::size_t i = 0; i < primitives_.size(); ++i)
    append_triangles(primitives_[i].shape, static_cast<std::uint32_t>(i), tess, mesh);
  return mesh;
}

AxisAlignedBox bounds_of(const Shape& shape) {
  AxisAlignedBox b;
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, PlanePatch>) {
          for (double sx : {-1.0, 1.0})
            for (double sy : {-1.0, 1.0}) b.extend(s.T_W_P * Vec3(sx * s.half_x, sy * s.half_y, 0.0));
        } else if constexpr (std::is_same_v<T, Box>) {
          const Vec3 e = s.T_W_O.rotation().cwiseAbs() * s.half_extents;
          b.extend(s.T_W_O.t - e);
          b.extend(s.T_W_O.t + e);
        } else if constexpr (std::is_same_v<T, VerticalCylinder>) {
          b.extend(s.base_center - Vec3(s.radius, s.radius, 0.0));
          b.extend(s.base_center + Vec3(s.radius, s.radius, s.height));
        } else if constexpr (std::is_same_v<T, Ellipsoid>) {
          // Support function of an ellipsoid: extent_i = |row_i(R diag(r))|.
          const Mat3 M = s.T_W_O.rotation() * s.radii.asDiagonal();
          const Vec3 e = M.rowwise().norm();
          b.extend(s.T_W_O.t - e);
          b.extend(s.T_W_O.t + e);
        } else {
          for (const Vec2& p : s.polygon) {
            b.extend(Vec3(p.x(), p.y(), s.z_min));
            b.extend(Vec3(p.x(), p.y(), s.z_max));
          }
        }
      },
      shape);
  return b;
}

AxisAlignedBox World::bounds() const {
  AxisAlignedBox b;
  for (const auto& p : primitives_) b.extend(bounds_of(p.shape));
  return b;
}

}  // namespace navaid::simulation
