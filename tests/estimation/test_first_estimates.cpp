// First-estimate Jacobians (navaid/estimation/first_estimates.hpp): the wrapped factor's residual at
// the current values, its Jacobians at the prior's first estimates, and a prior re-expressed
// around the old first estimates that keeps its value.
#include "navaid/estimation/first_estimates.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "factor_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/landmark_factors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {
namespace {

using testing::random_pose;
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// A prior on the given blocks around x0 (copies of the values given), unit information.
std::shared_ptr<MarginalizationPrior> prior_on(const std::vector<double*>& blocks, const std::vector<BlockKind>& kinds,
                                               const std::vector<std::vector<double>>& x0) {
  auto p = std::make_shared<MarginalizationPrior>();
  int offset = 0;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    p->blocks.push_back(blocks[i]);
    p->kinds.push_back(kinds[i]);
    p->ambient_sizes.push_back(static_cast<int>(x0[i].size()));
    p->tangent_offsets.push_back(offset);
    p->x0.push_back(x0[i]);
    offset += tangent_size(kinds[i], static_cast<int>(x0[i].size()));
  }
  p->J = Eigen::MatrixXd::Identity(offset, offset);
  p->r = Eigen::VectorXd::Zero(offset);
  return p;
}

struct Evaluated {
  Eigen::Vector2d r;
  std::vector<RowMajor> J;  // ambient
};

Evaluated evaluate(const ceres::CostFunction& f, const std::vector<const double*>& at) {
  Evaluated e;
  const std::vector<int> sizes = f.parameter_block_sizes();
  std::vector<double*> ptrs;
  for (int s : sizes) e.J.emplace_back(2, s);
  for (auto& j : e.J) ptrs.push_back(j.data());
  EXPECT_TRUE(f.Evaluate(at.data(), e.r.data(), ptrs.data()));
  return e;
}

RowMajor plus_jacobian(const ceres::Manifold& m, const double* x) {
  RowMajor P(7, 6);
  m.PlusJacobian(x, P.data());
  return P;
}

TEST(FirstEstimateCost, ResidualAtTheCurrentValuesJacobiansAtTheFirstEstimates) {
  std::mt19937_64 rng(7);
  double anchor[7], target[7], extrinsic[7], landmark[3] = {0.1, -0.05, 0.4};
  pose_to_block(SE3(), anchor);
  pose_to_block(SE3(Quat::Identity(), Vec3(0.3, 0.0, 0.1)), target);
  pose_to_block(SE3(), extrinsic);
  // The first estimates of the target pose and the landmark, a little away from the current values.
  double target0[7], landmark0[3] = {0.11, -0.04, 0.38};
  pose_to_block(SE3(Quat(Eigen::AngleAxisd(0.05, Vec3(0.3, 1.0, 0.2).normalized())), Vec3(0.25, 0.02, 0.12)),
                target0);
  const auto prior = prior_on({target, landmark}, {BlockKind::kPose, BlockKind::kEuclidean},
                              {std::vector<double>(target0, target0 + 7), std::vector<double>(landmark0, landmark0 + 3)});
  auto factor = std::make_shared<LandmarkReprojectionFactor>(Eigen::Vector2d(0.2, -0.1), 450.0, 1.5);
  std::shared_ptr<const ceres::Manifold> manifold = make_pose_manifold();
  const FirstEstimateCost fej(factor, {anchor, target, extrinsic, landmark}, prior, manifold);

  const Evaluated wrapped = evaluate(fej, {anchor, target, extrinsic, landmark});
  const Evaluated current = evaluate(*factor, {anchor, target, extrinsic, landmark});
  const Evaluated first = evaluate(*factor, {anchor, target0, extrinsic, landmark0});
  EXPECT_LT((wrapped.r - current.r).norm(), 1e-12);
  // Blocks the prior does not hold: the factor's Jacobian, taken at the first estimates of the others.
  EXPECT_LT((wrapped.J[0] - first.J[0]).norm(), 1e-9 * first.J[0].norm());
  // The landmark (Euclidean): the Jacobian at its first estimate.
  EXPECT_LT((wrapped.J[3] - first.J[3]).norm(), 1e-9 * first.J[3].norm());
  EXPECT_GT((current.J[3] - first.J[3]).norm(), 1e-3 * first.J[3].norm());  // the test moves something
  // The target pose: Ceres' tangent Jacobian is the first estimate's, J(x0) P(x0).
  const RowMajor tangent_wrapped = wrapped.J[1] * plus_jacobian(*manifold, target);
  const RowMajor tangent_first = first.J[1] * plus_jacobian(*manifold, target0);
  EXPECT_LT((tangent_wrapped - tangent_first).norm(), 1e-9 * tangent_first.norm());
  const RowMajor tangent_current = current.J[1] * plus_jacobian(*manifold, target);
  EXPECT_GT((tangent_current - tangent_first).norm(), 1e-3 * tangent_first.norm());
}

TEST(FirstEstimateCost, WithoutPriorBlocksItIsTheFactor) {
  std::mt19937_64 rng(3);
  double anchor[7], target[7], extrinsic[7], landmark[3] = {0.05, 0.02, 0.5}, other[3] = {0, 0, 0};
  pose_to_block(SE3(), anchor);
  pose_to_block(random_pose(rng, 0.3), target);
  pose_to_block(SE3(), extrinsic);
  const auto prior = prior_on({other}, {BlockKind::kEuclidean}, {{1.0, 2.0, 3.0}});
  auto factor = std::make_shared<LandmarkReprojectionFactor>(Eigen::Vector2d(0.0, 0.0), 450.0, 1.5);
  const std::vector<double*> blocks{anchor, target, extrinsic, landmark};
  EXPECT_FALSE(FirstEstimateCost::touches(blocks, *prior));
  const FirstEstimateCost fej(factor, blocks, prior, make_pose_manifold());
  const Evaluated a = evaluate(fej, {anchor, target, extrinsic, landmark});
  const Evaluated b = evaluate(*factor, {anchor, target, extrinsic, landmark});
  EXPECT_EQ(a.r, b.r);
  for (std::size_t i = 0; i < a.J.size(); ++i) EXPECT_EQ(a.J[i], b.J[i]) << i;
}

TEST(FirstEstimateCost, RejectsBlocksThatDoNotFitTheFactor) {
  double pose[7] = {0, 0, 0, 0, 0, 0, 1}, landmark[3] = {0, 0, 1};
  const auto prior = prior_on({landmark}, {BlockKind::kEuclidean}, {{0, 0, 1}});
  auto factor = std::make_shared<LandmarkReprojectionFactor>(Eigen::Vector2d::Zero(), 450.0, 1.5);
  EXPECT_THROW(FirstEstimateCost(factor, {pose, pose, landmark}, prior, make_pose_manifold()), Error);
  EXPECT_THROW(FirstEstimateCost(nullptr, {landmark}, prior, make_pose_manifold()), Error);
  // A pose kind on a block the factor sizes 3.
  const auto wrong = prior_on({landmark}, {BlockKind::kPose}, {{0, 0, 0, 0, 0, 0, 1}});
  double a[7] = {0, 0, 0, 0, 0, 0, 1}, t[7] = {0, 0, 0, 0, 0, 0, 1}, e[7] = {0, 0, 0, 0, 0, 0, 1};
  EXPECT_THROW(FirstEstimateCost(factor, {a, t, e, landmark}, wrong, make_pose_manifold()), Error);
}

// e(x) = r + J (x [-] x0) of a prior, through its factor.
Eigen::VectorXd prior_value(const std::shared_ptr<MarginalizationPrior>& p) {
  const MarginalizationFactor f(p);
  Eigen::VectorXd e(p->J.rows());
  EXPECT_TRUE(f.Evaluate(p->blocks.data(), e.data(), nullptr));
  return e;
}

TEST(KeepFirstEstimates, MovesTheLinearizationPointAndKeepsThePrior) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  double pose[7], point[3] = {1.0, 2.0, 3.0}, fresh[2] = {0.5, -0.5};
  pose_to_block(random_pose(rng, 1.0), pose);
  // The new prior, linearized at the current values; the old one held the pose and the point.
  auto now = prior_on({pose, point, fresh}, {BlockKind::kPose, BlockKind::kEuclidean, BlockKind::kEuclidean},
                      {std::vector<double>(pose, pose + 7), {1.0, 2.0, 3.0}, {0.5, -0.5}});
  for (int i = 0; i < now->J.rows(); ++i)
    for (int j = 0; j < now->J.cols(); ++j) now->J(i, j) = n(rng);
  for (int i = 0; i < now->r.size(); ++i) now->r(i) = n(rng);
  double pose_old[7];
  pose_to_block(pose_from_block(pose) * SE3(Quat(Eigen::AngleAxisd(0.02, Vec3::UnitZ())), Vec3(0.01, 0, 0)), pose_old);
  const auto old = prior_on({point, pose}, {BlockKind::kEuclidean, BlockKind::kPose},
                            {{0.9, 2.1, 3.05}, std::vector<double>(pose_old, pose_old + 7)});
  const Eigen::VectorXd before = prior_value(now);
  keep_first_estimates(*now, *old);
  EXPECT_EQ(now->x0[0], std::vector<double>(pose_old, pose_old + 7));
  EXPECT_EQ(now->x0[1], (std::vector<double>{0.9, 2.1, 3.05}));
  EXPECT_EQ(now->x0[2], (std::vector<double>{0.5, -0.5}));  // new in this prior: its own
  // At the current values (where it was computed) the prior's value is unchanged.
  EXPECT_LT((prior_value(now) - before).norm(), 1e-12 * (1.0 + before.norm()));
  // Elsewhere, along the Euclidean blocks, exactly so too (the prior is linear in them).
  point[0] += 0.3;
  fresh[1] -= 0.2;
  const Eigen::VectorXd moved = prior_value(now);
  Eigen::VectorXd expected = before;
  expected += now->J.col(6) * 0.3 - now->J.col(10) * 0.2;
  EXPECT_LT((moved - expected).norm(), 1e-12 * (1.0 + expected.norm()));
}

}  // namespace
}  // namespace navaid::estimation
