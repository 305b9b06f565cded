#include "navaid/simulation/occupancy_export.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

#include "navaid/core/errors.hpp"
#include "scenarios/shape_queries.hpp"

namespace navaid::simulation {

namespace {

constexpr double kEps = 1e-9;       // interior overlap margin [m]
constexpr double kHalfOpen = 1e-7;  // a plane patch on a voxel's max face belongs to the next voxel

struct Cell {
  Vec3 lo, hi;
  Vec3 center() const { return 0.5 * (lo + hi); }
  Vec3 half() const { return 0.5 * (hi - lo); }
};

// Separating-axis test between an oriented box (centre c, axes columns of R, half extents e) and
// an axis-aligned cell. strict: the interiors must overlap by more than kEps; otherwise touching
// counts (for zero-thickness patches).
struct ObbTester {
  Vec3 c;
  Mat3 R;
  Vec3 e;
  std::vector<Vec3> axes;

  ObbTester(const SE3& T, const Vec3& half) : c(T.t), R(T.rotation()), e(half) {
    for (int i = 0; i < 3; ++i) axes.push_back(Vec3::Unit(i));
    for (int i = 0; i < 3; ++i) axes.push_back(R.col(i));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const Vec3 a = Vec3::Unit(i).cross(R.col(j));
        if (a.norm() > 1e-6) axes.push_back(a.normalized());
      }
  }

  bool overlaps(const Cell& cell, bool strict) const {
    const Vec3 v = cell.center(), h = cell.half();
    const Vec3 d = c - v;
    for (const Vec3& L : axes) {
      const double rb = e.x() * std::abs(R.col(0).dot(L)) + e.y() * std::abs(R.col(1).dot(L)) + e.z() * std::abs(R.col(2).dot(L));
      const double ra = h.x() * std::abs(L.x()) + h.y() * std::abs(L.y()) + h.z() * std::abs(L.z());
      const double dist = std::abs(d.dot(L));
      if (strict ? dist >= ra + rb - kEps : dist > ra + rb + kEps) return false;
    }
    return true;
  }
};

bool z_overlap(double z0, double z1, const Cell& cell) { return z1 > cell.lo.z() + kEps && z0 < cell.hi.z() - kEps; }

// Ellipsoid (x - c)^T M (x - c) < 1 against a cell: minimum of the quadratic over the cell by
// projected Gauss-Seidel (converges for a positive definite M), with early exits.
struct EllipsoidTester {
  Vec3 c;
  Mat3 M;
  double r_min;
  EllipsoidTester(const Ellipsoid& e) : c(e.T_W_O.t), r_min(e.radii.minCoeff()) {
    const Mat3 R = e.T_W_O.rotation();
    M = R * e.radii.cwiseInverse().cwiseAbs2().asDiagonal() * R.transpose();
  }
  double f(const Vec3& x) const { return (x - c).dot(M * (x - c)); }
  bool overlaps(const Cell& cell) const {
    const Vec3 v = cell.center();
    const double fv = f(v);
    if (fv < 1.0) return true;
    if (std::sqrt(fv) - cell.half().norm() / r_min >= 1.0) return false;
    Vec3 x = c.cwiseMax(cell.lo).cwiseMin(cell.hi);
    for (int sweep = 0; sweep < 60; ++sweep) {
      for (int i = 0; i < 3; ++i) {
        double s = 0.0;
        for (int j = 0; j < 3; ++j)
          if (j != i) s += M(i, j) * (x[j] - c[j]);
        x[i] = std::clamp(c[i] - s / M(i, i), cell.lo[i], cell.hi[i]);
      }
      if (f(x) < 1.0 - kEps) return true;
    }
    return false;
  }
};

// Interior-overlap predicate of one primitive against a cell.
std::function<bool(const Cell&)> overlap_test(const Shape& shape) {
  return std::visit(
      [](const auto& s) -> std::function<bool(const Cell&)> {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Box>) {
          return [t = ObbTester(s.T_W_O, s.half_extents)](const Cell& c) { return t.overlaps(c, true); };
        } else if constexpr (std::is_same_v<T, PlanePatch>) {
          return [t = ObbTester(s.T_W_P, Vec3(s.half_x, s.half_y, 0.0))](const Cell& c) {
            return t.overlaps(Cell{c.lo, c.hi - Vec3::Constant(kHalfOpen)}, false);
          };
        } else if constexpr (std::is_same_v<T, VerticalCylinder>) {
          return [s](const Cell& c) {
            if (!z_overlap(s.base_center.z(), s.base_center.z() + s.height, c)) return false;
            const Vec2 q = s.base_center.template head<2>().cwiseMax(c.lo.head<2>()).cwiseMin(c.hi.head<2>());
            return (q - s.base_center.template head<2>()).norm() < s.radius - kEps;
          };
        } else if constexpr (std::is_same_v<T, ExtrudedPolygon>) {
          return [s](const Cell& c) {
            if (!z_overlap(s.z_min, s.z_max, c)) return false;
            const Vec2 lo2 = c.lo.head<2>() + Vec2::Constant(kEps), hi2 = c.hi.head<2>() - Vec2::Constant(kEps);
            if (detail::point_in_polygon(s.polygon, 0.5 * (lo2 + hi2))) return true;
            for (std::size_t i = 0, j = s.polygon.size() - 1; i < s.polygon.size(); j = i++)
              if (detail::segment_crosses_open_rect(s.polygon[j], s.polygon[i], lo2, hi2)) return true;
            return false;
          };
        } else {
          return [t = EllipsoidTester(s)](const Cell& c) { return t.overlaps(c); };
        }
      },
      shape);
}

}  // namespace

std::size_t OccupancyGrid3D::count_occupied() const {
  return static_cast<std::size_t>(std::count_if(cells.begin(), cells.end(), [](std::uint8_t v) { return v != kFree; }));
}

OccupancyGrid3D voxelize(const World& world, double resolution_m, const AxisAlignedBox& bounds) {
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) throw Error("voxelize: resolution must be finite and > 0");
  if (bounds.empty || !(bounds.max.array() > bounds.min.array()).all())
    throw Error("voxelize: bounds must be non-empty with max > min on every axis");
  OccupancyGrid3D g;
  g.origin = bounds.min;
  g.resolution_m = resolution_m;
  double total = 1.0;
  for (int a = 0; a < 3; ++a) {
    g.size[a] = std::max(1, static_cast<int>(std::ceil((bounds.max[a] - bounds.min[a]) / resolution_m - 1e-9)));
    total *= g.size[a];
  }
  if (total > 2147483648.0) throw Error("voxelize: more than 2^31 voxels; use a coarser resolution or smaller bounds");
  g.cells.assign(static_cast<std::size_t>(total), OccupancyGrid3D::kFree);

  for (const Primitive& prim : world.primitives()) {
    const AxisAlignedBox b = bounds_of(prim.shape);
    Eigen::Vector3i lo, hi;
    bool outside = false;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(0, static_cast<int>(std::floor((b.min[a] - g.origin[a]) / resolution_m)) - 1);
      hi[a] = std::min(g.size[a] - 1, static_cast<int>(std::floor((b.max[a] - g.origin[a]) / resolution_m)) + 1);
      outside = outside || lo[a] > hi[a];
    }
    if (outside) continue;
    const auto label = static_cast<std::uint8_t>(prim.surface.semantic);
    const std::function<bool(const Cell&)> test = overlap_test(prim.shape);
    for (int iz = lo.z(); iz <= hi.z(); ++iz)
      for (int iy = lo.y(); iy <= hi.y(); ++iy)
        for (int ix = lo.x(); ix <= hi.x(); ++ix) {
          const Vec3 cmin = g.origin + resolution_m * Vec3(ix, iy, iz);
          if (test(Cell{cmin, cmin + Vec3::Constant(resolution_m)})) g.cells[g.index(ix, iy, iz)] = label;
        }
  }
  return g;
}

ImageU8 occupancy_slice(const OccupancyGrid3D& grid, double z_min, double z_max) {
  ImageU8 img(grid.size.x(), grid.size.y(), 1, 254);
  for (int iz = 0; iz < grid.size.z(); ++iz) {
    const double zc = grid.center(0, 0, iz).z();
    if (zc < z_min || zc > z_max) continue;
    for (int iy = 0; iy < grid.size.y(); ++iy)
      for (int ix = 0; ix < grid.size.x(); ++ix)
        if (grid.occupied(ix, iy, iz)) img.at(ix, grid.size.y() - 1 - iy) = 0;
  }
  return img;
}

void write_occupancy_map(const OccupancyGrid3D& grid, double z_min, double z_max, const std::string& stem) {
  const ImageU8 img = occupancy_slice(grid, z_min, z_max);
  const std::string pgm = stem + ".pgm", yaml = stem + ".yaml";
  {
    std::ofstream out(pgm, std::ios::binary);
    if (!out) throw IoError(pgm, "cannot open for writing");
    out << "P5\n" << img.width << ' ' << img.height << "\n255\n";
    out.write(reinterpret_cast<const char*>(img.data()), static_cast<std::streamsize>(img.pixels.size()));
    if (!out) throw IoError(pgm, "write failed");
  }
  std::ofstream out(yaml);
  if (!out) throw IoError(yaml, "cannot open for writing");
  out << std::setprecision(10);
  out << "image: " << std::filesystem::path(pgm).filename().string() << "\n"
      << "resolution: " << grid.resolution_m << "\n"
      << "origin: [" << grid.origin.x() << ", " << grid.origin.y() << ", 0.0]\n"
      << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
      << "# navaid: occupied when any voxel with centre z in [" << z_min << ", " << z_max << "] m is occupied\n";
  if (!out) throw IoError(yaml, "write failed");
}

void write_voxel_csv(const OccupancyGrid3D& grid, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw IoError(path, "cannot open for writing");
  out << std::setprecision(10);
  out << "# navaid voxel list v1\n"
      << "# resolution_m=" << grid.resolution_m << "\n"
      << "# origin_m=" << grid.origin.x() << "," << grid.origin.y() << "," << grid.origin.z() << "\n"
      << "# size=" << grid.size.x() << "," << grid.size.y() << "," << grid.size.z() << "\n"
      << "ix,iy,iz,x,y,z,class\n";
  for (int iz = 0; iz < grid.size.z(); ++iz)
    for (int iy = 0; iy < grid.size.y(); ++iy)
      for (int ix = 0; ix < grid.size.x(); ++ix) {
        const std::uint8_t v = grid.cells[grid.index(ix, iy, iz)];
        if (v == OccupancyGrid3D::kFree) continue;
        const Vec3 c = grid.center(ix, iy, iz);
        out << ix << ',' << iy << ',' << iz << ',' << c.x() << ',' << c.y() << ',' << c.z() << ','
            << semantic_class_name(static_cast<SemanticClass>(v)) << '\n';
      }
  if (!out) throw IoError(path, "write failed");
}

}  // namespace navaid::simulation
