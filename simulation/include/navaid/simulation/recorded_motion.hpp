#pragma once
// A real recording's motion driving the simulator (`navaid simulate --from-recording`): the real
// IMU samples and the real ground-truth trajectory of an EuRoC folder are kept, and only the camera
// is simulated (features or rendered images) in a world around the flight. The estimator then
// meets real IMU noise, bias drift and rotor vibration on a real flight, with a camera whose
// geometry is exactly known.
#include <filesystem>
#include <vector>

#include "navaid/core/messages.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/simulator.hpp"

namespace navaid::simulation {

/// Ground-truth poses between the samples: position by cubic Hermite interpolation with the
/// samples' velocities (linear without them), orientation by slerp.
class RecordedMotion {
 public:
  /// Throws navaid::Error with fewer than 2 samples or times that do not strictly increase.
  explicit RecordedMotion(std::vector<GroundTruthState> samples);
  /// Pose of B in W at t, inside [begin(), end()] (throws outside).
  SE3 pose_at(Timestamp t) const;
  Timestamp begin() const { return samples_.front().t; }
  Timestamp end() const { return samples_.back().t; }
  const std::vector<GroundTruthState>& samples() const { return samples_; }
  /// The box the body positions span.
  AxisAlignedBox bounds() const;

 private:
  std::vector<GroundTruthState> samples_;
};

/// A textured room around a flight: walls `margin_m` beyond the flown box, floor just below its
/// lowest point, ceiling at least 3 m up, furniture along the walls (never inside the flown box
/// grown by margin_m / 2). Seeded; the geodetic origin is ETH Zurich's (EuRoC's).
Scenario make_flight_room(const AxisAlignedBox& flown, std::uint64_t seed, double margin_m = 1.5);

/// Writes a navaid recording in `out` with the source's IMU samples and ground truth over the span
/// both cover (cut to config.duration_s when > 0), the camera `config.camera` simulated along the
/// ground truth in `scenario` (features or images per config.mode), the IMU calibration
/// `config.imu`; no GNSS and no magnetometer. Stamps stay the source's. Throws UsageError when the
/// source has no IMU or fewer than 2 ground-truth states, or they do not overlap.
SimulationSummary simulate_recorded_motion(const Scenario& scenario, const SimulationConfig& config,
                                           const io::Recording& source, const std::filesystem::path& out,
                                           const SimulateOptions& options = {});

}  // namespace navaid::simulation
