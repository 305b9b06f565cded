// The newest state's marginal covariance from the window's information (docs/estimator.md,
// "Covariance").
#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

#include <Eigen/Cholesky>

#include "impl.hpp"
#include "navaid/estimation/factors/landmark_factors.hpp"
#include "inlier_gate.hpp"

namespace navaid::estimation {

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using JMap = Eigen::Map<RowMajor>;
template <int Cols>
using FixedColsMap = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Cols, Eigen::RowMajor>>;

// dst += A^T B for the rows x ca and rows x cb row-major blocks at a and b: fixed-size kernels for
// the blocks of nearly every term (pose tangents of 6, landmarks of 3), generic otherwise.
template <typename Dst>
void add_At_B(Dst&& dst, const double* a, int ca, const double* b, int cb, int rows) {
  if (ca == 6 && cb == 6) {
    dst.template topLeftCorner<6, 6>() += FixedColsMap<6>(a, rows, 6).transpose().lazyProduct(FixedColsMap<6>(b, rows, 6));
  } else if (ca == 6 && cb == 3) {
    dst.template topLeftCorner<6, 3>() += FixedColsMap<6>(a, rows, 6).transpose().lazyProduct(FixedColsMap<3>(b, rows, 3));
  } else if (ca == 3 && cb == 3) {
    dst.template topLeftCorner<3, 3>() += FixedColsMap<3>(a, rows, 3).transpose().lazyProduct(FixedColsMap<3>(b, rows, 3));
  } else {
    const Eigen::Map<const RowMajor> A(a, rows, ca), B(b, rows, cb);
    dst.topLeftCorner(ca, cb) += A.transpose().lazyProduct(B);
  }
}

}  // namespace

std::optional<NewestCovariance> SlidingWindowEstimator::Impl::newest_covariance(ceres::Problem& problem,
                                                                             const std::vector<Residual>& residuals) {
  const WindowState& s = *window.back();
  const bool with_enu = problem.HasParameterBlock(enu_alignment);
  NewestCovariance out;
  Eigen::Matrix<double, 15, 15> C;  // Ceres tangent [dp, d, v, b_g, b_a]
  const sliding_window::GatedLoss gated(loss.get(), robust_loss.get(), cfg.covariance_weights == CovarianceWeights::kInliers);
  if (cfg.covariance_method == CovarianceMethod::kCeres) {
    if (problem.IsParameterBlockConstant(s.speed_bias)) return std::nullopt;
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::SPARSE_QR;
    co.num_threads = 1;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> pairs = {
        {s.pose, s.pose}, {s.pose, s.speed_bias}, {s.speed_bias, s.speed_bias}};
    if (with_enu) pairs.emplace_back(enu_alignment, enu_alignment);
    if (!covariance.Compute(pairs, &problem)) return std::nullopt;
    Eigen::Matrix<double, 15, 15, Eigen::RowMajor> Cr;
    if (!covariance.GetCovarianceMatrixInTangentSpace({s.pose, s.speed_bias}, Cr.data())) return std::nullopt;
    C = Cr;
    if (with_enu) {
      Eigen::Matrix<double, 4, 4, Eigen::RowMajor> A;
      if (!covariance.GetCovarianceBlock(enu_alignment, enu_alignment, A.data())) return std::nullopt;
      out.enu_alignment = A;
    }
  } else {
    // Same quantity from the Gauss-Newton information J^T J (robust losses applied, as
    // ceres::Covariance does), accumulated residual block by residual block in the tangent space:
    // the state blocks into a dense S (columns: T_ENU_W when present, the magnetometer's psi when
    // present, the online extrinsic, td, the GPS biases, the states oldest first, the newest
    // last), each landmark's own 3x3 (or 1x1) information and its blocks with the poses that see
    // it; then the landmarks are Schur-complemented out, S = H_ss - sum H_sl H_ll^-1 H_ls, one by
    // one on the poses they touch, in track order (deterministic), and the newest state's block
    // of S^-1 is read off.
    struct Column {
      int offset;
      int size;
    };
    std::unordered_map<const double*, Column> columns;
    int state_cols = 0;
    auto add_column = [&](const double* block, int size) {
      columns[block] = {state_cols, size};
      state_cols += size;
    };
    if (with_enu) add_column(enu_alignment, kEnuAlignmentSize);
    if (problem.HasParameterBlock(mag_alignment)) add_column(mag_alignment, kEnuAlignmentSize);
    if (!problem.IsParameterBlockConstant(extrinsic)) add_column(extrinsic, kPoseTangentSize);
    if (problem.HasParameterBlock(time_offset)) add_column(time_offset, 1);
    for (const auto& w : window)
      if (problem.HasParameterBlock(w->gps_bias)) add_column(w->gps_bias, 3);
    // Landmarks the prior holds are tied to each other through it: state columns, not eliminated.
    for (auto& [id, track] : tracks.tracks()) {
      double* landmark = landmark_block(track);
      if (in_marginal_prior(landmark) && problem.HasParameterBlock(landmark) &&
          !problem.IsParameterBlockConstant(landmark))
        add_column(landmark, kLandmarkSize);
    }
    for (const auto& w : window) {
      if (!problem.IsParameterBlockConstant(w->pose)) add_column(w->pose, kPoseTangentSize);
      if (!problem.IsParameterBlockConstant(w->speed_bias)) add_column(w->speed_bias, kSpeedBiasSize);
    }
    const int landmark_size = landmark_block_size();
    std::unordered_map<const double*, std::size_t> landmark_index;
    for (auto& [id, track] : tracks.tracks()) {
      double* landmark = landmark_block(track);
      if (problem.HasParameterBlock(landmark) && !problem.IsParameterBlockConstant(landmark) && !columns.count(landmark))
        landmark_index.emplace(landmark, landmark_index.size());
    }
    struct LandmarkInformation {
      Eigen::Matrix3d H_ll = Eigen::Matrix3d::Zero();
      std::vector<std::pair<int, Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 15, 3>>> H_sl;  // (state offset, block)
    };
    std::vector<LandmarkInformation> landmarks(landmark_index.size());
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(state_cols, state_cols);

    // Scratch reused across residual blocks (no allocation per block once grown).
    std::vector<double> r;
    std::vector<std::vector<double>> ambient, tangent;
    std::vector<int> tangent_cols, state_offset, state_size, landmark_of;
    std::vector<double*> jacobian_ptrs;
    // The pose blocks' d(ambient)/d(tangent), once per block.
    std::unordered_map<const double*, Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> plus;
    for (const auto& w : window)
      if (columns.count(w->pose)) pose_manifold->PlusJacobian(w->pose, plus[w->pose].data());
    if (columns.count(extrinsic)) pose_manifold->PlusJacobian(extrinsic, plus[extrinsic].data());
    for (const Residual& res : residuals) {
      const int rows = res.cost->num_residuals();
      const std::size_t nb = res.blocks.size();
      if (ambient.size() < nb) ambient.resize(nb), tangent.resize(nb);
      tangent_cols.assign(nb, 0);
      state_offset.assign(nb, -1);
      state_size.assign(nb, 0);
      landmark_of.assign(nb, -1);
      jacobian_ptrs.assign(nb, nullptr);
      bool any = false;
      for (std::size_t i = 0; i < nb; ++i) {
        const double* b = res.blocks[i];
        if (const auto c = columns.find(b); c != columns.end()) {
          state_offset[i] = c->second.offset;
          state_size[i] = c->second.size;
        } else if (const auto l = landmark_index.find(b); l != landmark_index.end()) {
          landmark_of[i] = static_cast<int>(l->second);
        } else {
          continue;  // held constant
        }
        ambient[i].resize(static_cast<std::size_t>(rows * res.cost->parameter_block_sizes()[i]));
        jacobian_ptrs[i] = ambient[i].data();
        any = true;
      }
      if (!any) continue;
      r.resize(static_cast<std::size_t>(rows));
      if (!res.cost->Evaluate(res.blocks.data(), r.data(), jacobian_ptrs.data())) return std::nullopt;
      // Ceres' robust-loss correction of the Jacobian (its Corrector: sqrt(rho') (I - alpha r r^T / |r|^2)).
      const Eigen::Map<const Eigen::VectorXd> rv(r.data(), rows);
      double scale = 1.0, alpha_sq = 0.0;
      if (res.loss) {
        const double sq = rv.squaredNorm();
        double rho[3];
        res.loss->Evaluate(sq, rho);
        scale = std::sqrt(std::max(rho[1], 0.0));
        if (sq > 0 && rho[2] > 0 && rho[1] > 0) alpha_sq = (1.0 - std::sqrt(1.0 + 2.0 * sq * rho[2] / rho[1])) / sq;
        if (scale == 0.0) continue;  // no weight: no information
      }
      for (std::size_t i = 0; i < nb; ++i) {
        if (!jacobian_ptrs[i]) continue;
        const int cols = res.cost->parameter_block_sizes()[i];
        JMap J(ambient[i].data(), rows, cols);
        if (alpha_sq != 0.0) J -= alpha_sq * rv * (rv.transpose() * J);
        J *= scale;
        const auto p = plus.find(res.blocks[i]);
        if (p != plus.end()) {
          tangent[i].resize(static_cast<std::size_t>(rows * kPoseTangentSize));
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, kPoseTangentSize, Eigen::RowMajor>>(tangent[i].data(), rows,
                                                                                          kPoseTangentSize)
              .noalias() = FixedColsMap<kPoseSize>(J.data(), rows, kPoseSize).lazyProduct(p->second);
          tangent_cols[i] = kPoseTangentSize;
        } else {
          tangent[i].swap(ambient[i]);
          tangent_cols[i] = cols;
        }
      }
      // Accumulate J_i^T J_j over the pairs of blocks (coefficient-wise products: the blocks are small).
      for (std::size_t i = 0; i < nb; ++i) {
        if (!jacobian_ptrs[i]) continue;
        const double* Ti = tangent[i].data();
        const int ci = tangent_cols[i];
        if (landmark_of[i] >= 0) {
          add_At_B(landmarks[static_cast<std::size_t>(landmark_of[i])].H_ll, Ti, ci, Ti, ci, rows);
          continue;
        }
        for (std::size_t j = 0; j < nb; ++j) {
          if (!jacobian_ptrs[j]) continue;
          const double* Tj = tangent[j].data();
          const int cj = tangent_cols[j];
          if (state_offset[j] >= 0) {
            add_At_B(S.block(state_offset[i], state_offset[j], ci, cj), Ti, ci, Tj, cj, rows);
            continue;
          }
          auto& blocks = landmarks[static_cast<std::size_t>(landmark_of[j])].H_sl;
          const int offset = state_offset[i];
          auto it = std::find_if(blocks.begin(), blocks.end(), [&](const auto& x) { return x.first == offset; });
          if (it == blocks.end()) {
            blocks.emplace_back(offset, Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 15, 3>::Zero(state_size[i], 3));
            it = std::prev(blocks.end());
          }
          add_At_B(it->second, Ti, ci, Tj, cj, rows);
        }
      }
    }
    // H_sl H_ll^-1 H_ls = W W^T with W = H_sl L^-T (H_ll = L L^T): each pair of blocks once, the
    // mirror block by transposition. A 1-dim landmark is padded to 3 (unit diagonal, zero columns).
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 15, 3>> W;
    for (LandmarkInformation& l : landmarks) {
      for (int k = landmark_size; k < 3; ++k) l.H_ll(k, k) = 1.0;
      const Eigen::LLT<Eigen::Matrix3d> llt(l.H_ll);
      // An unobserved landmark carries no information.
      if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().cwiseAbs2().minCoeff() > 1e-12)) continue;
      W.resize(l.H_sl.size());
      for (std::size_t a = 0; a < l.H_sl.size(); ++a)
        W[a] = llt.matrixL().solve(l.H_sl[a].second.transpose()).transpose();
      for (std::size_t a = 0; a < l.H_sl.size(); ++a) {
        const int oa = l.H_sl[a].first;
        for (std::size_t b = a; b < l.H_sl.size(); ++b) {
          const int ob = l.H_sl[b].first;
          if (W[a].rows() == 6 && W[b].rows() == 6) {
            const Eigen::Matrix<double, 6, 6> P = W[b].topRows<6>() * W[a].topRows<6>().transpose();
            S.block<6, 6>(ob, oa) -= P;
            if (a != b) S.block<6, 6>(oa, ob) -= P.transpose();
          } else {
            const Eigen::MatrixXd P = W[b] * W[a].transpose();
            S.block(ob, oa, P.rows(), P.cols()) -= P;
            if (a != b) S.block(oa, ob, P.cols(), P.rows()) -= P.transpose();
          }
        }
      }
    }
    const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (S + S.transpose()));
    if (llt.info() != Eigen::Success) return std::nullopt;
    // The newest state's columns are the last ones: its pose, and its speed-bias unless constant.
    if (!columns.count(s.pose)) return std::nullopt;
    const int newest = problem.IsParameterBlockConstant(s.speed_bias) ? kPoseTangentSize : 15;
    const int enu = with_enu ? kEnuAlignmentSize : 0;
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(state_cols, newest + enu);
    E.bottomLeftCorner(newest, newest).setIdentity();
    if (enu) E.topRightCorner(enu, enu).setIdentity();
    const Eigen::MatrixXd X = llt.solve(E);
    C.setZero();
    C.topLeftCorner(newest, newest) = X.bottomLeftCorner(newest, newest);
    // A constant speed-bias (IMU factors off) is not estimated: report it as unknown.
    if (newest < 15) C.bottomRightCorner<9, 9>() = Eigen::Matrix<double, 9, 9>::Identity() * kUnknownVariance;
    if (enu) out.enu_alignment = Mat4(X.topRightCorner(enu, enu));
  }
  // Ceres' tangent [dp, d, v, b_g, b_a], q (+) d = Exp(2 d) q, to StateEstimate's
  // [dtheta_right, dp, dv, db_g, db_a]: dtheta_right = 2 R^T d.
  Mat15 T = Mat15::Zero();
  T.block<3, 3>(0, 3) = 2.0 * s.T_W_B().rotation().transpose();
  T.block<3, 3>(3, 0).setIdentity();
  T.block<9, 9>(6, 6).setIdentity();
  Mat15 P = T * C * T.transpose();
  out.state = 0.5 * (P + P.transpose());
  if (!out.state.allFinite() || (out.enu_alignment && !out.enu_alignment->allFinite())) return std::nullopt;
  return out;
}

}  // namespace navaid::estimation
