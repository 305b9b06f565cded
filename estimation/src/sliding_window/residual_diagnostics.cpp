// Whitened residual statistics per factor type (estimator.diagnostics.residuals): a check of the
// noise models against the data (docs/estimator.md, "Residual diagnostics").
#include <string>
#include <vector>

#include "navaid/estimation/first_estimates.hpp"
#include "impl.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/gauss_markov_factor.hpp"
#include "navaid/estimation/factors/gps_position_factor.hpp"
#include "navaid/estimation/factors/imu_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/landmark_factors.hpp"
#include "navaid/estimation/factors/magnetometer_yaw_factor.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/estimation/factors/time_offset_factors.hpp"
#include "navaid/estimation/factors/zero_velocity_factor.hpp"

namespace navaid::estimation {

namespace {

template <typename T>
bool is(const ceres::CostFunction* c) {
  return dynamic_cast<const T*>(c) != nullptr;
}

std::string factor_type(const ceres::CostFunction* c) {
  if (const auto* fej = dynamic_cast<const FirstEstimateCost*>(c)) c = &fej->factor();
  if (is<ImuFactor>(c)) return "imu";
  if (is<ReprojectionFactor>(c) || is<ReprojectionTdFactor>(c) || is<LandmarkReprojectionFactor>(c) ||
      is<LandmarkReprojectionTdFactor>(c))
    return "reprojection";
  if (is<Depth3dFactor>(c) || is<Depth3dTdFactor>(c) || is<LandmarkDepth3dFactor>(c) ||
      is<LandmarkDepth3dTdFactor>(c))
    return "depth_3d";
  if (is<InverseDepthFactor>(c) || is<AnchorInverseDepthFactor>(c)) return "inverse_depth";
  if (is<AnchorBearingFactor>(c) || is<AnchorBearingTdFactor>(c)) return "anchor_bearing";
  if (is<MarginalizationFactor>(c) || is<StatePriorFactor>(c)) return "prior";
  if (is<GpsPositionFactor>(c) || is<GpsPositionBiasFactor>(c)) return "gps";
  if (is<GaussMarkovFactor>(c)) return "gps_multipath";
  if (is<MagnetometerYawFactor>(c)) return "magnetometer";
  if (is<ZeroVelocityFactor>(c)) return "zero_velocity";
  return "other";
}

}  // namespace

void SlidingWindowEstimator::Impl::accumulate_residual_statistics(const std::vector<Residual>& residuals) {
  std::vector<double> r;
  for (const Residual& res : residuals) {
    r.resize(static_cast<std::size_t>(res.cost->num_residuals()));
    if (!res.cost->Evaluate(res.blocks.data(), r.data(), nullptr)) continue;
    double sq = 0;
    for (double v : r) sq += v * v;
    ResidualStatistics& s =
        stats.residuals[res.diagnostic_type != nullptr ? std::string(res.diagnostic_type) : factor_type(res.cost.get())];
    ++s.factors;
    s.rows += r.size();
    s.squared_sum += sq;
    if (sq > 9.0 * static_cast<double>(r.size())) ++s.beyond_3_sigma_rms;
  }
}

}  // namespace navaid::estimation

namespace navaid::estimation {

void SlidingWindowEstimator::Impl::count_newest_inliers(const std::vector<Residual>& residuals,
                                                        VisualCount& count) const {
  const double* newest = window.back()->pose;
  std::vector<double> r;
  for (const Residual& res : residuals) {
    // Visual factors: blocks (anchor pose, target pose, T_B_C, landmark[, td]).
    if (res.blocks.size() < 4 || res.blocks[2] != extrinsic || res.blocks[1] != newest) continue;
    if (fresh_landmarks.count(res.blocks[3])) continue;
    r.resize(static_cast<std::size_t>(res.cost->num_residuals()));
    if (!res.cost->Evaluate(res.blocks.data(), r.data(), nullptr)) continue;
    double sq = 0;
    for (double v : r) sq += v * v;
    ++count.newest.residuals;
    if (sq <= kCovarianceGate) ++count.newest.inliers;
  }
}

}  // namespace navaid::estimation
