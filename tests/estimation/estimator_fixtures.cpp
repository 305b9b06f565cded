#include "estimator_fixtures.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/estimation/config_schema.hpp"
#include "navaid/io/event_stream.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/simulation/config_schema.hpp"
#include "navaid/simulation/simulator.hpp"
#include "test_support.hpp"

namespace navaid::estimation::testing {

io::Recording simulate_recording(const std::string& scratch_name, const std::vector<std::string>& overrides) {
  navaid::testing::ScratchDir dir(scratch_name);
  // The estimator's tests keep the walks they were designed on: no hand-guidance target box (it
  // moves landmarks and occlusions of the lab walks, and these tests' margins are on that data).
  std::vector<std::string> all = {"simulation.targets=false"};
  all.insert(all.end(), overrides.begin(), overrides.end());
  const Config c = Config::parse("{}", "<test>", all);
  const auto scenario = simulation::make_scenario(simulation::read_scenario_name(c), simulation::read_scenario_options(c));
  const auto sim = simulation::read_simulation_config(c, scenario);
  c.reject_unknown_keys(simulation::simulation_config_schema());
  simulation::SimulateOptions options;
  options.threads = 1;
  simulation::simulate(scenario, sim, dir.path(), options);
  return io::read_navaid_recording(dir.path());
}

EstimatorRun run_estimator(const io::Recording& rec, const std::vector<std::string>& overrides, bool flush) {
  const Config c = Config::parse("{}", "<test>", overrides);
  SlidingWindowEstimator estimator(rec.calibration, read_estimator_config(c), {}, rec.origin);
  c.reject_unknown_keys(estimator_config_schema());
  EstimatorRun r;
  io::SensorEventStream stream(rec);
  while (auto e = stream.next())
    for (auto& s : estimator.process(*e)) r.estimates.push_back(s);
  if (flush)
    for (auto& s : estimator.finish()) r.estimates.push_back(s);
  r.stats = estimator.statistics();
  r.camera_extrinsic = estimator.camera_extrinsic();
  r.camera_time_offset_s = estimator.camera_time_offset_s();
  return r;
}

double position_rmse(const std::vector<StateEstimate>& est, const std::vector<GroundTruthState>& gt) {
  std::optional<SE3> align;
  double sq = 0;
  int n = 0;
  for (const auto& s : est) {
    if (s.mode == EstimatorMode::kInitializing) continue;
    const SE3 g = groundtruth_at(gt, s.t);
    if (!align) {
      const Quat dq(Eigen::AngleAxisd(yaw_of(g.q) - yaw_of(s.T_W_B.q), Vec3::UnitZ()));
      align = SE3(dq, g.t - dq * s.T_W_B.t);
    }
    sq += ((*align * s.T_W_B).t - g.t).squaredNorm();
    ++n;
  }
  return std::sqrt(sq / n);
}

SE3 groundtruth_at(const std::vector<GroundTruthState>& gt, Timestamp t) {
  auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const GroundTruthState& s, Timestamp x) { return s.t < x; });
  if (it == gt.end()) return gt.back().T_W_B;
  if (it->t == t || it == gt.begin()) return it->T_W_B;
  const auto& a = *std::prev(it);
  return interpolate(a.T_W_B, it->T_W_B, static_cast<double>(t - a.t) / static_cast<double>(it->t - a.t));
}

}  // namespace navaid::estimation::testing
