#pragma once
// Marginalization prior for the sliding window (VINS-Mono style; W-ROMA RGBD-VIO §V-B).
//
// When the window drops states (the oldest keyframe's pose and speed-bias, the inverse depths of
// the features anchored in it), every factor touching them is linearized at the current estimate
// in the blocks' tangent spaces, whitened by its robust loss, and stacked:
//
//   H = J^T J,  b = J^T r   over all blocks, ordered [marginalized m | kept k]
//   H* = H_kk - H_km H_mm^+ H_mk,   b* = b_k - H_km H_mm^+ b_m
//
// H_mm^+ is a pseudo-inverse: eigenvalues of H_mm = V S V^T below the threshold (Options) are
// dropped, so a marginalized direction that nothing observes (a block without information, a
// gauge freedom) leaves no NaN. The prior is stored in square-root form: J_p = S^1/2 V^T,
// r_p = S^-1/2 V^T b* from H* = V S V^T (same threshold), so J_p^T J_p = H*, J_p^T r_p = b*.
// A well-conditioned matrix (rcond estimate 1000x above the relative threshold: no eigenvalue
// would be dropped) is factored by Cholesky instead, H = L L^T, J_p = L^T, r_p = L^-1 b*: the
// same H*, b* at a fraction of the cost.
//
// MarginalizationFactor turns the prior into a residual on the kept blocks:
//
//   e(x) = r_p + J_p (x [-] x0)
//
// with x0 the kept blocks' values at marginalization time. J_p stays the Jacobian at x0 (first
// estimates): the prior is never re-linearized, so it keeps the null space it had there (global
// position and yaw) and cannot gain spurious information along it when the kept states move.
//
// Tangents are the manifolds' (docs/estimator.md §2): Euclidean blocks x - x0; pose blocks
// (PoseManifold, 7 doubles [p, q]) [p - p0, d] where d inverts Ceres' quaternion plus
// q0 [+] d = [cos|d|, sin|d| d/|d|] * q0 (a LEFT rotation by 2d): with dq = q * q0^-1, flipped
// to dq_w >= 0, d = atan2(|dq_v|, dq_w) dq_v / |dq_v|. Then q0 [+] (q [-] q0) = +-q, the same
// rotation; it is invariant to the scale and sign of q, so its ambient Jacobian has no component
// along q. The factor returns Jacobians w.r.t. the 7 ambient numbers: J_p d(x [-] x0)/dx.
//
// Robust losses are applied as Ceres applies them (Triggs correction; see Problem::Evaluate):
// with s = |r|^2 and rho(s), J <- sqrt(rho') (I - alpha r r^T / s) J, r <- sqrt(rho') r / (1 - alpha),
// alpha = 1 - sqrt(1 + 2 s rho'' / rho') when rho'' > 0, else 0 (plain sqrt(rho') scaling).
//
// Usage (one window shift):
//   Marginalizer marg;
//   marg.set_manifold(pose_block, BlockKind::kPose);             // for every pose block involved
//   marg.set_constant(extrinsic_block);                           // blocks held constant in the window
//   marg.add({imu_factor, nullptr, {pose0, sb0, pose1, sb1}, {0, 1}});
//   marg.add({reproj, cauchy, {pose0, pose3, T_B_C, lambda}, {0, 3}});
//   marg.add({old_prior_factor, nullptr, old_prior->blocks, {index of pose0, index of sb0}});
//   auto prior = std::make_shared<MarginalizationPrior>(marg.marginalize());
//   ... the window shifts its arrays; prior->remap({{old_address, new_address}, ...});
//   if (!prior->empty())
//     problem.AddResidualBlock(new MarginalizationFactor(prior), nullptr, prior->blocks);
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

namespace navaid::estimation {

/// How a parameter block's tangent relates to its stored numbers.
enum class BlockKind {
  kEuclidean,  ///< tangent = ambient (speed-bias, inverse depth, T_ENU_W, ...)
  kPose,       ///< 7 doubles on PoseManifold, tangent 6
};

/// Tangent size of a block of the given kind and ambient size (6 for a pose).
int tangent_size(BlockKind kind, int ambient_size);

/// A factor to be marginalized: its cost, optional loss, blocks in the cost's order, and which of
/// them (indices into blocks) leave the window. A block is marginalized when any term marks it.
struct MarginalizationTerm {
  std::shared_ptr<const ceres::CostFunction> cost;  ///< shared: the window keeps using its factors
  std::shared_ptr<const ceres::LossFunction> loss;  ///< may be null (plain least squares)
  std::vector<double*> blocks;
  std::vector<int> marginalize;
};

/// Wraps a factor the caller keeps owning (e.g. one a ceres::Problem owns) without taking ownership.
/// The object must outlive the Marginalizer's use of it.
template <typename T>
std::shared_ptr<const T> borrow(const T* object) {
  return std::shared_ptr<const T>(std::shared_ptr<const T>(), object);
}

/// The linear prior left on the kept blocks. Square-root form: cost 1/2 |r + J (x [-] x0)|^2.
struct MarginalizationPrior {
  std::vector<double*> blocks;             ///< kept blocks (addresses in the window), in order
  std::vector<BlockKind> kinds;            ///< per block
  std::vector<int> ambient_sizes;          ///< per block (7 for a pose)
  std::vector<int> tangent_offsets;        ///< per block: first column of the block in J
  std::vector<std::vector<double>> x0;     ///< per block: linearization point (ambient numbers)
  Eigen::MatrixXd J;                       ///< rank x tangent_size()
  Eigen::VectorXd r;                       ///< rank

  int tangent_size() const { return static_cast<int>(J.cols()); }
  /// True when the prior carries no information (J has no rows): do not add a factor then.
  bool empty() const { return J.rows() == 0; }
  /// H* = J^T J (tangent_size x tangent_size).
  Eigen::MatrixXd information() const { return J.transpose() * J; }
  /// b* = J^T r.
  Eigen::VectorXd gradient() const { return J.transpose() * r; }
  /// Index of a block in blocks, or -1 (e.g. to mark the old prior's blocks in the next term).
  int index_of(const double* block) const;

  /// Replaces block addresses after the window moved its state arrays. Blocks absent from the map
  /// keep their address. Throws Error when two kept blocks would end at the same address.
  void remap(const std::unordered_map<const double*, double*>& old_to_new);
};

/// A Gaussian prior on one block around its current value, in the prior's square-root form
/// (J = sqrt_information, r = 0): r(x) = sqrt_information (x [-] x0). sqrt_information is
/// tangent x tangent (e.g. L^-1 of the covariance, or diag(1/sigma)); throws Error on a size mismatch.
MarginalizationPrior gaussian_block_prior(double* block, BlockKind kind, int ambient_size,
                                          const Eigen::MatrixXd& sqrt_information);

/// x [-] x0 in the tangent of the block's manifold (see the top of this file); tangent_size() doubles.
void block_minus(BlockKind kind, int ambient_size, const double* x, const double* x0, double* delta);

/// Collects the factors of the states leaving the window and computes the prior on the rest.
class Marginalizer {
 public:
  struct Options {
    /// Eigenvalues of H_mm and of H* below max(relative * largest eigenvalue, absolute) count as
    /// zero (dropped from the pseudo-inverse / from the prior's rows).
    double relative_eigenvalue_threshold = 1e-10;
    double absolute_eigenvalue_threshold = 1e-12;
  };

  Marginalizer() = default;
  explicit Marginalizer(Options options);

  /// Declares a block's manifold (default kEuclidean). Must be called for every pose block.
  /// Throws Error for a pose block that a term gives a size other than 7 (at marginalize()).
  void set_manifold(const double* block, BlockKind kind);
  /// A block held constant in the window: it is neither marginalized nor part of the prior
  /// (its Jacobian columns are ignored). Throws Error at marginalize() when a term marks it.
  void set_constant(const double* block);

  /// Throws Error when the cost is null, the block count does not match the cost, a block is null
  /// or repeated, or an index in marginalize is out of range.
  void add(MarginalizationTerm term);

  /// Linearizes every term at the current block values and Schur-complements the marginalized
  /// blocks out. Kept blocks appear in the order they were first met in the terms. Throws Error
  /// when a cost fails to evaluate or returns non-finite values, or a block's size is inconsistent.
  MarginalizationPrior marginalize() const;

  std::size_t num_terms() const { return terms_.size(); }

 private:
  Options options_;
  std::unordered_map<const double*, BlockKind> kinds_;
  std::unordered_set<const double*> constant_;
  std::vector<MarginalizationTerm> terms_;
};

/// The prior as a Ceres cost on prior->blocks (ambient sizes; pose blocks need the PoseManifold in
/// the problem). Residual r + J (x [-] x0), Jacobian J d(x [-] x0)/dx w.r.t. the ambient numbers.
class MarginalizationFactor final : public ceres::CostFunction {
 public:
  /// Throws Error when the prior is null or empty.
  explicit MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  const MarginalizationPrior& prior() const { return *prior_; }

 private:
  std::shared_ptr<const MarginalizationPrior> prior_;
};

}  // namespace navaid::estimation
