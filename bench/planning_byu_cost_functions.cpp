// The BYU augmented cane's cost functions (FICF, CACF) and rumble table per scan: on the thesis's
// 61-bin scan (1 deg over +-30 deg) and on a finer 241-bin one (0.25 deg), a cluttered scene (random
// returns in 0.3-4 m, a drop-off in some bins, fixed seed); the whole chain to a GuidanceCommand;
// and reading obstacle_scan.csv (1000 rows). The thesis ran its pipeline at 2-3 Hz: the costs
// are a vanishing part of that budget.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "navaid/planning/byu_cost_functions.hpp"
#include "navaid/planning/obstacle_scan_csv.hpp"

namespace {

using namespace navaid;
using namespace navaid::planning;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

mapping::ObstacleScan cluttered(std::size_t bins) {
  const double increment = 60.0 * kDeg / static_cast<double>(bins - 1);
  mapping::ObstacleScan s = mapping::ObstacleScan::empty(bins, -30.0 * kDeg, increment);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> range(0.3f, 4.0f);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t i = 0; i < bins; ++i) {
    if (u(rng) < 0.8f) s.ranges[i] = range(rng);
    if (u(rng) < 0.1f) s.drop_off_ranges[i] = range(rng);
  }
  s.counters.ground_source = mapping::GroundSource::kRansac;
  return s;
}

void BM_Costs(benchmark::State& state) {
  const auto function = static_cast<ByuCostFunction>(state.range(0));
  const mapping::ObstacleScan scan = cluttered(static_cast<std::size_t>(state.range(1)));
  const ByuCostConfig config;
  for (auto _ : state) {
    const ByuCosts c = byu_costs(scan, function, config);
    benchmark::DoNotOptimize(c);
  }
  state.SetLabel(std::string(to_string(function)));
  state.counters["bins"] = static_cast<double>(scan.size());
  state.counters["scans_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Costs)->ArgsProduct({{0, 1}, {61, 241}});

void BM_Guidance(benchmark::State& state) {
  const auto function = static_cast<ByuCostFunction>(state.range(0));
  const mapping::ObstacleScan scan = cluttered(61);
  const ByuCostConfig config;
  for (auto _ : state) {
    GuidanceCommand c = byu_guidance(scan, EstimatorMode::kLost, function, config);
    benchmark::DoNotOptimize(c);
  }
  state.SetLabel(std::string(to_string(function)));
}
BENCHMARK(BM_Guidance)->Arg(0)->Arg(1);

void BM_ReadObstacleScanCsv(benchmark::State& state) {
  std::ostringstream text;
  text << "t_ns,ground,ransac,obstacle_points,drop_off_points";
  for (int b = -30; b <= 30; ++b) text << ",r_" << b;
  text << "\n";
  const mapping::ObstacleScan scan = cluttered(61);
  for (int row = 0; row < 1000; ++row) {
    text << 1000000000LL + 66666667LL * row << ",0,1,5000,10";
    for (const float r : scan.ranges) {
      text << ",";
      if (std::isfinite(r)) text << r;
    }
    text << "\n";
  }
  const std::string csv = text.str();
  for (auto _ : state) {
    std::istringstream in(csv);
    const auto scans = parse_obstacle_scan_csv(in, "bench.csv");
    benchmark::DoNotOptimize(scans.data());
  }
  state.counters["rows_per_s"] = benchmark::Counter(1000.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ReadObstacleScanCsv)->Unit(benchmark::kMillisecond);

}  // namespace
