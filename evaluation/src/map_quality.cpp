#include "navaid/evaluation/map_quality.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {

namespace {

constexpr double kTileM = 10.0;
constexpr double kBelowGroundM = 1.0, kAboveGroundM = 4.0;

using Cell = std::array<long, 3>;

std::uint64_t pack(const Cell& c) {
  constexpr long kBias = 1L << 20;
  return static_cast<std::uint64_t>(c[0] + kBias) | (static_cast<std::uint64_t>(c[1] + kBias) << 21) |
         (static_cast<std::uint64_t>(c[2] + kBias) << 42);
}

}  // namespace

struct MapQualityAccumulator::Impl {
  const simulation::Scenario& scenario;
  double res;
  MapQualityConfig config;
  long z_lo = 0, z_hi = 0;  ///< truth cells' vertical index range
  std::unordered_map<std::uint64_t, simulation::OccupancyGrid3D> tiles;  ///< key: tile x, y packed
  std::vector<std::vector<Cell>> deliberate_cells;
  std::vector<DeliberateObstacleResult> deliberate;
  std::unordered_map<std::uint64_t, bool> mapped;     ///< map cell -> a truth voxel is near
  std::unordered_map<std::uint64_t, std::pair<SemanticClass, SemanticClass>> semantics;  ///< truth, map
  std::unordered_map<std::uint64_t, bool> recalled;   ///< observed truth cell -> detected
  std::size_t snapshots = 0;
  SE3 T_truth_map;

  Impl(const simulation::Scenario& s, double r, const MapQualityConfig& c) : scenario(s), res(r), config(c) {
    z_lo = static_cast<long>(std::floor((s.ground_z_m - kBelowGroundM) / res));
    z_hi = static_cast<long>(std::ceil((s.ground_z_m + kAboveGroundM) / res));
  }

  Cell cell_of(const Vec3& p) const {
    return {static_cast<long>(std::floor(p.x() / res)), static_cast<long>(std::floor(p.y() / res)),
            static_cast<long>(std::floor(p.z() / res))};
  }
  Vec3 center(const Cell& c) const { return res * Vec3(c[0] + 0.5, c[1] + 0.5, c[2] + 0.5); }

  const simulation::OccupancyGrid3D& tile(long tx, long ty) {
    const std::uint64_t key = pack({tx, ty, 0});
    auto it = tiles.find(key);
    if (it != tiles.end()) return it->second;
    // Whole cells: the tile's corner is a multiple of the resolution, so its cells are the map's.
    const long cells = static_cast<long>(std::llround(kTileM / res));
    simulation::AxisAlignedBox box;
    box.extend(Vec3(tx * cells * res, ty * cells * res, z_lo * res));
    box.extend(Vec3((tx + 1) * cells * res - 1e-9, (ty + 1) * cells * res - 1e-9, z_hi * res - 1e-9));
    return tiles.emplace(key, simulation::voxelize(scenario.world, res, box)).first->second;
  }

  /// Truth class of a cell (OccupancyGrid3D::kFree when free or outside the truth's z range).
  std::uint8_t truth(const Cell& c) {
    if (c[2] < z_lo || c[2] >= z_hi) return simulation::OccupancyGrid3D::kFree;
    const long cells = static_cast<long>(std::llround(kTileM / res));
    const long tx = static_cast<long>(std::floor(static_cast<double>(c[0]) / cells));
    const long ty = static_cast<long>(std::floor(static_cast<double>(c[1]) / cells));
    const auto& g = tile(tx, ty);
    const long ix = c[0] - tx * cells, iy = c[1] - ty * cells, iz = c[2] - z_lo;
    if (ix < 0 || iy < 0 || iz < 0 || ix >= g.size.x() || iy >= g.size.y() || iz >= g.size.z())
      return simulation::OccupancyGrid3D::kFree;
    return g.cells[g.index(static_cast<int>(ix), static_cast<int>(iy), static_cast<int>(iz))];
  }

  /// A truth voxel within tolerance of c: its class, the exact cell preferred.
  std::optional<SemanticClass> truth_near(const Cell& c) {
    const std::uint8_t own = truth(c);
    if (own != simulation::OccupancyGrid3D::kFree) return static_cast<SemanticClass>(own);
    const long t = config.tolerance_voxels;
    for (long dz = -t; dz <= t; ++dz)
      for (long dy = -t; dy <= t; ++dy)
        for (long dx = -t; dx <= t; ++dx) {
          const std::uint8_t v = truth({c[0] + dx, c[1] + dy, c[2] + dz});
          if (v != simulation::OccupancyGrid3D::kFree) return static_cast<SemanticClass>(v);
        }
    return std::nullopt;
  }

  bool near_set(const Cell& c, const std::unordered_set<std::uint64_t>& set) const {
    const long t = config.tolerance_voxels;
    for (long dz = -t; dz <= t; ++dz)
      for (long dy = -t; dy <= t; ++dy)
        for (long dx = -t; dx <= t; ++dx)
          if (set.count(pack({c[0] + dx, c[1] + dy, c[2] + dz}))) return true;
    return false;
  }

  void drop_far_tiles(const Vec3& user) {
    for (auto it = tiles.begin(); it != tiles.end();) {
      const auto& g = it->second;
      const Vec3 mid = g.origin + 0.5 * kTileM * Vec3(1, 1, 0);
      if ((mid - user).head<2>().norm() > 4.0 * kTileM) it = tiles.erase(it);
      else ++it;
    }
  }
};

MapQualityAccumulator::MapQualityAccumulator(const simulation::Scenario& scenario, double resolution_m,
                                             const MapQualityConfig& config)
    : impl_(std::make_unique<Impl>(scenario, resolution_m, config)) {
  if (!(resolution_m > 0.0)) throw Error("map quality: resolution must be positive");
  std::vector<std::pair<std::uint32_t, bool>> obstacles;
  for (const auto i : scenario.deliberate_obstacles) obstacles.emplace_back(i, true);
  for (const auto i : scenario.placed_obstacles) obstacles.emplace_back(i, false);
  for (const auto& [index, on_path] : obstacles) {
    const auto& prim = scenario.world.primitive(index);
    simulation::World alone;
    alone.add(prim.shape, prim.surface);
    simulation::AxisAlignedBox box = alone.bounds();
    const Vec3 lo = (box.min / resolution_m).array().floor().matrix() * resolution_m;
    simulation::AxisAlignedBox snapped;
    snapped.extend(lo);
    snapped.extend(box.max);
    const auto grid = simulation::voxelize(alone, resolution_m, snapped);
    std::vector<Cell> cells;
    for (int z = 0; z < grid.size.z(); ++z)
      for (int y = 0; y < grid.size.y(); ++y)
        for (int x = 0; x < grid.size.x(); ++x)
          if (grid.occupied(x, y, z)) cells.push_back(impl_->cell_of(grid.center(x, y, z)));
    DeliberateObstacleResult r;
    r.primitive = index;
    r.on_path = on_path;
    r.semantic = prim.surface.semantic;
    r.min_z_m = box.min.z();
    r.max_z_m = box.max.z();
    impl_->deliberate.push_back(r);
    impl_->deliberate_cells.push_back(std::move(cells));
  }
}

MapQualityAccumulator::~MapQualityAccumulator() = default;

void MapQualityAccumulator::set_map_to_truth(const SE3& T_truth_map) { impl_->T_truth_map = T_truth_map; }

void MapQualityAccumulator::add_snapshot(const mapping::SemanticMap& map, const Vec3& user_map) {
  Impl& m = *impl_;
  ++m.snapshots;
  const SE3 T_map_truth = m.T_truth_map.inverse();
  const Vec3 user = m.T_truth_map * user_map;  // everything below is in the truth's world
  const double r = m.config.path_radius_m;
  auto near_user = [&](const Vec3& p) { return (p - user).head<2>().norm() <= r; };
  // The map's occupied voxels near the user: precision and semantics.
  std::unordered_set<std::uint64_t> occupied;
  for (const auto& v : map.occupied_voxels()) {
    const Vec3 p = m.T_truth_map * v.center_W;
    if (!near_user(p)) continue;
    const Cell c = m.cell_of(p);
    const std::uint64_t key = pack(c);
    occupied.insert(key);
    const auto truth = m.truth_near(c);
    m.mapped[key] = truth.has_value();
    // Semantic accuracy needs a class on both sides (truth objects of class unlabeled have none).
    if (truth && *truth != SemanticClass::kUnlabeled && v.semantic != SemanticClass::kUnlabeled)
      m.semantics[key] = {*truth, v.semantic};
    else m.semantics.erase(key);
  }
  // Truth voxels near the user that the map has observed: recall.
  const Vec3 lo = user - Vec3(r, r, map.config().window_below_m);
  const Vec3 hi = user + Vec3(r, r, map.config().window_above_m);
  const Cell c0 = m.cell_of(lo), c1 = m.cell_of(hi);
  for (long z = std::max(c0[2], m.z_lo); z <= std::min(c1[2], m.z_hi - 1); ++z)
    for (long y = c0[1]; y <= c1[1]; ++y)
      for (long x = c0[0]; x <= c1[0]; ++x) {
        const Cell c{x, y, z};
        if (m.truth(c) == simulation::OccupancyGrid3D::kFree || !near_user(m.center(c))) continue;
        const bool detected = m.near_set(c, occupied);
        if (detected || map.voxel_at(T_map_truth * m.center(c))) m.recalled[pack(c)] = detected;
      }
  // Deliberate obstacles.
  for (std::size_t i = 0; i < m.deliberate.size(); ++i) {
    auto& d = m.deliberate[i];
    bool reach = false;
    for (const Cell& c : m.deliberate_cells[i]) {
      if (!near_user(m.center(c))) continue;
      reach = true;
      if (m.near_set(c, occupied)) {
        d.detected = true;
        break;
      }
    }
    d.in_reach = d.in_reach || reach;
  }
  m.drop_far_tiles(user);
}

MapQuality MapQualityAccumulator::result() const {
  const Impl& m = *impl_;
  MapQuality q;
  q.snapshots = m.snapshots;
  for (const auto& [key, ok] : m.mapped) (ok ? q.true_positive : q.false_positive)++;
  for (const auto& [key, detected] : m.recalled) q.false_negative += !detected;
  std::size_t recalled = 0;
  for (const auto& [key, detected] : m.recalled) recalled += detected;
  q.precision = q.true_positive + q.false_positive ? static_cast<double>(q.true_positive) / (q.true_positive + q.false_positive) : 0.0;
  q.recall = m.recalled.empty() ? 0.0 : static_cast<double>(recalled) / static_cast<double>(m.recalled.size());
  q.f1 = q.precision + q.recall > 0 ? 2 * q.precision * q.recall / (q.precision + q.recall) : 0.0;
  std::size_t correct = 0;
  for (const auto& [key, pair] : m.semantics) {
    auto& acc = q.per_class[pair.first];
    ++acc.total;
    if (pair.first == pair.second) ++acc.correct, ++correct;
  }
  q.semantic_accuracy = m.semantics.empty() ? 0.0 : static_cast<double>(correct) / static_cast<double>(m.semantics.size());
  q.deliberate = m.deliberate;
  std::size_t reach = 0, found = 0, reach_path = 0, found_path = 0;
  for (const auto& d : m.deliberate) {
    reach += d.in_reach, found += d.in_reach && d.detected;
    if (d.on_path) reach_path += d.in_reach, found_path += d.in_reach && d.detected;
  }
  q.in_reach = reach;
  q.on_path_in_reach = reach_path;
  q.detected = found;
  q.on_path_detected = found_path;
  q.deliberate_recall = reach ? static_cast<double>(found) / static_cast<double>(reach) : 0.0;
  q.on_path_recall = reach_path ? static_cast<double>(found_path) / static_cast<double>(reach_path) : 0.0;
  return q;
}

}  // namespace navaid::evaluation
