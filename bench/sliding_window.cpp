// Cost of the sliding-window estimator: one optimization of a full window (10 keyframes, ~150
// features tracked per frame, simulated lab-walk-1 with the hand mount), per linear solver, and
// one whole frame (solve, covariance of the newest state, marginalization when it is a keyframe).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "navaid/io/event_stream.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/simulation/simulator.hpp"

namespace {

using namespace navaid;
using namespace navaid::estimation;

const io::Recording& recording() {
  static const io::Recording rec = [] {
    const auto dir = std::filesystem::temp_directory_path() / "navaid_bench_sliding_window";
    const Config c = Config::parse("{}", "<bench>",
                                   {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=9",
                                    "seed=1", "features.max_per_frame=150"});
    const auto scenario = simulation::make_scenario(simulation::read_scenario_name(c));
    simulation::SimulateOptions options;
    options.overwrite = true;
    simulation::simulate(scenario, simulation::read_simulation_config(c, scenario), dir, options);
    auto r = io::read_navaid_recording(dir);
    std::filesystem::remove_all(dir);
    return r;
  }();
  return rec;
}

// The estimator after 7 s of the walk (window full), and the events of the next second.
struct Warm {
  std::unique_ptr<SlidingWindowEstimator> estimator;
  std::vector<SensorEvent> next_events;
};

Warm warm(const std::string& solver) {
  const auto& rec = recording();
  const Config c = Config::parse("{}", "<bench>", {"estimator.solver.linear_solver=" + solver});
  Warm w;
  w.estimator = std::make_unique<SlidingWindowEstimator>(rec.calibration, read_estimator_config(c));
  io::SensorEventStream stream(rec);
  const Timestamp stop = rec.imu.front().t + 7'000'000'000;
  while (auto e = stream.next()) {
    if (event_time(*e) < stop) {
      w.estimator->process(*e);
    } else {
      w.next_events.push_back(*e);
    }
  }
  return w;
}

void BM_WindowOptimization(benchmark::State& state, const std::string& solver) {
  const Warm w = warm(solver);
  std::size_t features = 0;
  for (auto _ : state) {
    state.PauseTiming();
    SlidingWindowEstimator copy(*w.estimator);  // every iteration starts from the same window
    state.ResumeTiming();
    features = copy.optimize();
    benchmark::DoNotOptimize(features);
  }
  state.counters["keyframes"] = static_cast<double>(w.estimator->window_keyframes());
  state.counters["features"] = static_cast<double>(features);
}
BENCHMARK_CAPTURE(BM_WindowOptimization, dense_schur, std::string("dense_schur"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WindowOptimization, sparse_schur, std::string("sparse_schur"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WindowOptimization, sparse_normal_cholesky, std::string("sparse_normal_cholesky"))
    ->Unit(benchmark::kMillisecond);

// One frame end to end: the events up to and including the next estimate.
void BM_WholeFrame(benchmark::State& state) {
  const Warm w = warm("dense_schur");
  for (auto _ : state) {
    state.PauseTiming();
    SlidingWindowEstimator copy(*w.estimator);
    state.ResumeTiming();
    for (const auto& e : w.next_events)
      if (!copy.process(e).empty()) break;
  }
}
BENCHMARK(BM_WholeFrame)->Unit(benchmark::kMillisecond);

}  // namespace
