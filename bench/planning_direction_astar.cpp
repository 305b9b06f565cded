// Direction A* (eLabrador Alg. 1) on 10 m x 10 m windows of the real Willow office map at its
// 0.05 m resolution (200 x 200 cells, the size of the local cost map at that resolution), n_s =
// 36 boundary targets: the one search toward all targets against Alg. 1's n_s separate A*
// searches, side by side. Counter `ratio` = one-search time / separate-searches time (goal <= 0.2);
// `nodes_ratio` the same for nodes expanded. Also plain A* across the whole office map.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <vector>

#include "navaid/io/occupancy_map_file.hpp"
#include "navaid/planning/direction_astar.hpp"
#include "navaid/planning/grid_astar.hpp"
#include "navaid/planning/occupancy_cost_map.hpp"

namespace {

using namespace navaid;
using namespace navaid::planning;
using mapping::Vec2;

const io::OccupancyMapFile& willow() {
  static const io::OccupancyMapFile m =
      io::read_occupancy_map(std::string(NAVAID_SHARED_DATA_DIR) + "/ros-map-willow/willow-full-0.05.yaml");
  return m;
}

OccupancyValue value(const io::OccupancyMapFile& m, int x, int y) {
  switch (m.cell(x, y)) {
    case io::OccupancyCell::kFree: return OccupancyValue::kFree;
    case io::OccupancyCell::kOccupied: return OccupancyValue::kOccupied;
    case io::OccupancyCell::kUnknown: break;
  }
  return OccupancyValue::kUnknown;
}

mapping::CostMap whole_map() {
  const io::OccupancyMapFile& m = willow();
  return cost_map_from_occupancy(m.image.width, m.image.height, m.resolution_m, Vec2::Zero(),
                                 [&](int x, int y) { return value(m, x, y); }, OccupancyCostConfig{});
}

// The 10 m window around p (the local map the Mapper hands over), cut from the office map.
mapping::CostMap window_around(const Vec2& p) {
  const io::OccupancyMapFile& m = willow();
  const int n = 200;
  const int x0 = static_cast<int>(p.x() / m.resolution_m) - n / 2;
  const int row0 = m.image.height - 1 - (static_cast<int>(p.y() / m.resolution_m) + n / 2 - 1);  // top row of the crop
  return cost_map_from_occupancy(n, n, m.resolution_m, Vec2(x0 * m.resolution_m, p.y() - n / 2 * m.resolution_m),
                                 [&](int x, int y) { return value(m, x0 + x, row0 + y); }, OccupancyCostConfig{});
}

// Free places in corridors and rooms of the office (map frame, origin at the lower-left pixel).
const std::vector<Vec2> kStarts = {{10.0, 10.0}, {20.0, 25.0}, {35.0, 40.0}, {15.0, 40.0}};
const std::vector<double> kDirections = {0.0, 1.5707963, 3.14159265, -0.8};

void BM_DirectionAStarOneVsSeparate(benchmark::State& state) {
  const auto i = static_cast<std::size_t>(state.range(0));
  const mapping::CostMap cost = window_around(kStarts[i]);
  PlanningProblem p;
  p.cost = &cost;
  p.start.position = kStarts[i];
  p.goal_direction_rad = kDirections[i];
  const DirectionAStarPlanner planner;
  double one_s = 0.0, separate_s = 0.0;
  std::size_t one_nodes = 0, separate_nodes = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const Plan one = planner.plan(p);
    const auto t1 = std::chrono::steady_clock::now();
    state.PauseTiming();
    const Plan separate = planner.plan_separately(p);
    const auto t2 = std::chrono::steady_clock::now();
    if (!one.found() || std::abs(one.cost - separate.cost) > 1e-9) state.SkipWithError("plans differ");
    one_s += std::chrono::duration<double>(t1 - t0).count();
    separate_s += std::chrono::duration<double>(t2 - t1).count();
    one_nodes += one.expanded;
    separate_nodes += separate.expanded;
    state.ResumeTiming();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["one_ms"] = 1e3 * one_s / n;
  state.counters["separate_ms"] = 1e3 * separate_s / n;
  state.counters["ratio"] = one_s / separate_s;
  state.counters["one_nodes"] = static_cast<double>(one_nodes) / n;
  state.counters["separate_nodes"] = static_cast<double>(separate_nodes) / n;
  state.counters["nodes_ratio"] = static_cast<double>(one_nodes) / static_cast<double>(separate_nodes);
}
BENCHMARK(BM_DirectionAStarOneVsSeparate)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

void BM_AStarAcrossTheOffice(benchmark::State& state) {
  static const mapping::CostMap cost = whole_map();
  PlanningProblem p;
  p.cost = &cost;
  p.start.position = Vec2(10.0, 10.0);
  p.goal_W = Vec2(35.0, 40.0);
  const GridAStarPlanner planner;
  std::size_t nodes = 0;
  for (auto _ : state) {
    const Plan plan = planner.plan(p);
    nodes = plan.expanded;
    benchmark::DoNotOptimize(plan.cost);
  }
  state.counters["nodes"] = static_cast<double>(nodes);
}
BENCHMARK(BM_AStarAcrossTheOffice)->Unit(benchmark::kMillisecond);

}  // namespace
