// The newest state's marginal covariance from the window's information (docs/estimator.md,
// "Covariance").
#include <algorithm>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include "impl.hpp"
#include "inlier_gate.hpp"

namespace navaid::estimation {

std::optional<NewestCovariance> SlidingWindowEstimator::Impl::newest_covariance(ceres::Problem& problem) {
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
    // ceres::Covariance does): Schur-complement the inverse depths (a diagonal block), then the
    // newest state's block of the inverse. Columns: T_ENU_W when present, the magnetometer's psi
    // when present, the online extrinsic, the states oldest first (the newest last), then every
    // free inverse depth; blocks left out of the list are held constant by Evaluate.
    ceres::Problem::EvaluateOptions eo;
    int state_cols = 0;
    // Blocks estimated with the states (T_ENU_W first: its columns are read back below). psi and
    // the online calibration correlate with every state: columns of their own, not held constant.
    std::vector<std::pair<double*, int>> extra;
    if (with_enu) extra.emplace_back(enu_alignment, kEnuAlignmentSize);
    if (problem.HasParameterBlock(mag_alignment)) extra.emplace_back(mag_alignment, kEnuAlignmentSize);
    if (!problem.IsParameterBlockConstant(extrinsic)) extra.emplace_back(extrinsic, kPoseTangentSize);
    if (problem.HasParameterBlock(time_offset)) extra.emplace_back(time_offset, 1);
    for (const auto& w : window)
      if (problem.HasParameterBlock(w->gps_bias)) extra.emplace_back(w->gps_bias, 3);
    for (const auto& [block, size] : extra) {
      eo.parameter_blocks.push_back(block);
      state_cols += size;
    }
    for (const auto& w : window) {
      eo.parameter_blocks.push_back(w->pose);
      state_cols += kPoseTangentSize;
      if (!problem.IsParameterBlockConstant(w->speed_bias)) {
        eo.parameter_blocks.push_back(w->speed_bias);
        state_cols += kSpeedBiasSize;
      }
    }
    // Landmarks (inverse depths, or [bearing, inverse depth]) in track order: Ceres lists its
    // blocks by address, which would make the sums below (and so the covariance's last bits)
    // depend on where the allocator put the tracks.
    const int landmark_size = landmark_block_size();
    for (auto& [id, track] : tracks.tracks()) {
      double* landmark = landmark_block(track);
      if (problem.HasParameterBlock(landmark) && !problem.IsParameterBlockConstant(landmark))
        eo.parameter_blocks.push_back(landmark);
    }
    ceres::CRSMatrix crs;
    if (!problem.Evaluate(eo, nullptr, nullptr, nullptr, &crs)) return std::nullopt;
    // J = [J_s | J_l] (states | landmarks), column-major so that column blocks are cheap. The
    // information is H = J^T J; the landmarks' block H_ll is block diagonal (one landmark per
    // block) and a landmark touches only the poses of the keyframes that see it, so the Schur
    // complement S = H_ss - H_sl H_ll^-1 H_ls is accumulated landmark by landmark on those rows.
    const Eigen::SparseMatrix<double> J = Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor, int>>(
        crs.num_rows, crs.num_cols, static_cast<int>(crs.values.size()), crs.rows.data(), crs.cols.data(),
        crs.values.data());
    const int nl = crs.num_cols - state_cols;
    const Eigen::SparseMatrix<double> J_s = J.leftCols(state_cols);
    Eigen::MatrixXd S = Eigen::MatrixXd(J_s.transpose() * J_s);
    if (nl > 0) {
      const Eigen::SparseMatrix<double> J_l = J.rightCols(nl);
      const Eigen::SparseMatrix<double> H_sl = J_s.transpose() * J_l;
      std::vector<int> rows;
      for (int k = 0; k < nl; k += landmark_size) {
        Eigen::MatrixXd H_ll(landmark_size, landmark_size);
        for (int a = 0; a < landmark_size; ++a)
          for (int b = 0; b <= a; ++b) H_ll(a, b) = H_ll(b, a) = J_l.col(k + a).dot(J_l.col(k + b));
        const Eigen::LDLT<Eigen::MatrixXd> ldlt(H_ll);
        // An unobserved landmark carries no information.
        if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12)) continue;
        rows.clear();
        for (int a = 0; a < landmark_size; ++a)
          for (Eigen::SparseMatrix<double>::InnerIterator it(H_sl, k + a); it; ++it) rows.push_back(it.row());
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        Eigen::MatrixXd B = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), landmark_size);
        for (int a = 0; a < landmark_size; ++a)
          for (Eigen::SparseMatrix<double>::InnerIterator it(H_sl, k + a); it; ++it)
            B(std::lower_bound(rows.begin(), rows.end(), it.row()) - rows.begin(), a) = it.value();
        const Eigen::MatrixXd D = B * ldlt.solve(B.transpose());
        for (std::size_t i = 0; i < rows.size(); ++i)
          for (std::size_t j = 0; j < rows.size(); ++j)
            S(rows[i], rows[j]) -= D(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      }
    }
    const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (S + S.transpose()));
    if (llt.info() != Eigen::Success) return std::nullopt;
    // The newest state's columns are the last ones: its pose, and its speed-bias unless constant.
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
