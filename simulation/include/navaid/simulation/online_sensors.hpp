#pragma once
// The simulator stepped online: the sensors of a rig sampled from wherever the body is now, for a
// closed loop in which the walker's next move depends on what the device said (simulated_user.hpp).
// The same models as `navaid simulate` (simulator.hpp), fed the same configuration: the IMU with
// its noise and bias walk, feature observations of landmarks with KLT-like track persistence, and
// RGB-D frames rendered by ray casting with depth noise, holes and the segmentation's label
// confusion, people and vehicles included. Frames stay in memory (RgbdFrame's images), nothing is
// written. Deterministic for a configuration, its seed and the sequence of poses.
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/simulation/feature_simulator.hpp"
#include "navaid/simulation/gnss_model.hpp"
#include "navaid/simulation/magnetometer_model.hpp"
#include "navaid/simulation/imu_model.hpp"
#include "navaid/simulation/label_confusion_model.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace navaid::simulation {

class OnlineSensors {
 public:
  /// `nominal`: the walk the landmarks are seeded along first (the scenario's path, exactly as
  /// `navaid simulate` seeds them). Where the person strays from it, features() seeds more around
  /// where they are (kSeedCellM cells, each seeded once, from a seed of the cell), so a walk off
  /// the planned path keeps seeing features (before, the camera saw none after 50 m down route1's
  /// first street, and the estimator was lost for want of landmarks, not by its own fault). `render_camera`: the camera RGB-D frames
  /// are rendered with (the same lens at a lower resolution, for speed), config.camera when unset;
  /// features are always observed with config.camera. Keeps a reference to `scenario`.
  OnlineSensors(const Scenario& scenario, const SimulationConfig& config, const WalkerTrajectory& nominal,
                const std::optional<CameraCalibration>& render_camera = std::nullopt);
  ~OnlineSensors();

  /// The IMU's sample of `body` at trajectory time t [ns] (calls in non-decreasing t).
  ImuSample imu(const KinematicState& body, Timestamp t);
  /// Feature observations of the camera on the body at pose T_W_B at trajectory time t.
  FeatureFrame features(const SE3& T_W_B, Timestamp t);
  /// The RGB-D frame (depth, labels and their confidence; intensity when config.render asks)
  /// rendered from T_W_B at trajectory time t, with the frame's number `index`.
  RgbdFrame rgbd(const SE3& T_W_B, Timestamp t, std::uint64_t index);

  /// The GNSS fix of the antenna on the body at T_W_B (multipath from the urban canyon there),
  /// none in an outage or when config.gps_enabled is off; calls in non-decreasing t.
  std::optional<GpsFix> gps(const SE3& T_W_B, Timestamp t);
  /// The magnetometer's sample at T_W_B; none when config.mag_enabled is off.
  std::optional<MagSample> mag(const SE3& T_W_B, Timestamp t);

  const std::vector<Landmark>& landmarks() const { return landmarks_; }
  const ImuModel& imu_model() const { return imu_; }
  /// Size of the cells landmarks are seeded per as the person goes [m].
  static constexpr double kSeedCellM = 2.0;
  const SimulationConfig& config() const { return config_; }
  const CameraCalibration& render_camera() const { return render_calibration_; }

 private:
  void seed_landmarks_around(const Vec2& xy);
  const Scenario* scenario_;
  SimulationConfig config_;
  RayCaster world_;
  std::unique_ptr<CameraModel> camera_;
  CameraCalibration render_calibration_;
  std::unique_ptr<CameraModel> render_camera_;
  RgbdRenderer renderer_;
  std::vector<Landmark> landmarks_;
  std::set<std::pair<long, long>> seeded_cells_;  // kSeedCellM cells with landmarks seeded
  double ground_z_m_ = 0;
  FeatureObserver observer_;
  std::mt19937_64 feature_rng_;
  ImuModel imu_;
  LabelConfusionModel confusion_;
  GnssModel gnss_;
  MagnetometerModel magnetometer_;
  double depth_unit_m_;
  RenderedFrame clean_;
};

}  // namespace navaid::simulation
