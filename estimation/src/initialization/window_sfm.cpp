#include "navaid/estimation/initialization/window_sfm.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <unordered_map>

#include <Eigen/Cholesky>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "navaid/core/errors.hpp"
#include "navaid/core/number_text.hpp"
#include "opencv_pose.hpp"

namespace navaid::estimation {
namespace {

Vec3 homogeneous(const Vec2& m) { return Vec3(m.x(), m.y(), 1.0); }

// Point P_l in the camera of pose (q_l_C, p_l_C).
template <class T>
Eigen::Matrix<T, 3, 1> point_in_camera(const T* q, const T* p, const T* P) {
  const Eigen::Map<const Eigen::Quaternion<T>> q_l_C(q);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_l_C(p), P_l(P);
  return q_l_C.conjugate() * (P_l - p_l_C);
}

// Reprojection on the normalized plane of camera pose (q_l_C, p_l_C) and point P_l, whitened.
struct ReprojectionResidual {
  Vec2 m;
  double weight;
  template <class T>
  bool operator()(const T* q, const T* p, const T* P, T* r) const {
    const Eigen::Matrix<T, 3, 1> X = point_in_camera(q, p, P);
    r[0] = (X.x() / X.z() - m.x()) * weight;
    r[1] = (X.y() / X.z() - m.y()) * weight;
    return true;
  }
};

// W-ROMA's inverse-depth residual (1/Z - 1/Z_meas) / sigma_lambda of a measured depth.
struct InverseDepthResidual {
  double inverse_depth;
  double weight;
  template <class T>
  bool operator()(const T* q, const T* p, const T* P, T* r) const {
    const Eigen::Matrix<T, 3, 1> X = point_in_camera(q, p, P);
    r[0] = (T(1.0) / X.z() - inverse_depth) * weight;
    return true;
  }
};

struct Track {
  std::vector<std::pair<std::size_t, const SfmObservation*>> obs;  // (keyframe, observation)
  std::optional<Vec3> P_l;
  bool excluded = false;  // outlier of the reference pose change
};

class Solver {
 public:
  Solver(const std::vector<SfmKeyframe>& kfs, const WindowSfmOptions& o) : kfs_(kfs), o_(o), poses_(kfs.size()) {
    for (std::size_t k = 0; k < kfs.size(); ++k)
      for (const auto& ob : kfs[k].observations) {
        tracks_[ob.track_id].obs.emplace_back(k, &ob);
        has_depth_ = has_depth_ || ob.depth_m.has_value();
      }
  }

  WindowSfm run() {
    WindowSfm out;
    out.up_to_scale = !has_depth_;
    if (!choose_reference(&out)) return out;
    update_points();
    if (!register_keyframes(&out)) return out;
    bundle_adjust(&out);
    return out;
  }

 private:
  const SfmObservation* find(std::size_t k, std::uint64_t id) const {
    const auto it = tracks_.find(id);
    if (it == tracks_.end()) return nullptr;
    for (const auto& [kk, ob] : it->second.obs)
      if (kk == k) return ob;
    return nullptr;
  }

  // Step 1. Returns false with out->failure set when no keyframe qualifies: the reason of the
  // candidate that came furthest (common tracks < parallax < pose change), the oldest on ties.
  bool choose_reference(WindowSfm* out) {
    const std::size_t n = kfs_.size() - 1;
    std::string reason = "no keyframe shares tracks with the newest";
    int furthest = -1;
    auto reject = [&](int stage, const std::string& why) {
      if (stage > furthest) furthest = stage, reason = why;
    };
    for (std::size_t l = 0; l < n; ++l) {
      std::vector<std::uint64_t> ids;
      std::vector<PoseChangeCorrespondence> c;
      double parallax = 0;
      for (const auto& ob : kfs_[l].observations) {
        const SfmObservation* on = find(n, ob.track_id);
        if (!on) continue;
        ids.push_back(ob.track_id);
        c.push_back({ob.m, on->m, ob.depth_m});
        parallax += (ob.m - on->m).norm() * o_.focal_px;
      }
      const std::string prefix = "keyframe " + std::to_string(l) + " / newest: ";
      if (static_cast<int>(c.size()) < o_.min_common_features) {
        reject(0, prefix + std::to_string(c.size()) + " common tracks (need " + std::to_string(o_.min_common_features) + ")");
        continue;
      }
      parallax /= static_cast<double>(c.size());
      if (parallax < o_.min_parallax_px) {
        reject(1, prefix + "mean parallax " + number_text(parallax, 4) + " px (need " + number_text(o_.min_parallax_px, 4) + ")");
        continue;
      }
      std::string why;
      const std::optional<PoseChange> pc = has_depth_ ? pose_change_with_depth(c, &why) : pose_change_up_to_scale(c, &why);
      if (!pc) {
        reject(2, prefix + "pose change failed: " + why);
        continue;
      }
      // Outliers of the pose change are left out; 3D-2D PnP never judged the features without depth.
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const bool judged = !has_depth_ || o_.method != PoseChangeMethod::kPnp || c[i].depth_i;
        if (judged && !pc->inlier[i]) tracks_[ids[i]].excluded = true;
      }
      out->reference = l;
      out->reference_pose_change = *pc;
      poses_[l] = SE3::identity();
      poses_[n] = pc->T_j_i.inverse();
      return true;
    }
    out->failure = "no reference keyframe: " + reason;
    return false;
  }

  std::optional<PoseChange> pose_change_with_depth(const std::vector<PoseChangeCorrespondence>& c, std::string* why) {
    PoseChangeOptions po = o_.pose_change;
    po.focal_px = o_.focal_px;
    return estimate_pose_change(c, o_.method, po, why);
  }

  // Without any depth only the essential matrix is left: translation of unit length.
  std::optional<PoseChange> pose_change_up_to_scale(const std::vector<PoseChangeCorrespondence>& c, std::string* why) {
    std::vector<cv::Point2d> a, b;
    for (const auto& x : c) {
      a.emplace_back(x.m_i.x(), x.m_i.y());
      b.emplace_back(x.m_j.x(), x.m_j.y());
    }
    const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
    cv::Mat mask;
    const double thr = o_.pose_change.ransac_threshold_px / o_.focal_px;
    const cv::Mat E = cv::findEssentialMat(a, b, K, cv::RANSAC, o_.pose_change.ransac_confidence, thr, mask);
    if (E.rows != 3 || E.cols != 3) {
      *why = "no essential matrix";
      return std::nullopt;
    }
    cv::Mat R, t;
    if (mask.rows != static_cast<int>(c.size())) {
      *why = "essential matrix: no inlier mask";
      return std::nullopt;
    }
    const int good = cv::recoverPose(E, a, b, K, R, t, mask);
    if (good < o_.min_common_features / 2 + 1) {
      *why = "essential matrix: " + std::to_string(good) + " inliers in front of both cameras";
      return std::nullopt;
    }
    Mat3 Re;
    Vec3 te;
    cv::cv2eigen(R, Re);
    cv::cv2eigen(t, te);
    PoseChange pc;
    pc.T_j_i = SE3(Re, te.normalized());
    for (int i = 0; i < mask.rows; ++i) pc.inlier.push_back(mask.at<unsigned char>(i) != 0 ? 1 : 0);
    pc.depth_inlier = std::vector<char>(pc.inlier.size(), 0);
    pc.inliers = good;
    return pc;
  }

  // Reprojection error [px] of P_l in keyframe k.
  double reprojection_px(std::size_t k, const Vec3& P_l, const Vec2& m) const {
    const Vec3 X = poses_[k]->inverse() * P_l;
    if (!(X.z() > 0)) return std::numeric_limits<double>::infinity();
    return (X.head<2>() / X.z() - m).norm() * o_.focal_px;
  }

  // Step 2: every track without a point that the keyframes of known pose can place.
  void update_points() {
    const double max_err = 2.0 * o_.pnp_ransac_threshold_px;
    const double min_cos = std::cos(o_.min_triangulation_angle_deg * M_PI / 180.0);
    for (auto& [id, tr] : tracks_) {
      if (tr.P_l || tr.excluded) continue;
      std::vector<std::pair<std::size_t, const SfmObservation*>> known;
      for (const auto& o : tr.obs)
        if (poses_[o.first]) known.push_back(o);
      if (known.empty()) continue;
      std::optional<Vec3> P;
      // The nearest measured depth is the most precise one (sigma_Z grows with Z^2).
      const SfmObservation* best = nullptr;
      std::size_t best_k = 0;
      for (const auto& [k, ob] : known)
        if (ob->depth_m && (!best || *ob->depth_m < *best->depth_m)) best = ob, best_k = k;
      if (best) {
        P = *poses_[best_k] * (*best->depth_m * homogeneous(best->m));
      } else if (known.size() >= 2) {
        P = triangulate(known, min_cos);
      }
      if (!P) continue;
      bool consistent = true;
      for (const auto& [k, ob] : known) consistent = consistent && reprojection_px(k, *P, ob->m) <= max_err;
      if (consistent) tr.P_l = P;
    }
  }

  // Linear triangulation in l: m_k x (R_C_l P + t_C_l) = 0 for every keyframe k of known pose.
  std::optional<Vec3> triangulate(const std::vector<std::pair<std::size_t, const SfmObservation*>>& known,
                                  double min_cos) const {
    Mat3 A = Mat3::Zero();
    Vec3 b = Vec3::Zero();
    std::vector<Vec3> rays;
    for (const auto& [k, ob] : known) {
      const SE3 T_C_l = poses_[k]->inverse();
      const Mat3 M = hat(homogeneous(ob->m));
      const Mat3 MR = M * T_C_l.rotation();
      A += MR.transpose() * MR;
      b -= MR.transpose() * (M * T_C_l.t);
      rays.push_back(poses_[k]->q * homogeneous(ob->m).normalized());
    }
    double min_dot = 1.0;
    for (std::size_t i = 0; i < rays.size(); ++i)
      for (std::size_t j = i + 1; j < rays.size(); ++j) min_dot = std::min(min_dot, rays[i].dot(rays[j]));
    if (min_dot > min_cos) return std::nullopt;
    const Eigen::LDLT<Mat3> ldlt(A);
    if (ldlt.info() != Eigen::Success) return std::nullopt;
    const Vec3 P = ldlt.solve(b);
    if (!P.allFinite()) return std::nullopt;
    return P;
  }

  // Step 3.
  bool register_keyframes(WindowSfm* out) {
    while (true) {
      std::size_t best = kfs_.size();
      int best_count = -1;
      for (std::size_t k = 0; k < kfs_.size(); ++k) {
        if (poses_[k]) continue;
        int count = 0;
        for (const auto& ob : kfs_[k].observations)
          if (tracks_.at(ob.track_id).P_l) ++count;
        if (count > best_count) best = k, best_count = count;
      }
      if (best == kfs_.size()) return true;
      if (best_count < o_.min_pnp_points) {
        out->failure = "keyframe " + std::to_string(best) + " sees " + std::to_string(best_count) +
                       " points of known position (PnP needs " + std::to_string(o_.min_pnp_points) + ")";
        return false;
      }
      std::string why;
      if (!pnp(best, &why)) {
        out->failure = "PnP of keyframe " + std::to_string(best) + " failed: " + why;
        return false;
      }
      update_points();
    }
  }

  bool pnp(std::size_t k, std::string* why) {
    std::vector<cv::Point3d> P;
    std::vector<cv::Point2d> m;
    for (const auto& ob : kfs_[k].observations)
      if (const auto& X = tracks_.at(ob.track_id).P_l) {
        P.emplace_back(X->x(), X->y(), X->z());
        m.emplace_back(ob.m.x(), ob.m.y());
      }
    const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    const bool ok = cv::solvePnPRansac(P, m, K, cv::noArray(), rvec, tvec, false, 200,
                                       static_cast<float>(o_.pnp_ransac_threshold_px / o_.focal_px), 0.99, inliers,
                                       cv::SOLVEPNP_ITERATIVE);
    if (!ok || static_cast<int>(inliers.size()) < o_.min_pnp_points) {
      *why = std::to_string(inliers.size()) + " inliers of " + std::to_string(P.size()) + " points";
      return false;
    }
    const auto pose = pose_from_rodrigues(rvec, tvec);
    if (!pose) {
      *why = "non-finite pose";
      return false;
    }
    poses_[k] = SE3(pose->first, pose->second).inverse();
    return true;
  }

  // Reprojection errors [px] of every observation of a placed point seen twice or more (a single
  // view reprojects exactly by construction).
  std::vector<double> reprojection_errors() const {
    std::vector<double> e;
    for (const auto& [id, tr] : tracks_)
      if (tr.P_l && tr.obs.size() >= 2)
        for (const auto& [k, ob] : tr.obs) e.push_back(reprojection_px(k, *tr.P_l, ob->m));
    return e;
  }

  static double rms(const std::vector<double>& e) {
    double s = 0;
    for (double x : e) s += x * x;
    return e.empty() ? 0.0 : std::sqrt(s / static_cast<double>(e.size()));
  }

  // Step 4.
  void bundle_adjust(WindowSfm* out) {
    const std::size_t n = kfs_.size();
    std::vector<std::array<double, 4>> q(n);
    std::vector<std::array<double, 3>> p(n);
    for (std::size_t k = 0; k < n; ++k) {
      Eigen::Map<Eigen::Vector4d>(q[k].data()) = poses_[k]->q.coeffs();
      Eigen::Map<Vec3>(p[k].data()) = poses_[k]->t;
    }
    std::unordered_map<std::uint64_t, std::array<double, 3>> points;
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    ceres::EigenQuaternionManifold quaternion;
    ceres::CauchyLoss cauchy(o_.cauchy_scale);
    const double w_px = o_.focal_px / o_.pixel_sigma_px;
    const double w_depth = 1.0 / o_.inverse_depth_sigma;
    const std::vector<double> before = reprojection_errors();
    for (const auto& [id, tr] : tracks_) {
      if (!tr.P_l || tr.obs.size() < 2) continue;  // a single view constrains no pose
      auto& P = points[id];
      Eigen::Map<Vec3>(P.data()) = *tr.P_l;
      for (const auto& [k, ob] : tr.obs) {
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionResidual, 2, 4, 3, 3>(
                                     new ReprojectionResidual{ob->m, w_px}),
                                 &cauchy, q[k].data(), p[k].data(), P.data());
        ++out->reprojection_residuals;
        if (ob->depth_m) {
          problem.AddResidualBlock(new ceres::AutoDiffCostFunction<InverseDepthResidual, 1, 4, 3, 3>(
                                       new InverseDepthResidual{1.0 / *ob->depth_m, w_depth}),
                                   &cauchy, q[k].data(), p[k].data(), P.data());
          ++out->depth_residuals;
        }
      }
    }
    for (std::size_t k = 0; k < n; ++k)
      if (problem.HasParameterBlock(q[k].data())) problem.SetManifold(q[k].data(), &quaternion);
    const std::size_t l = out->reference;
    if (!problem.HasParameterBlock(q[l].data())) {
      out->failure = "bundle adjustment: the reference keyframe shares no point with the others";
      return;
    }
    problem.SetParameterBlockConstant(q[l].data());
    problem.SetParameterBlockConstant(p[l].data());
    if (out->depth_residuals == 0) {  // the scale gauge
      if (!problem.HasParameterBlock(p[n - 1].data())) {
        out->failure = "bundle adjustment: the newest keyframe shares no point with the others";
        return;
      }
      problem.SetParameterBlockConstant(p[n - 1].data());
    }

    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_SCHUR;
    so.max_num_iterations = o_.max_ba_iterations;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable()) {
      out->failure = "bundle adjustment failed: " + summary.message;
      return;
    }
    for (std::size_t k = 0; k < n; ++k) poses_[k] = SE3(Quat(q[k].data()), Vec3(p[k].data()));
    for (auto& [id, P] : points) tracks_[id].P_l = Vec3(P.data());

    std::vector<double> after = reprojection_errors();
    out->initial_rms_px = rms(before);
    out->final_rms_px = rms(after);
    std::nth_element(after.begin(), after.begin() + static_cast<long>(after.size() / 2), after.end());
    const double median = after.empty() ? 0.0 : after[after.size() / 2];
    if (!(median <= o_.max_median_error_px)) {
      out->failure = "bundle adjustment: median reprojection error " + number_text(median, 4) + " px (limit " +
                     number_text(o_.max_median_error_px, 4) + ")";
      return;
    }
    for (std::size_t k = 0; k < n; ++k) out->T_l_C.push_back(*poses_[k]);
    for (const auto& [id, tr] : tracks_) {
      if (!tr.P_l) continue;
      bool in_front = true;
      for (const auto& [k, ob] : tr.obs) in_front = in_front && (poses_[k]->inverse() * *tr.P_l).z() > 0;
      if (in_front) out->points_l.emplace(id, *tr.P_l);
    }
    out->success = true;
  }

  const std::vector<SfmKeyframe>& kfs_;
  const WindowSfmOptions& o_;
  std::vector<std::optional<SE3>> poses_;  // T_l_C, once known
  std::map<std::uint64_t, Track> tracks_;  // ordered: deterministic iteration
  bool has_depth_ = false;
};

void validate_input(const std::vector<SfmKeyframe>& kfs) {
  const std::string where = "window SfM: ";
  if (kfs.size() < 2) throw Error(where + std::to_string(kfs.size()) + " keyframes (need at least 2)");
  for (std::size_t k = 0; k < kfs.size(); ++k) {
    std::set<std::uint64_t> seen;
    for (const auto& ob : kfs[k].observations) {
      const std::string what = "keyframe " + std::to_string(k) + ", track " + std::to_string(ob.track_id) + ": ";
      if (!ob.m.allFinite()) throw Error(where + what + "non-finite coordinates");
      if (ob.depth_m && !(std::isfinite(*ob.depth_m) && *ob.depth_m > 0))
        throw Error(where + what + "depth " + number_text(*ob.depth_m, 4) + " is not a positive finite number");
      if (!seen.insert(ob.track_id).second) throw Error(where + what + "observed twice");
    }
  }
}

}  // namespace

void validate(const WindowSfmOptions& o, const std::string& source) {
  auto require = [&](bool ok, const char* key, const char* range) {
    if (!ok) throw ConfigError(source, key, std::string("must be ") + range);
  };
  require(o.focal_px > 0 && std::isfinite(o.focal_px), "focal_px", "> 0");
  require(o.min_common_features >= 5, "min_common_features", ">= 5");
  require(o.min_parallax_px >= 0, "min_parallax_px", ">= 0");
  require(o.min_triangulation_angle_deg >= 0 && o.min_triangulation_angle_deg < 90, "min_triangulation_angle_deg",
          "in [0, 90)");
  require(o.min_pnp_points >= 6, "min_pnp_points", ">= 6");
  require(o.pnp_ransac_threshold_px > 0, "pnp_ransac_threshold_px", "> 0");
  require(o.pixel_sigma_px > 0, "pixel_sigma_px", "> 0");
  require(o.inverse_depth_sigma > 0, "inverse_depth_sigma", "> 0");
  require(o.cauchy_scale > 0, "cauchy_scale", "> 0");
  require(o.max_ba_iterations >= 0, "max_ba_iterations", ">= 0");
  require(o.max_median_error_px > 0, "max_median_error_px", "> 0");
  PoseChangeOptions pc = o.pose_change;
  pc.focal_px = o.focal_px;
  validate(pc, source + ".pose_change");
}

WindowSfm solve_window_sfm(const std::vector<SfmKeyframe>& keyframes, const WindowSfmOptions& options) {
  validate(options);
  validate_input(keyframes);
  return Solver(keyframes, options).run();
}

}  // namespace navaid::estimation
