#pragma once
// First-estimate Jacobians (FEJ; Huang, Mourikis and Roumeliotis 2010, as OpenVINS and Basalt use
// them) for the factors that share blocks with the marginalization prior.
//
// The prior's Jacobian is fixed at its linearization point x0 (marginalization.hpp). A factor
// linearized elsewhere on a block the prior holds disagrees with it about the directions nothing
// observes (global position and yaw); together they gain information along them and the
// covariance shrinks where it should grow. FirstEstimateCost evaluates its factor's residual at the
// current values and its Jacobians at x0 for the blocks the prior holds (at the current value for
// the others), so every factor sees those blocks through the same linearization point.
//
// Pose blocks: Ceres multiplies an ambient Jacobian by the manifold's PlusJacobian at the current
// value. The wrapper returns J_amb(x0) P(x0) P(x)^+ (P^+ P = I: P has full column rank), so Ceres,
// the covariance and the marginalizer see the tangent Jacobian J_amb(x0) P(x0).
#include <memory>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/manifold.h>

#include "navaid/estimation/marginalization.hpp"

namespace navaid::estimation {

class FirstEstimateCost final : public ceres::CostFunction {
 public:
  /// `blocks` as the factor takes them; the prior's x0 replaces the blocks it holds. Pose blocks
  /// (ambient 7) use `pose_manifold`.
  FirstEstimateCost(std::shared_ptr<ceres::CostFunction> factor, const std::vector<double*>& blocks,
                    std::shared_ptr<const MarginalizationPrior> prior, std::shared_ptr<const ceres::Manifold> pose_manifold);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  const ceres::CostFunction& factor() const { return *factor_; }
  /// True when some block of `blocks` is one the prior holds.
  static bool touches(const std::vector<double*>& blocks, const MarginalizationPrior& prior);

 private:
  std::shared_ptr<ceres::CostFunction> factor_;
  std::shared_ptr<const MarginalizationPrior> prior_;  // owns the first estimates
  std::shared_ptr<const ceres::Manifold> pose_manifold_;
  std::vector<const double*> first_;                   // per block: x0, or null for the current value
  std::vector<bool> pose_;                             // per block: on the pose manifold
};

/// Re-expresses a prior just computed at the current values around the first estimates the old
/// prior kept for the same blocks: r <- r - J (x [-] x0_old), x0 <- x0_old (first order), so a block
/// keeps one linearization point for as long as priors hold it.
void keep_first_estimates(MarginalizationPrior& prior, const MarginalizationPrior& old_prior);

}  // namespace navaid::estimation
