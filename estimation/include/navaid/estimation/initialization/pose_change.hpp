#pragma once
// Pose-change estimation (PCE) between two frames of the initialization window, W-ROMA RGBD-VIO
// (../shared/seeds/w-roma-rgbd-vio-object-manipulation.txt, §V-A, eq. 1-3) and its baseline.
//
//   kHybrid (HPnP): rotation R_ji from ALL correspondences (with and without depth) by the 2D-2D
//     method (cv::findEssentialMat, RANSAC on normalized coordinates, + cv::recoverPose, then the
//     Sampson error of the inliers minimized over (R, unit t) with Ceres, since OpenCV's RANSAC
//     returns a 5-point minimal model; the translation direction is discarded). A rotation-only
//     model (2-point RANSAC on bearings, Kabsch refit) is fitted too and chosen by Torr's GRIC
//     (pure rotation or all points far, where the essential matrix is degenerate). Then t_ji
//     from the features WITH depth, P_k^i = Z_i [m_i; 1]:
//       eq. 1  Z_j m_j = R_ji P_i + t_ji  ->  eq. 3  r_k = A_k t - b_k,
//              A_k = [1 0 -u_j; 0 1 -v_j],  b_k = [(u_j R3 - R1) P_i; (v_j R3 - R2) P_i]
//     (eq. 2 with the 3D point in place of p_i, as eq. 1 needs). Eq. 3 is linear in t: closed-form
//     least squares inside a 2-point RANSAC over all depth features (their inliers judged by
//     reprojection under (R, t): the epipolar test hangs on the discarded translation direction
//     and cannot see a wrong depth), then Levenberg-Marquardt (Ceres) from the closed form with a
//     Huber loss per feature scaled so that it switches at the pixel threshold, then the depth
//     inliers re-checked by reprojection. Needs >= 2 depth inliers (each gives 2 equations for 3
//     unknowns).
//   kPnp (VINS-RGBD's 3D-2D PnP): cv::solvePnPRansac on the depth features (P_i, m_j), flag
//     SOLVEPNP_ITERATIVE: OpenCV samples 5-point EPnP models in RANSAC (P3P when exactly 4
//     points) and refines the inliers by Levenberg-Marquardt. OpenCV asserts >= 4 points; we
//     return nullopt below max(4, min_depth_inliers).
// Thresholds are in pixels at focal_px; RANSAC is deterministic (OpenCV's registrator uses a fixed
// seed; our own RANSACs use `seed`). Details: docs/initialization.md.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/geometry.hpp"

namespace navaid::estimation {

using Vec2 = Eigen::Vector2d;

/// One feature seen in frames i and j: normalized image coordinates (undistorted, z = 1) and, when
/// the RGB-D camera measured it, the depth Z_i of the feature in frame i [m].
struct PoseChangeCorrespondence {
  Vec2 m_i = Vec2::Zero();
  Vec2 m_j = Vec2::Zero();
  std::optional<double> depth_i;
};

enum class PoseChangeMethod {
  kHybrid,  ///< HPnP, paper §V-A
  kPnp,     ///< 3D-2D PnP, VINS-RGBD
};

struct PoseChangeOptions {
  double focal_px = 460;             ///< to express thresholds in pixels, > 0
  double ransac_threshold_px = 1.0;  ///< 2D-2D (Sampson) and reprojection inlier threshold, > 0
  /// Reprojection threshold of depth features (HPnP's translation, PnP's RANSAC) when > 0; 0: the
  /// ransac_threshold_px. A depth error dZ moves the reprojection by ~ (dZ / Z) x the parallax the
  /// translation causes, so noisy RGB-D depth may call for more than the 2D threshold.
  double depth_threshold_px = 0.0;
  double ransac_confidence = 0.99;   ///< in (0, 1)
  int ransac_max_iterations = 1000;  ///< per RANSAC, >= 1
  /// Depth inliers required: the effective minimum is max(this, 2) for HPnP (eq. 3 gives 2
  /// equations per feature, t has 3 unknowns) and max(this, 4) for PnP (OpenCV's solvePnPRansac).
  int min_depth_inliers = 2;
  /// Correspondences (with or without depth) required by HPnP's 2D-2D step, >= 5 (5-point solver).
  int min_correspondences = 8;
  /// HPnP: image noise sigma assumed by the model selection between the essential and the
  /// rotation-only model (Torr's GRIC), > 0.
  double noise_sigma_px = 0.5;
  /// HPnP: the essential matrix by OpenCV's USAC_ACCURATE (GC-RANSAC with local optimization)
  /// instead of plain RANSAC (the paper's 2D-2D method); fewer wrong rotations in the HPnP-vs-PnP
  /// study (docs/initialization.md). Both are deterministic (fixed internal seeds).
  bool essential_usac = false;
  /// HPnP: Huber loss in the LM refinement of eq. 3 (false: plain least squares).
  bool robust_translation = true;
  /// HPnP: LM minimizes eq. 3 as printed (false; residual = Z_j x reprojection error on the
  /// normalized plane, so far points weigh more) or eq. 3 divided by Z_j = R3 P_i + t3, the
  /// reprojection error the paper's text names (true).
  bool reprojection_translation = false;
  std::uint64_t seed = 1;  ///< RANSAC determinism
};

/// Throws ConfigError naming the first bad option and its allowed range.
void validate(const PoseChangeOptions& options, const std::string& source = "pose_change");

struct PoseChange {
  SE3 T_j_i;                       ///< maps points of camera frame i into camera frame j (eq. 1)
  std::vector<char> inlier;        ///< per correspondence: consistent with T_j_i (see .cpp)
  std::vector<char> depth_inlier;  ///< per correspondence: has depth and reprojects within threshold
  int inliers = 0, depth_inliers = 0;
  bool rotation_only = false;      ///< HPnP chose the rotation-only model (no measurable parallax)
};

/// Throws navaid::Error on malformed input (non-finite values, non-positive depth) or options;
/// returns nullopt when the method fails (too few correspondences / depth inliers, degenerate
/// geometry), with the reason in *why when given.
std::optional<PoseChange> estimate_pose_change(const std::vector<PoseChangeCorrespondence>& c,
                                               PoseChangeMethod method,
                                               const PoseChangeOptions& options,
                                               std::string* why = nullptr);

std::string to_string(PoseChangeMethod method);

// --- eq. 3 building blocks (exposed for tests and for the window SfM) ---

/// One depth feature for eq. 3: the 3D point in frame i and its normalized coordinates in j.
struct TranslationObservation {
  Vec3 P_i = Vec3::Zero();
  Vec2 m_j = Vec2::Zero();
};

/// Closed-form least squares of eq. 3: t = (sum A^T A)^-1 sum A^T b. nullopt when fewer than 2
/// observations or the normal matrix is singular (e.g. identical m_j).
std::optional<Vec3> translation_least_squares(const Mat3& R_j_i,
                                              const std::vector<TranslationObservation>& obs);

/// sum_k rho(|A_k t - b_k|^2) by Levenberg-Marquardt (Ceres) from t0. huber_px > 0 puts a Huber
/// loss on each feature, switching where its reprojection error (residual / Z_j, times focal_px)
/// reaches huber_px; huber_px <= 0: plain least squares. reprojection: each residual divided by
/// Z_j = R3 P_i + t3 (the reprojection error on the normalized plane, nonlinear in t).
Vec3 translation_levenberg_marquardt(const Mat3& R_j_i,
                                     const std::vector<TranslationObservation>& obs,
                                     const Vec3& t0, double huber_px = 0.0,
                                     double focal_px = 460.0, bool reprojection = false);

}  // namespace navaid::estimation
