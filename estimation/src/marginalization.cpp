#include "navaid/estimation/marginalization.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "navaid/core/errors.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// dq = q * q0^-1 flipped to dq_w >= 0, and the sign used (so that d(dq)/dq carries it).
Eigen::Vector4d relative_quaternion(const double* q, const double* q0, double& sign) {
  const Quat q0_unit = Eigen::Map<const Quat>(q0).normalized();
  const Quat dq = Eigen::Map<const Quat>(q) * q0_unit.conjugate();
  sign = dq.w() < 0.0 ? -1.0 : 1.0;
  return sign * dq.coeffs();
}

// d = atan2(|v|, w) v / |v| for dq = [v, w], w >= 0: inverts [cos|d|, sin|d| d/|d|] up to scale.
Vec3 half_log(const Eigen::Vector4d& dq) {
  const Vec3 v = dq.head<3>();
  const double w = dq[3];
  const double n = v.norm();
  if (n <= 1e-6 * w) return (1.0 / w - n * n / (3.0 * w * w * w)) * v;  // atan series, exact to O(n^4)
  return std::atan2(n, w) / n * v;
}

// d(half_log)/d(dq), 3 x 4 (columns x y z w).
Eigen::Matrix<double, 3, 4> half_log_jacobian(const Eigen::Vector4d& dq) {
  const Vec3 v = dq.head<3>();
  const double w = dq[3];
  const double n2 = v.squaredNorm();
  const double n = std::sqrt(n2);
  double f = 0.0;  // theta / n
  double g = 0.0;  // d(theta / n)/dv = g v
  if (n <= 1e-6 * w) {
    f = 1.0 / w - n2 / (3.0 * w * w * w);
    g = -2.0 / (3.0 * w * w * w);
  } else {
    f = std::atan2(n, w) / n;
    g = (w / (n2 + w * w) - f) / n2;
  }
  Eigen::Matrix<double, 3, 4> D;
  D.leftCols<3>() = f * Mat3::Identity() + g * v * v.transpose();
  D.col(3) = -v / (n2 + w * w);
  return D;
}

// d(q * p)/dq for a fixed p, 4 x 4 in [x y z w] order.
Eigen::Matrix4d right_multiplication_matrix(const Quat& p) {
  Eigen::Matrix4d M;
  M.topLeftCorner<3, 3>() = p.w() * Mat3::Identity() - hat(p.vec());
  M.topRightCorner<3, 1>() = p.vec();
  M.bottomLeftCorner<1, 3>() = -p.vec().transpose();
  M(3, 3) = p.w();
  return M;
}

// d(pose [-] pose0)/d(pose), 6 x 7.
Eigen::Matrix<double, 6, 7> pose_minus_jacobian(const double* x, const double* x0) {
  double sign = 1.0;
  const Eigen::Vector4d dq = relative_quaternion(x + 3, x0 + 3, sign);
  const Quat q0_inverse = Eigen::Map<const Quat>(x0 + 3).normalized().conjugate();
  Eigen::Matrix<double, 6, 7> D = Eigen::Matrix<double, 6, 7>::Zero();
  D.topLeftCorner<3, 3>().setIdentity();
  D.bottomRightCorner<3, 4>() = sign * half_log_jacobian(dq) * right_multiplication_matrix(q0_inverse);
  return D;
}

bool all_finite(const double* values, int count) {
  return std::all_of(values, values + count, [](double v) { return std::isfinite(v); });
}

// Whitens a residual and its Jacobian by the loss like Ceres' residual evaluation (Triggs et al.,
// "Bundle adjustment - a modern synthesis", §4.3), so that J^T J and J^T r are Ceres' Gauss-Newton
// Hessian and gradient of rho(|r|^2) / 2. The Jacobian is corrected with the uncorrected residual.
void apply_loss(const ceres::LossFunction& loss, Eigen::VectorXd& r, Eigen::MatrixXd& J) {
  const double s = r.squaredNorm();
  double rho[3];
  loss.Evaluate(s, rho);
  if (!(rho[1] > 0.0)) {  // a loss that ignores this residual entirely
    r.setZero();
    J.setZero();
    return;
  }
  const double sqrt_rho1 = std::sqrt(rho[1]);
  if (s == 0.0 || rho[2] <= 0.0) {
    r *= sqrt_rho1;
    J *= sqrt_rho1;
    return;
  }
  const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
  J = sqrt_rho1 * (J - (alpha / s) * r * (r.transpose() * J));
  r *= sqrt_rho1 / (1.0 - alpha);
}

// A square root R (R^T R = H, rows = numerical rank) of a positive semi-definite H, and the
// products with R^+T that the Schur complement and the prior need. When H is well conditioned
// (the rcond estimate bounds lambda_min / lambda_max from below, kept 1000x above the threshold so
// that no eigenvalue would be dropped) a Cholesky factor R = L^T serves, at a fraction of the cost;
// otherwise H = U S U^T with the eigenvalues below max(relative * largest, absolute) dropped,
// R = S^1/2 U^T and R^+T = S^-1/2 U^T (the pseudo-inverse).
// The Cholesky test above, for any fixed or dynamic size: llt of H, norm1 = H's largest column sum.
template <typename Llt>
bool cholesky_suffices(const Llt& llt, double norm1, const Marginalizer::Options& options) {
  return llt.info() == Eigen::Success && llt.rcond() > 1e3 * options.relative_eigenvalue_threshold &&
         llt.rcond() * norm1 > 1e3 * options.absolute_eigenvalue_threshold;
}

class SquareRoot {
 public:
  SquareRoot(const Eigen::MatrixXd& H, const Marginalizer::Options& options) {
    const Eigen::Index n = H.rows();
    if (n == 0) return;
    llt_.compute(H);
    const double norm1 = H.cwiseAbs().colwise().sum().maxCoeff();  // >= lambda_max
    triangular_ = cholesky_suffices(llt_, norm1, options);
    if (triangular_) return;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
    const double largest = eig.eigenvalues()[n - 1];  // ascending
    const double threshold =
        std::max(options.relative_eigenvalue_threshold * largest, options.absolute_eigenvalue_threshold);
    Eigen::Index first = 0;
    while (first < n && !(eig.eigenvalues()[first] > threshold)) ++first;
    sqrt_values_ = eig.eigenvalues().tail(n - first).cwiseSqrt();
    vectors_ = eig.eigenvectors().rightCols(n - first);
  }

  /// R (rank x n).
  Eigen::MatrixXd factor() const {
    if (triangular_) return llt_.matrixU();
    return sqrt_values_.asDiagonal() * vectors_.transpose();
  }
  /// R^+T M.
  Eigen::MatrixXd solve_transpose(const Eigen::MatrixXd& M) const {
    if (triangular_) return llt_.matrixL().solve(M);
    return sqrt_values_.cwiseInverse().asDiagonal() * (vectors_.transpose() * M);
  }

 private:
  bool triangular_ = false;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd sqrt_values_;
  Eigen::MatrixXd vectors_;
};

// A landmark (tangent 3) seen from poses (tangent 6), the bulk of the first-eliminated blocks:
// the same complement as the generic path with fixed-size kernels, when its Cholesky factor is
// well conditioned by SquareRoot's test (else false: the generic path takes the pseudo-inverse).
bool eliminate_landmark_on_poses(const Eigen::MatrixXd& H_ii, const Eigen::VectorXd& b_i,
                                 const std::vector<Eigen::MatrixXd>& H_ia, const std::vector<int>& offsets,
                                 const Marginalizer::Options& options, Eigen::MatrixXd& H, Eigen::VectorXd& b) {
  const Eigen::Matrix3d A = H_ii;
  const Eigen::LLT<Eigen::Matrix3d> llt(A);
  if (!cholesky_suffices(llt, A.cwiseAbs().colwise().sum().maxCoeff(), options)) return false;
  const auto L = llt.matrixL();
  const Eigen::Vector3d w_b = L.solve(Eigen::Vector3d(b_i));
  thread_local std::vector<Eigen::Matrix<double, 3, 6>> W;
  W.resize(H_ia.size());
  for (std::size_t x = 0; x < H_ia.size(); ++x) W[x] = L.solve(Eigen::Matrix<double, 3, 6>(H_ia[x]));
  for (std::size_t x = 0; x < W.size(); ++x) {
    b.segment<6>(offsets[x]).noalias() -= W[x].transpose() * w_b;
    for (std::size_t y = 0; y < W.size(); ++y)
      H.block<6, 6>(offsets[x], offsets[y]).noalias() -= W[x].transpose() * W[y];
  }
  return true;
}

struct BlockInfo {
  double* address = nullptr;
  BlockKind kind = BlockKind::kEuclidean;
  int ambient = 0;
  int tangent = 0;
  bool marginalized = false;
  bool constant = false;
  int offset = -1;  // column in H; -1 for constant blocks
  Eigen::Matrix<double, kPoseSize, kPoseTangentSize, Eigen::RowMajor> plus_jacobian;  // poses only
};

}  // namespace

int tangent_size(BlockKind kind, int ambient_size) {
  if (kind == BlockKind::kPose) {
    if (ambient_size != kPoseSize) {
      throw Error("marginalization: a pose block has 7 doubles, got " + std::to_string(ambient_size));
    }
    return kPoseTangentSize;
  }
  return ambient_size;
}

void block_minus(BlockKind kind, int ambient_size, const double* x, const double* x0, double* delta) {
  if (kind == BlockKind::kEuclidean) {
    for (int i = 0; i < ambient_size; ++i) delta[i] = x[i] - x0[i];
    return;
  }
  tangent_size(kind, ambient_size);  // validates the size
  for (int i = 0; i < 3; ++i) delta[i] = x[i] - x0[i];
  double sign = 1.0;
  Eigen::Map<Vec3>(delta + 3) = half_log(relative_quaternion(x + 3, x0 + 3, sign));
}

MarginalizationPrior gaussian_block_prior(double* block, BlockKind kind, int ambient_size,
                                          const Eigen::MatrixXd& sqrt_information) {
  const int n = tangent_size(kind, ambient_size);
  if (sqrt_information.rows() != n || sqrt_information.cols() != n)
    throw Error("gaussian_block_prior: the square-root information must be " + std::to_string(n) + "x" +
                std::to_string(n));
  MarginalizationPrior prior;
  prior.blocks = {block};
  prior.kinds = {kind};
  prior.ambient_sizes = {ambient_size};
  prior.tangent_offsets = {0};
  prior.x0 = {std::vector<double>(block, block + ambient_size)};
  prior.J = sqrt_information;
  prior.r = Eigen::VectorXd::Zero(n);
  return prior;
}

int MarginalizationPrior::index_of(const double* block) const {
  const auto it = std::find(blocks.begin(), blocks.end(), block);
  return it == blocks.end() ? -1 : static_cast<int>(it - blocks.begin());
}

void MarginalizationPrior::remap(const std::unordered_map<const double*, double*>& old_to_new) {
  std::vector<double*> moved = blocks;
  for (double*& block : moved) {
    const auto it = old_to_new.find(block);
    if (it != old_to_new.end()) block = it->second;
  }
  std::unordered_set<const double*> seen;
  for (const double* block : moved) {
    if (block == nullptr) throw Error("marginalization prior: remap to a null block address");
    if (!seen.insert(block).second) {
      throw Error("marginalization prior: remap sends two kept blocks to the same address");
    }
  }
  blocks = std::move(moved);
}

Marginalizer::Marginalizer(Options options) : options_(options) {
  if (!(options_.relative_eigenvalue_threshold >= 0.0) || !(options_.absolute_eigenvalue_threshold >= 0.0)) {
    throw Error("marginalization: eigenvalue thresholds must be >= 0");
  }
}

void Marginalizer::set_manifold(const double* block, BlockKind kind) {
  if (block == nullptr) throw Error("marginalization: set_manifold on a null block");
  kinds_[block] = kind;
}

void Marginalizer::set_constant(const double* block) {
  if (block == nullptr) throw Error("marginalization: set_constant on a null block");
  constant_.insert(block);
}

void Marginalizer::add(MarginalizationTerm term) {
  if (!term.cost) throw Error("marginalization: term without a cost function");
  const auto& sizes = term.cost->parameter_block_sizes();
  if (sizes.size() != term.blocks.size()) {
    throw Error("marginalization: the cost has " + std::to_string(sizes.size()) + " parameter blocks, the term " +
                std::to_string(term.blocks.size()));
  }
  for (std::size_t i = 0; i < term.blocks.size(); ++i) {
    if (term.blocks[i] == nullptr) throw Error("marginalization: null parameter block in a term");
    for (std::size_t j = 0; j < i; ++j) {
      if (term.blocks[i] == term.blocks[j]) throw Error("marginalization: a block appears twice in one term");
    }
  }
  for (const int index : term.marginalize) {
    if (index < 0 || index >= static_cast<int>(term.blocks.size())) {
      throw Error("marginalization: marginalized index " + std::to_string(index) + " out of range");
    }
  }
  terms_.push_back(std::move(term));
}

MarginalizationPrior Marginalizer::marginalize() const {
  // 1. The blocks, their kinds and sizes, and which ones leave.
  static const PoseManifold pose_manifold;
  std::vector<BlockInfo> infos;
  std::unordered_map<const double*, int> index;
  for (const MarginalizationTerm& term : terms_) {
    const auto& sizes = term.cost->parameter_block_sizes();
    for (std::size_t i = 0; i < term.blocks.size(); ++i) {
      double* block = term.blocks[i];
      const auto [it, inserted] = index.emplace(block, static_cast<int>(infos.size()));
      if (inserted) {
        BlockInfo info;
        info.address = block;
        const auto kind = kinds_.find(block);
        info.kind = kind == kinds_.end() ? BlockKind::kEuclidean : kind->second;
        info.ambient = sizes[i];
        info.tangent = tangent_size(info.kind, info.ambient);
        info.constant = constant_.count(block) > 0;
        if (info.kind == BlockKind::kPose) pose_manifold.PlusJacobian(block, info.plus_jacobian.data());
        infos.push_back(info);
      } else if (infos[it->second].ambient != sizes[i]) {
        throw Error("marginalization: a block has size " + std::to_string(infos[it->second].ambient) +
                    " in one term and " + std::to_string(sizes[i]) + " in another");
      }
    }
    for (const int m : term.marginalize) infos[index.at(term.blocks[m])].marginalized = true;
  }
  int marginal_size = 0;
  int kept_size = 0;
  for (const BlockInfo& info : infos) {
    if (info.constant && info.marginalized) throw Error("marginalization: a constant block is marked to marginalize");
    if (info.constant) continue;
    (info.marginalized ? marginal_size : kept_size) += info.tangent;
  }
  // Leaving blocks that share no term with each other (the landmarks) are eliminated one by one
  // on the few columns they touch before the dense rest; they come first in H.
  std::vector<std::vector<int>> neighbours(infos.size());
  for (const MarginalizationTerm& term : terms_)
    for (const double* a : term.blocks)
      for (const double* c : term.blocks) {
        const int ia = index.at(a), ic = index.at(c);
        if (ia != ic && infos[ia].marginalized && !infos[ic].constant) neighbours[ia].push_back(ic);
      }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<int> order;  // leaving blocks, smallest first: landmarks before the states they share terms with
  for (std::size_t i = 0; i < infos.size(); ++i)
    if (infos[i].marginalized) order.push_back(static_cast<int>(i));
  std::stable_sort(order.begin(), order.end(), [&](int a, int c) { return infos[a].tangent < infos[c].tangent; });
  std::vector<char> independent(infos.size(), 0);
  std::vector<int> eliminated_first;
  for (const int i : order) {
    const bool free = std::none_of(neighbours[i].begin(), neighbours[i].end(), [&](int j) { return independent[j]; });
    if (!free) continue;
    independent[i] = 1;
    eliminated_first.push_back(i);
  }
  int next_first = 0;
  for (const int i : eliminated_first) {
    infos[i].offset = next_first;
    next_first += infos[i].tangent;
  }
  const int first_size = next_first;
  int next_marginal = first_size;
  int next_kept = marginal_size;
  for (std::size_t i = 0; i < infos.size(); ++i) {
    BlockInfo& info = infos[i];
    if (info.constant || independent[i]) continue;
    int& next = info.marginalized ? next_marginal : next_kept;
    info.offset = next;
    next += info.tangent;
  }
  const int n = marginal_size + kept_size;

  // 2. Linearize every term in the tangent spaces and accumulate H = J^T J, b = J^T r: the
  //    blocks eliminated first keep their own rows (their diagonal block and one block per
  //    neighbour; no two of them share a term), the rest of H is dense. A window's leaving
  //    landmarks make H mostly those rows (n ~ 500, rest ~ 80), which a dense n x n would hold
  //    as 2 MB of mostly zeros.
  const int rest_n = n - first_size;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(rest_n, rest_n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(rest_n);
  struct FirstRows {
    Eigen::MatrixXd H_ii;
    Eigen::VectorXd b_i;
    std::vector<Eigen::MatrixXd> H_ia;  // one per neighbour, in neighbours[i]'s order
  };
  std::vector<int> first_slot(infos.size(), -1);
  std::vector<FirstRows> first_rows(eliminated_first.size());
  for (std::size_t k = 0; k < eliminated_first.size(); ++k) {
    const int i = eliminated_first[k];
    first_slot[i] = static_cast<int>(k);
    FirstRows& f = first_rows[k];
    f.H_ii = Eigen::MatrixXd::Zero(infos[i].tangent, infos[i].tangent);
    f.b_i = Eigen::VectorXd::Zero(infos[i].tangent);
    for (const int a : neighbours[i]) f.H_ia.push_back(Eigen::MatrixXd::Zero(infos[i].tangent, infos[a].tangent));
  }
  std::vector<RowMajorMatrix> ambient;
  std::vector<double*> jacobian_pointers;
  std::vector<const double*> parameters;
  std::vector<int> term_blocks;   // info index per block of the term
  std::vector<int> term_columns;  // column in the term's tangent Jacobian per block
  Eigen::MatrixXd JtJ;
  Eigen::VectorXd Jtr;
  for (const MarginalizationTerm& term : terms_) {
    const int rows = term.cost->num_residuals();
    const std::size_t count = term.blocks.size();
    ambient.resize(count);
    jacobian_pointers.assign(count, nullptr);
    parameters.assign(term.blocks.begin(), term.blocks.end());
    term_blocks.resize(count);
    term_columns.resize(count);
    int columns = 0;
    for (std::size_t i = 0; i < count; ++i) {
      term_blocks[i] = index.at(term.blocks[i]);
      const BlockInfo& info = infos[term_blocks[i]];
      term_columns[i] = columns;
      if (info.constant) continue;
      columns += info.tangent;
      ambient[i].resize(rows, info.ambient);
      jacobian_pointers[i] = ambient[i].data();
    }
    Eigen::VectorXd r(rows);
    if (!term.cost->Evaluate(parameters.data(), r.data(), jacobian_pointers.data())) {
      throw Error("marginalization: a factor failed to evaluate at the current estimate");
    }
    Eigen::MatrixXd J(rows, columns);
    for (std::size_t i = 0; i < count; ++i) {
      const BlockInfo& info = infos[term_blocks[i]];
      if (info.constant) continue;
      if (!all_finite(ambient[i].data(), static_cast<int>(ambient[i].size()))) {
        throw Error("marginalization: a factor returned a non-finite Jacobian");
      }
      if (info.kind == BlockKind::kPose) {
        J.middleCols(term_columns[i], info.tangent) = ambient[i] * info.plus_jacobian;
      } else {
        J.middleCols(term_columns[i], info.tangent) = ambient[i];
      }
    }
    if (!all_finite(r.data(), rows)) throw Error("marginalization: a factor returned a non-finite residual");
    if (term.loss) apply_loss(*term.loss, r, J);

    JtJ.noalias() = J.transpose() * J;
    Jtr.noalias() = J.transpose() * r;
    for (std::size_t i = 0; i < count; ++i) {
      const BlockInfo& bi = infos[term_blocks[i]];
      if (bi.constant) continue;
      const int slot = first_slot[term_blocks[i]];
      if (slot >= 0) {
        FirstRows& f = first_rows[slot];
        f.b_i += Jtr.segment(term_columns[i], bi.tangent);
        const std::vector<int>& around = neighbours[term_blocks[i]];
        for (std::size_t j = 0; j < count; ++j) {
          const BlockInfo& bj = infos[term_blocks[j]];
          if (bj.constant) continue;
          const auto block = JtJ.block(term_columns[i], term_columns[j], bi.tangent, bj.tangent);
          if (j == i) {
            f.H_ii += block;
          } else {
            const auto at = std::lower_bound(around.begin(), around.end(), term_blocks[j]);
            f.H_ia[static_cast<std::size_t>(at - around.begin())] += block;
          }
        }
        continue;
      }
      b.segment(bi.offset - first_size, bi.tangent) += Jtr.segment(term_columns[i], bi.tangent);
      for (std::size_t j = 0; j < count; ++j) {
        const BlockInfo& bj = infos[term_blocks[j]];
        if (bj.constant || first_slot[term_blocks[j]] >= 0) continue;  // held in that block's rows
        H.block(bi.offset - first_size, bj.offset - first_size, bi.tangent, bj.tangent) +=
            JtJ.block(term_columns[i], term_columns[j], bi.tangent, bj.tangent);
      }
    }
  }

  // 3. Schur complement with the pseudo-inverse H_mm^+ = R^+ R^+T (R^T R = H_mm):
  //    H* = H_kk - W^T W, b* = b_k - W^T R^+T b_m, W = R^+T H_mk.
  //    First each independent leaving block i on its neighbours' rows and columns (H_mm is block
  //    diagonal there, so this is the same complement, each block's pseudo-inverse its own), then
  //    the remaining leaving blocks densely.
  std::vector<Eigen::MatrixXd> W;  // R^+T H_i,a per neighbour a
  std::vector<int> offsets;
  for (std::size_t k = 0; k < eliminated_first.size(); ++k) {
    const std::vector<int>& around = neighbours[eliminated_first[k]];
    const FirstRows& f = first_rows[k];
    if (infos[eliminated_first[k]].tangent == 3 &&
        std::all_of(around.begin(), around.end(), [&](int a) { return infos[a].tangent == 6; })) {
      offsets.clear();
      for (const int a : around) offsets.push_back(infos[a].offset - first_size);
      if (eliminate_landmark_on_poses(f.H_ii, f.b_i, f.H_ia, offsets, options_, H, b)) continue;
    }
    const SquareRoot R(f.H_ii, options_);
    const Eigen::VectorXd w_b = R.solve_transpose(f.b_i);
    W.resize(around.size());
    for (std::size_t x = 0; x < around.size(); ++x) W[x] = R.solve_transpose(f.H_ia[x]);
    for (std::size_t x = 0; x < W.size(); ++x) {
      const BlockInfo& ba = infos[around[x]];
      b.segment(ba.offset - first_size, ba.tangent).noalias() -= W[x].transpose() * w_b;
      for (std::size_t y = 0; y < W.size(); ++y) {
        const BlockInfo& bc = infos[around[y]];
        H.block(ba.offset - first_size, bc.offset - first_size, ba.tangent, bc.tangent).noalias() -=
            W[x].transpose() * W[y];
      }
    }
  }
  const int rest_size = marginal_size - first_size;
  Eigen::MatrixXd H_star = H.bottomRightCorner(kept_size, kept_size);
  Eigen::VectorXd b_star = b.tail(kept_size);
  if (rest_size > 0 && kept_size > 0) {
    const SquareRoot R_mm(H.topLeftCorner(rest_size, rest_size), options_);
    const Eigen::MatrixXd W_rest = R_mm.solve_transpose(H.block(0, rest_size, rest_size, kept_size));
    H_star.noalias() -= W_rest.transpose() * W_rest;
    b_star.noalias() -= W_rest.transpose() * R_mm.solve_transpose(b.head(rest_size));
  }

  // 4. Square-root form of the prior: J = R, r = R^+T b* (R^T R = H*), so J^T r = b*.
  MarginalizationPrior prior;
  for (const BlockInfo& info : infos) {
    if (info.constant || info.marginalized) continue;
    prior.blocks.push_back(info.address);
    prior.kinds.push_back(info.kind);
    prior.ambient_sizes.push_back(info.ambient);
    prior.tangent_offsets.push_back(info.offset - marginal_size);
    prior.x0.emplace_back(info.address, info.address + info.ambient);
  }
  prior.J.resize(0, kept_size);
  prior.r.resize(0);
  if (kept_size > 0) {
    const SquareRoot R_kk(H_star, options_);
    prior.J = R_kk.factor();
    prior.r = R_kk.solve_transpose(b_star);
  }
  if (!all_finite(prior.J.data(), static_cast<int>(prior.J.size())) ||
      !all_finite(prior.r.data(), static_cast<int>(prior.r.size()))) {
    throw Error("marginalization: the prior is not finite");
  }
  return prior;
}

MarginalizationFactor::MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior)
    : prior_(std::move(prior)) {
  if (!prior_) throw Error("MarginalizationFactor: null prior");
  if (prior_->empty()) throw Error("MarginalizationFactor: the prior carries no information");
  const std::size_t count = prior_->blocks.size();
  if (prior_->kinds.size() != count || prior_->ambient_sizes.size() != count ||
      prior_->tangent_offsets.size() != count || prior_->x0.size() != count ||
      prior_->r.size() != prior_->J.rows()) {
    throw Error("MarginalizationFactor: inconsistent prior");
  }
  for (std::size_t i = 0; i < count; ++i) {
    const int tangent = tangent_size(prior_->kinds[i], prior_->ambient_sizes[i]);
    if (static_cast<int>(prior_->x0[i].size()) != prior_->ambient_sizes[i] ||
        prior_->tangent_offsets[i] + tangent > prior_->J.cols()) {
      throw Error("MarginalizationFactor: inconsistent prior");
    }
    mutable_parameter_block_sizes()->push_back(prior_->ambient_sizes[i]);
  }
  set_num_residuals(static_cast<int>(prior_->J.rows()));
}

bool MarginalizationFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const MarginalizationPrior& p = *prior_;
  const std::size_t count = p.blocks.size();
  const auto rows = p.J.rows();
  Eigen::VectorXd dx(p.J.cols());
  for (std::size_t i = 0; i < count; ++i) {
    if (p.kinds[i] == BlockKind::kPose && Eigen::Map<const Eigen::Vector4d>(parameters[i] + 3).squaredNorm() == 0.0) {
      return false;
    }
    block_minus(p.kinds[i], p.ambient_sizes[i], parameters[i], p.x0[i].data(), dx.data() + p.tangent_offsets[i]);
  }
  Eigen::Map<Eigen::VectorXd>(residuals, rows) = p.r + p.J * dx;
  if (jacobians == nullptr) return true;
  for (std::size_t i = 0; i < count; ++i) {
    if (jacobians[i] == nullptr) continue;
    Eigen::Map<RowMajorMatrix> jac(jacobians[i], rows, p.ambient_sizes[i]);
    const int offset = p.tangent_offsets[i];
    if (p.kinds[i] == BlockKind::kPose) {
      jac = p.J.middleCols<kPoseTangentSize>(offset) * pose_minus_jacobian(parameters[i], p.x0[i].data());
    } else {
      jac = p.J.middleCols(offset, p.ambient_sizes[i]);
    }
  }
  return true;
}

}  // namespace navaid::estimation
