// The walking-path generator against the A* baseline on the Smart Cane Table I maps (simulated
// office1, office2, pillar, school), side by side on the same seeded start/goal pairs as
// `navaid reproduce smart-cane-table1`: counters wpg_ms / astar_ms per plan and ratio = WPG time /
// A* time (goal: < 1 on all four maps), and the nodes of both. Then re-planning inside the 10 m
// sensing range at 10 Hz: a user walks a WPG plan at 1.2 m/s on office1 and on the real Willow
// office map, and every 0.1 s the planner re-plans from where the user is with horizon_m = 10;
// counters p50_ms / p99_ms / max_ms over all re-plans (goal: p99 <= 100 ms).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "navaid/experiments/planner_comparison.hpp"
#include "navaid/experiments/scenario_cost_map.hpp"
#include "navaid/io/occupancy_map_file.hpp"
#include "navaid/planning/grid_astar.hpp"
#include "navaid/planning/occupancy_cost_map.hpp"
#include "navaid/planning/wpg_planner.hpp"

namespace {

using namespace navaid;
using namespace navaid::planning;
using mapping::Vec2;

struct Map {
  mapping::CostMap cost;
  mapping::Esdf2d esdf;
  std::vector<experiments::PlannerPair> pairs;
};

const char* const kMaps[] = {"office1", "office2", "pillar", "school"};

GridAStarConfig astar_config() {
  GridAStarConfig c;
  c.cost.base_clearance_m = 0.3;  // as smart-cane-table1.yaml: the CoM sphere kept clear
  return c;
}

const Map& scenario_map(int i) {
  static std::vector<std::unique_ptr<Map>> maps(4);
  if (!maps[static_cast<std::size_t>(i)]) {
    const bool school = i == 3;
    const Config config =
        Config::parse("{}", "<bench>", {school ? "planning.map.resolution_m=0.2" : "planning.map.resolution_m=0.1"});
    auto m = std::make_unique<Map>(Map{experiments::scenario_cost_map(kMaps[i], config).cost, mapping::Esdf2d(), {}});
    m->esdf.update(m->cost);
    experiments::PairSampling s;
    s.pairs = 30;
    s.min_distance_m = school ? 150.0 : i == 2 ? 20.0 : 15.0;
    m->pairs = experiments::sample_planner_pairs(m->cost, m->esdf, GridAStarPlanner(astar_config()), s);
    maps[static_cast<std::size_t>(i)] = std::move(m);
  }
  return *maps[static_cast<std::size_t>(i)];
}

PlanningProblem problem_of(const Map& m, const experiments::PlannerPair& pair) {
  PlanningProblem p;
  p.cost = &m.cost;
  p.esdf = &m.esdf;
  p.start = pair.start;
  p.goal_W = pair.goal;
  return p;
}

void BM_WpgVsAStar(benchmark::State& state) {
  const Map& m = scenario_map(static_cast<int>(state.range(0)));
  WpgConfig wc;
  if (state.range(0) == 3) wc.heuristic_cell_m = 1.0;  // as smart-cane-table1.yaml on school
  const WpgPlanner wpg(wc);
  const GridAStarPlanner astar(astar_config());
  double wpg_s = 0.0, astar_s = 0.0;
  double wpg_nodes = 0.0, astar_nodes = 0.0;
  std::size_t plans = 0;
  for (auto _ : state) {
    for (const auto& pair : m.pairs) {
      const PlanningProblem p = problem_of(m, pair);
      const auto t0 = std::chrono::steady_clock::now();
      const Plan a = wpg.plan(p);
      const auto t1 = std::chrono::steady_clock::now();
      const Plan b = astar.plan(p);
      const auto t2 = std::chrono::steady_clock::now();
      wpg_s += std::chrono::duration<double>(t1 - t0).count();
      astar_s += std::chrono::duration<double>(t2 - t1).count();
      wpg_nodes += static_cast<double>(a.expanded);
      astar_nodes += static_cast<double>(b.expanded);
      ++plans;
    }
  }
  state.SetLabel(kMaps[state.range(0)]);
  const double n = static_cast<double>(plans);
  state.counters["wpg_ms"] = 1e3 * wpg_s / n;
  state.counters["astar_ms"] = 1e3 * astar_s / n;
  state.counters["ratio"] = wpg_s / astar_s;
  state.counters["wpg_nodes"] = wpg_nodes / n;
  state.counters["astar_nodes"] = astar_nodes / n;
}
BENCHMARK(BM_WpgVsAStar)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->Iterations(3);

// The user walks the first plan; every 0.1 s (0.12 m along the path) WPG re-plans toward the goal
// inside the 10 m horizon. Returns every re-plan's time.
std::vector<double> replan_times(const mapping::CostMap& cost, const mapping::Esdf2d& esdf,
                                 const std::vector<experiments::PlannerPair>& pairs) {
  WpgConfig c;
  c.horizon_m = 10.0;
  const WpgPlanner wpg(c);
  const WpgPlanner full;
  std::vector<double> times;
  for (const auto& pair : pairs) {
    PlanningProblem p;
    p.cost = &cost;
    p.esdf = &esdf;
    p.start = pair.start;
    p.goal_W = pair.goal;
    const Plan route = full.plan(p);
    if (!route.found()) continue;
    double along = 0.0;
    std::size_t k = 0;
    for (int tick = 0; tick < 200 && k + 1 < route.path_W.size(); ++tick) {
      along += 0.12;
      while (k + 1 < route.path_W.size() && along > (route.path_W[k + 1] - route.path_W[k]).norm()) {
        along -= (route.path_W[k + 1] - route.path_W[k]).norm();
        ++k;
      }
      if (k + 1 >= route.path_W.size()) break;
      const Vec2 d = route.path_W[k + 1] - route.path_W[k];
      p.start.position = route.path_W[k] + along / d.norm() * d;
      p.start.yaw_rad = route.yaw_rad[k + 1];
      const Plan replan = wpg.plan(p);
      times.push_back(replan.time_s);
    }
  }
  return times;
}

void report(benchmark::State& state, std::vector<double> times) {
  std::sort(times.begin(), times.end());
  const auto q = [&](double f) { return times[static_cast<std::size_t>(f * static_cast<double>(times.size() - 1))]; };
  state.counters["replans"] = static_cast<double>(times.size());
  state.counters["p50_ms"] = 1e3 * q(0.5);
  state.counters["p99_ms"] = 1e3 * q(0.99);
  state.counters["max_ms"] = 1e3 * times.back();
}

void BM_WpgReplanEvery100msOffice1(benchmark::State& state) {
  const Map& m = scenario_map(0);
  const std::vector<experiments::PlannerPair> pairs(m.pairs.begin(), m.pairs.begin() + 10);
  std::vector<double> times;
  for (auto _ : state) times = replan_times(m.cost, m.esdf, pairs);
  report(state, times);
}
BENCHMARK(BM_WpgReplanEvery100msOffice1)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_WpgReplanEvery100msWillow(benchmark::State& state) {
  const io::OccupancyMapFile file =
      io::read_occupancy_map(std::string(NAVAID_SHARED_DATA_DIR) + "/ros-map-willow/willow-full-0.05.yaml");
  const mapping::CostMap cost = cost_map_from_occupancy(
      file.image.width, file.image.height, file.resolution_m, Vec2::Zero(),
      [&](int x, int y) {
        switch (file.cell(x, y)) {
          case io::OccupancyCell::kFree: return OccupancyValue::kFree;
          case io::OccupancyCell::kOccupied: return OccupancyValue::kOccupied;
          case io::OccupancyCell::kUnknown: break;
        }
        return OccupancyValue::kUnknown;
      },
      OccupancyCostConfig{});
  mapping::Esdf2d esdf;
  esdf.update(cost);
  experiments::PairSampling s;
  s.pairs = 10;
  s.min_distance_m = 15.0;
  const auto pairs = experiments::sample_planner_pairs(cost, esdf, GridAStarPlanner(astar_config()), s);
  std::vector<double> times;
  for (auto _ : state) times = replan_times(cost, esdf, pairs);
  report(state, times);
}
BENCHMARK(BM_WpgReplanEvery100msWillow)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
