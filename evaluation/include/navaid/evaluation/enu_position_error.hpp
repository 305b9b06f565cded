#pragma once
// Absolute (ENU) position error of a GPS-aided run, and the reference it should be read against:
// the error that the ground truth itself would have after the 4-DOF registration to the same
// fixes (eLabrador eq. 6-7, docs/estimator.md "GPS registration"). Time-correlated multipath moves
// the fixes' mean over a walk away from the truth, and no rigid alignment can see that offset, so a
// run whose error is close to this reference has used what the fixes tell.
#include <cstddef>
#include <optional>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/estimation/gps_registration.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::evaluation {

struct EnuPositionError {
  double rmse_m = 0;             ///< 3-D
  double horizontal_rmse_m = 0;  ///< east-north
  double vertical_rmse_m = 0;
  double max_m = 0;              ///< largest 3-D error
  std::size_t poses = 0;
};

/// Position errors of estimated ENU poses against ground truth already in ENU (no alignment),
/// poses paired by time (associate_poses). nullopt when no pose pairs.
std::optional<EnuPositionError> enu_position_error(const std::vector<io::StampedPose>& estimate_enu,
                                                   const std::vector<io::StampedPose>& groundtruth_enu);

/// The ground-truth antenna path (T_ENU_B * lever_arm_B at each fix, the nearest ground-truth pose
/// within 20 ms) registered to all fixes by register_gps_to_world with `options`; the error of the
/// registered ground truth at the times of `evaluate_at` (ground truth poses paired with them).
/// nullopt when the registration does not reach kRegistered or nothing pairs.
std::optional<EnuPositionError> rigid_registration_reference(const std::vector<GpsFix>& fixes,
                                                             const std::vector<io::StampedPose>& groundtruth_enu,
                                                             const Vec3& lever_arm_B, const GeodeticOrigin& origin,
                                                             const std::vector<Timestamp>& evaluate_at,
                                                             const estimation::GpsRegistrationOptions& options = {});

/// As rigid_registration_reference, but causal, as an estimator sees the fixes: at each time of
/// `evaluate_at`, the ground truth registered to the fixes up to that time (re-registered at each
/// new fix). Times before the first successful registration are left out (`poses` counts the
/// rest). nullopt when it never registers.
std::optional<EnuPositionError> causal_registration_reference(const std::vector<GpsFix>& fixes,
                                                              const std::vector<io::StampedPose>& groundtruth_enu,
                                                              const Vec3& lever_arm_B, const GeodeticOrigin& origin,
                                                              const std::vector<Timestamp>& evaluate_at,
                                                              const estimation::GpsRegistrationOptions& options = {});

}  // namespace navaid::evaluation
