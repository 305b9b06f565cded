#include "navaid/experiments/trial_device.hpp"

#include <chrono>

#include "navaid/estimation/estimator_config.hpp"
#include "navaid/estimation/frontend/image_feature_source.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "navaid/experiments/device_run.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/runtime/estimator_driver.hpp"
#include "navaid/simulation/online_sensors.hpp"

namespace navaid::experiments {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The recording the rig would write: its calibration and origin (no samples).
io::Recording rig_recording(const simulation::Scenario& scenario, const simulation::SimulationConfig& sim) {
  io::Recording recording;
  recording.format = "navaid";
  recording.origin = scenario.origin;
  recording.calibration.cameras = {sim.camera};
  recording.calibration.imu = sim.imu;
  recording.calibration.gps_lever_arm_B = sim.mount.gps_lever_arm_B;
  if (sim.gps_enabled) recording.calibration.gps_rate_hz = sim.gps.rate_hz;
  if (sim.mag_enabled) recording.calibration.mag_rate_hz = sim.mag_rate_hz;
  return recording;
}

}  // namespace

struct TrialDevice::Impl {
  Impl(const runtime::DeviceSpec& spec, const Config& config, const simulation::Scenario& scenario,
       const simulation::SimulationConfig& simulation, const simulation::WalkerTrajectory& nominal,
       const std::filesystem::path& out_dir, const TrialDeviceOptions& o)
      : sim(simulation),
        options(o),
        out(out_dir),
        recording(rig_recording(scenario, simulation)),
        uses_gps(spec.guidance == runtime::GuidanceKind::kRoute),
        imu_dt(seconds_to_ns(1.0 / simulation.imu.rate_hz)),
        camera_dt(seconds_to_ns(1.0 / o.camera_rate_hz)) {
    // The rig's features feed the estimator: no image front end.
    auto driver = std::make_unique<runtime::EstimatorDriver>(estimation::SlidingWindowEstimator(
        recording.calibration, estimation::read_estimator_config(config), sim.camera.name, recording.origin));
    MapSessionOptions map_options;
    map_options.quality = false;  // a trial scores the walk, not the map
    DeviceRunOptions run_options;
    run_options.device.mapping = runtime::read_mapping_stage_options(config);
    run_options.device.threaded = false;  // deterministic, and the person reacts to this frame's cues
    run_options.figures = false;
    run_options.cue_sink = o.cue_sink;
    run_options.estimate_sink = [this](const StateEstimate& e) { last_estimate = e; };
    device_run = std::make_unique<DeviceRun>(spec, config, recording, out, o.render_camera, out, map_options, run_options);
    device().set_estimator(std::move(driver));
    sensors = std::make_unique<simulation::OnlineSensors>(scenario, sim, nominal, o.render_camera);
    if (o.save_recording) {
      saved = recording;
      saved.calibration.cameras.front().rate_hz = o.camera_rate_hz;  // the rate the features come at
    }
  }

  runtime::Device& device() { return device_run->device(); }

  /// Renders the sensors due at `t` (one IMU tick; the camera, GNSS and the magnetometer at their
  /// rates) and hands them to the device in the order the estimator takes them.
  void step(const simulation::KinematicState& state, Timestamp t) {
    if (!next_camera) next_camera = next_gps = next_mag = t;
    const auto t0 = Clock::now();
    std::vector<SensorEvent> events = render(state, t);
    const auto t1 = Clock::now();
    n.sensor_s += seconds_since(t0);
    const double estimator_before = device().estimator_busy_s();
    for (SensorEvent& event : events) device().add(std::move(event), t1);
    const double estimator_s = device().estimator_busy_s() - estimator_before;
    n.estimator_s += estimator_s;
    n.device_s += seconds_since(t1) - estimator_s;
  }

  /// The events of one tick, rendered in the rig's order (the sensors share their random
  /// streams) and handed over in the estimator's: the camera frame (kept by the device for
  /// mapping), the IMU sample, GNSS and the magnetometer for the devices that read them (a route),
  /// then the frame's features, which the estimator attaches the fix of the same moment to.
  std::vector<SensorEvent> render(const simulation::KinematicState& state, Timestamp t) {
    std::vector<SensorEvent> events;
    const ImuSample imu = sensors->imu(state, t);
    if (options.save_recording) {
      saved.imu.push_back(imu);
      saved.groundtruth.push_back(
          {imu.t, state.T_W_B, state.v_W, sensors->imu_model().gyro_bias(), sensors->imu_model().accel_bias()});
    }
    std::optional<FeatureFrame> features;
    if (t >= *next_camera) {
      *next_camera += camera_dt;
      features = sensors->features(state.T_W_B, t);
      if (options.save_recording) saved.features.push_back(*features);
      events.emplace_back(sensors->rgbd(state.T_W_B, t, n.frames++));
    }
    events.emplace_back(imu);
    if (uses_gps && t >= *next_gps) {
      *next_gps += seconds_to_ns(1.0 / sim.gps.rate_hz);
      if (auto fix = sensors->gps(state.T_W_B, t)) {
        ++n.gps_fixes;
        if (options.save_recording) saved.gps.push_back(*fix);
        events.emplace_back(*fix);
      }
    }
    if (uses_gps && t >= *next_mag) {
      *next_mag += seconds_to_ns(1.0 / sim.mag_rate_hz);
      if (auto m = sensors->mag(state.T_W_B, t)) {
        ++n.mag_samples;
        if (options.save_recording) saved.mag.push_back(*m);
        events.emplace_back(*m);
      }
    }
    if (features) events.emplace_back(std::move(*features));
    return events;
  }

  simulation::SimulationConfig sim;
  TrialDeviceOptions options;
  std::filesystem::path out;
  io::Recording recording;
  bool uses_gps;
  Timestamp imu_dt, camera_dt;
  std::unique_ptr<DeviceRun> device_run;
  std::unique_ptr<simulation::OnlineSensors> sensors;
  io::Recording saved;  // trial.save_recording
  std::optional<Timestamp> next_camera, next_gps, next_mag;
  TrialDeviceCounts n;
  std::optional<StateEstimate> last_estimate;  // the device's estimate sink
};

TrialDevice::TrialDevice(const runtime::DeviceSpec& spec, const Config& config, const simulation::Scenario& scenario,
                         const simulation::SimulationConfig& sim, const simulation::WalkerTrajectory& nominal,
                         const std::filesystem::path& out, const TrialDeviceOptions& options)
    : impl_(std::make_unique<Impl>(spec, config, scenario, sim, nominal, out, options)) {}

TrialDevice::~TrialDevice() = default;

void TrialDevice::step(const simulation::KinematicState& state, Timestamp t) { impl_->step(state, t); }

const std::optional<StateEstimate>& TrialDevice::last_estimate() const { return impl_->last_estimate; }

nlohmann::ordered_json TrialDevice::finish() {
  Impl& d = *impl_;
  if (d.options.save_recording) {
    d.saved.landmarks = d.sensors->landmarks();
    io::write_navaid_recording(d.saved, d.out / "recording");
  }
  const auto tp = Clock::now();
  nlohmann::ordered_json summary = d.device_run->finish();
  d.n.device_s += seconds_since(tp);
  return summary;
}

nlohmann::ordered_json TrialDevice::estimator_summary() const {
  const estimation::EstimatorStatistics& es = impl_->device_run->device().estimator().estimator().statistics();
  return {{"failures", es.failures},
          {"last_failure", es.last_failure},
          {"restarts", es.restarts},
          {"map_frame_resets", es.map_frame_resets},
          {"gps_registrations", es.gps_registrations},
          {"covariance_failures", es.covariance_failures}};
}

const TrialDeviceCounts& TrialDevice::counts() const { return impl_->n; }

}  // namespace navaid::experiments
