#include "factor_check.hpp"

#include <sstream>

#include <Eigen/Core>

#include "navaid/core/random_draws.hpp"

namespace navaid::estimation::testing {

namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::VectorXd evaluate(const ceres::CostFunction& f, const std::vector<double*>& blocks, bool* ok) {
  Eigen::VectorXd r(f.num_residuals());
  *ok = f.Evaluate(blocks.data(), r.data(), nullptr);
  return r;
}

}  // namespace

::testing::AssertionResult jacobians_match(const ceres::CostFunction& f, const std::vector<double*>& blocks,
                                           const std::vector<const ceres::Manifold*>& manifolds, double tol,
                                           double step) {
  const std::vector<int32_t>& sizes = f.parameter_block_sizes();
  const int m = f.num_residuals();
  if (blocks.size() != sizes.size() || manifolds.size() != sizes.size()) {
    return ::testing::AssertionFailure() << "block count mismatch";
  }
  std::vector<RowMajorMatrix> J(sizes.size());
  std::vector<double*> J_ptrs(sizes.size());
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    J[b].resize(m, sizes[b]);
    J_ptrs[b] = J[b].data();
  }
  Eigen::VectorXd r0(m);
  if (!f.Evaluate(blocks.data(), r0.data(), J_ptrs.data())) return ::testing::AssertionFailure() << "Evaluate failed";

  std::ostringstream report;
  bool all_ok = true;
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    const ceres::Manifold* manifold = manifolds[b];
    const int n = sizes[b];
    const int t = manifold ? manifold->TangentSize() : n;
    RowMajorMatrix plus_jacobian = RowMajorMatrix::Identity(n, t);
    if (manifold) manifold->PlusJacobian(blocks[b], plus_jacobian.data());
    const Eigen::MatrixXd analytic = J[b] * plus_jacobian;

    Eigen::MatrixXd numeric(m, t);
    const std::vector<double> x0(blocks[b], blocks[b] + n);
    for (int k = 0; k < t; ++k) {
      Eigen::VectorXd delta = Eigen::VectorXd::Zero(t);
      Eigen::VectorXd r[2];
      for (int s = 0; s < 2; ++s) {
        delta[k] = s == 0 ? step : -step;
        if (manifold) {
          manifold->Plus(x0.data(), delta.data(), blocks[b]);
        } else {
          for (int i = 0; i < n; ++i) blocks[b][i] = x0[i] + delta[i];
        }
        bool ok = false;
        r[s] = evaluate(f, blocks, &ok);
        if (!ok) return ::testing::AssertionFailure() << "Evaluate failed at a perturbed state";
      }
      numeric.col(k) = (r[0] - r[1]) / (2.0 * step);
      std::copy(x0.begin(), x0.end(), blocks[b]);
    }
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    const double err = (analytic - numeric).cwiseAbs().maxCoeff() / scale;
    if (!(err <= tol)) {
      all_ok = false;
      report << "block " << b << ": relative error " << err << " (scale " << scale << ")\nanalytic:\n"
             << analytic << "\nnumeric:\n" << numeric << "\n";
    }
  }
  if (!all_ok) return ::testing::AssertionFailure() << report.str();
  return ::testing::AssertionSuccess();
}

Quat random_rotation(std::mt19937_64& rng, double max_angle) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, max_angle);
  const Vec3 axis = draw_vector<3>([&] { return n(rng); });
  return so3_exp(axis.normalized() * u(rng));
}

Vec3 random_vector(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  const double x = u(rng), y = u(rng), z = u(rng);
  return Vec3(x, y, z);
}

SE3 random_pose(std::mt19937_64& rng, double translation_scale) {
  const Quat q = random_rotation(rng);
  return SE3(q, random_vector(rng, translation_scale));
}

}  // namespace navaid::estimation::testing
