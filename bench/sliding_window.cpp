// Cost of the sliding-window estimator: one optimization of a full window (10 keyframes, ~150
// features tracked per frame, simulated lab-walk-1 with the hand mount), per linear solver; one
// whole frame (solve, covariance of the newest state, marginalization when it is a keyframe) and
// the next 2 s of frames, with non-keyframes solved with the window or alone.
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

// The estimator after 7 s of the walk (window full), and the events of the 2 s after.
struct Warm {
  std::unique_ptr<SlidingWindowEstimator> estimator;
  std::vector<SensorEvent> next_events;
};

Warm warm(const std::string& solver, const std::string& non_keyframes = "window") {
  const auto& rec = recording();
  const Config c = Config::parse("{}", "<bench>", {"estimator.solver.linear_solver=" + solver,
                                                   "estimator.solver.non_keyframes=" + non_keyframes});
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

// One frame end to end: the events up to and including the next estimate (a non-keyframe here).
void BM_WholeFrame(benchmark::State& state, const std::string& non_keyframes) {
  const Warm w = warm("dense_schur", non_keyframes);
  for (auto _ : state) {
    state.PauseTiming();
    SlidingWindowEstimator copy(*w.estimator);
    state.ResumeTiming();
    for (const auto& e : w.next_events)
      if (!copy.process(e).empty()) break;
  }
}
BENCHMARK_CAPTURE(BM_WholeFrame, non_keyframes_window, std::string("window"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WholeFrame, non_keyframes_newest, std::string("newest"))->Unit(benchmark::kMillisecond);

// The 2 s after the warm-up (60 frames, keyframes and others as they come): time per frame is the
// iteration time over the "frames" counter.
void BM_TwoSeconds(benchmark::State& state, const std::string& non_keyframes) {
  const Warm w = warm("dense_schur", non_keyframes);
  std::size_t frames = 0, keyframes = 0;
  for (auto _ : state) {
    state.PauseTiming();
    SlidingWindowEstimator copy(*w.estimator);
    const std::size_t keyframes_before = copy.statistics().keyframes;
    state.ResumeTiming();
    frames = 0;
    for (const auto& e : w.next_events) frames += copy.process(e).size();
    keyframes = copy.statistics().keyframes - keyframes_before;
  }
  state.counters["frames"] = static_cast<double>(frames);
  state.counters["keyframes"] = static_cast<double>(keyframes);
}
BENCHMARK_CAPTURE(BM_TwoSeconds, non_keyframes_window, std::string("window"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TwoSeconds, non_keyframes_newest, std::string("newest"))->Unit(benchmark::kMillisecond);

}  // namespace
