#include "navaid/estimation/first_estimates.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include "navaid/core/errors.hpp"

namespace navaid::estimation {

namespace {

constexpr int kPoseAmbient = 7;
constexpr int kPoseTangent = 6;
using PlusJacobian = Eigen::Matrix<double, kPoseAmbient, kPoseTangent, Eigen::RowMajor>;

}  // namespace

FirstEstimateCost::FirstEstimateCost(std::shared_ptr<ceres::CostFunction> factor, const std::vector<double*>& blocks,
                                     std::shared_ptr<const MarginalizationPrior> prior,
                                     std::shared_ptr<const ceres::Manifold> pose_manifold)
    : factor_(std::move(factor)), prior_(std::move(prior)), pose_manifold_(std::move(pose_manifold)) {
  if (!factor_ || !prior_ || !pose_manifold_) throw Error("FirstEstimateCost: null factor, prior or manifold");
  if (blocks.size() != factor_->parameter_block_sizes().size())
    throw Error("FirstEstimateCost: " + std::to_string(blocks.size()) + " blocks for a factor of " +
                std::to_string(factor_->parameter_block_sizes().size()));
  set_num_residuals(factor_->num_residuals());
  *mutable_parameter_block_sizes() = factor_->parameter_block_sizes();
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const int k = prior_->index_of(blocks[i]);
    first_.push_back(k >= 0 ? prior_->x0[static_cast<std::size_t>(k)].data() : nullptr);
    pose_.push_back(k >= 0 && prior_->kinds[static_cast<std::size_t>(k)] == BlockKind::kPose);
    if (pose_.back() && factor_->parameter_block_sizes()[i] != kPoseAmbient)
      throw Error("FirstEstimateCost: a pose block of size " + std::to_string(factor_->parameter_block_sizes()[i]));
  }
}

bool FirstEstimateCost::touches(const std::vector<double*>& blocks, const MarginalizationPrior& prior) {
  for (const double* b : blocks)
    if (prior.index_of(b) >= 0) return true;
  return false;
}

bool FirstEstimateCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  if (!factor_->Evaluate(parameters, residuals, nullptr)) return false;
  if (!jacobians) return true;
  const std::size_t n = first_.size();
  std::vector<const double*> at(n);
  for (std::size_t i = 0; i < n; ++i) at[i] = first_[i] ? first_[i] : parameters[i];
  std::vector<double> scratch(static_cast<std::size_t>(num_residuals()));
  if (!factor_->Evaluate(at.data(), scratch.data(), jacobians)) return false;
  const int rows = num_residuals();
  for (std::size_t i = 0; i < n; ++i) {
    if (!jacobians[i] || !pose_[i]) continue;
    PlusJacobian P0, P;
    pose_manifold_->PlusJacobian(first_[i], P0.data());
    pose_manifold_->PlusJacobian(parameters[i], P.data());
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, kPoseAmbient, Eigen::RowMajor>> J(jacobians[i], rows, kPoseAmbient);
    const Eigen::Matrix<double, kPoseTangent, kPoseAmbient> P_pinv =
        Eigen::Matrix<double, kPoseAmbient, kPoseTangent>(P).completeOrthogonalDecomposition().pseudoInverse();
    const Eigen::MatrixXd tangent = J * P0;
    J = tangent * P_pinv;
  }
  return true;
}

void keep_first_estimates(MarginalizationPrior& prior, const MarginalizationPrior& old_prior) {
  for (std::size_t i = 0; i < prior.blocks.size(); ++i) {
    const int k = old_prior.index_of(prior.blocks[i]);
    if (k < 0) continue;
    const auto& first = old_prior.x0[static_cast<std::size_t>(k)];
    const int size = tangent_size(prior.kinds[i], prior.ambient_sizes[i]);
    Eigen::VectorXd delta(size);
    // x0 holds the values the new prior was linearized at (the current ones).
    block_minus(prior.kinds[i], prior.ambient_sizes[i], prior.x0[i].data(), first.data(), delta.data());
    prior.r -= prior.J.middleCols(prior.tangent_offsets[i], size) * delta;
    prior.x0[i] = first;
  }
}

}  // namespace navaid::estimation
