// HPnP and 3D-2D PnP pose-change estimation; equations and choices in pose_change.hpp and
// docs/initialization.md ("Pose change: HPnP and 3D-2D PnP").
#include "navaid/estimation/initialization/pose_change.hpp"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/core/number_text.hpp"
#include "opencv_pose.hpp"

namespace navaid::estimation {
namespace {

constexpr int kHybridMinDepth = 2;  // eq. 3: 2 equations per feature, 3 unknowns
constexpr int kPnpMinDepth = 4;     // cv::solvePnPRansac asserts >= 4 points
constexpr int kEssentialMinPoints = 5;
constexpr double kMinDepthJ = 1e-6;  // a point must stay in front of camera j [m]

std::optional<PoseChange> fail(std::string* why, const std::string& reason) {
  if (why) *why = reason;
  return std::nullopt;
}

void check_input(const std::vector<PoseChangeCorrespondence>& c) {
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!c[k].m_i.allFinite() || !c[k].m_j.allFinite())
      throw Error("pose change: correspondence " + std::to_string(k) + " has non-finite image coordinates");
    if (c[k].depth_i && !(std::isfinite(*c[k].depth_i) && *c[k].depth_i > 0.0))
      throw Error("pose change: correspondence " + std::to_string(k) + " has depth " + number_text(*c[k].depth_i) +
                  " m; expected a finite value > 0");
  }
}

Vec3 point_i(const PoseChangeCorrespondence& c) { return *c.depth_i * Vec3(c.m_i.x(), c.m_i.y(), 1.0); }

/// Reprojection error [px] of P_i in frame j, infinity when the point is behind camera j.
double reprojection_px(const Mat3& R, const Vec3& t, const Vec3& P_i, const Vec2& m_j, double focal_px) {
  const Vec3 X = R * P_i + t;
  if (!(X.z() > kMinDepthJ)) return std::numeric_limits<double>::infinity();
  return focal_px * (X.head<2>() / X.z() - m_j).norm();
}

/// Adaptive RANSAC iteration count for a sample of `sample` points and an inlier ratio.
int ransac_iterations(double inlier_ratio, int sample, double confidence, int max_iterations) {
  const double w = std::pow(std::clamp(inlier_ratio, 0.0, 1.0), sample);
  if (w >= 1.0 - 1e-12) return 1;
  if (w <= 0.0) return max_iterations;
  const double n = std::log(1.0 - confidence) / std::log(1.0 - w);
  return static_cast<int>(std::clamp(std::ceil(n), 1.0, static_cast<double>(max_iterations)));
}

// --- 2D-2D rotation models -------------------------------------------------------------------

struct RotationModel {
  Mat3 R = Mat3::Identity();
  std::vector<char> inlier;
  std::vector<double> error_px;  ///< geometric error of each correspondence under the model
  int inliers = 0;
  bool ok = false;
};

/// Sampson distance of x2^T E x1 = 0 on the normalized plane (first-order geometric error,
/// both images together), E = [t]x R.
template <typename T>
T sampson(const Eigen::Matrix<T, 3, 3>& E, const Eigen::Matrix<T, 3, 1>& x1, const Eigen::Matrix<T, 3, 1>& x2) {
  const Eigen::Matrix<T, 3, 1> Ex1 = E * x1;
  const Eigen::Matrix<T, 3, 1> Etx2 = E.transpose() * x2;
  const T den = Ex1(0) * Ex1(0) + Ex1(1) * Ex1(1) + Etx2(0) * Etx2(0) + Etx2(1) * Etx2(1);
  return x2.dot(Ex1) / ceres::sqrt(den + T(1e-30));
}

template <typename T>
Eigen::Matrix<T, 3, 3> essential(const Eigen::Quaternion<T>& q, const Eigen::Matrix<T, 3, 1>& t) {
  Eigen::Matrix<T, 3, 3> tx;
  tx << T(0), -t(2), t(1), t(2), T(0), -t(0), -t(1), t(0), T(0);
  return tx * q.toRotationMatrix();
}

struct SampsonCost {
  Vec3 x1, x2;
  template <typename T>
  bool operator()(const T* q, const T* t, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Q(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tt(t);
    r[0] = sampson<T>(essential<T>(Q, tt), x1.cast<T>(), x2.cast<T>());
    return true;
  }
};

Vec3 homogeneous(const Vec2& m) { return Vec3(m.x(), m.y(), 1.0); }

/// Sampson errors [px] of every correspondence and the inlier flags.
void score_essential(const std::vector<PoseChangeCorrespondence>& c, const Quat& q, const Vec3& t,
                     const PoseChangeOptions& o, RotationModel* m) {
  const Mat3 E = essential<double>(q, t);
  m->error_px.resize(c.size());
  m->inlier.assign(c.size(), 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    m->error_px[k] = std::abs(sampson<double>(E, homogeneous(c[k].m_i), homogeneous(c[k].m_j))) * o.focal_px;
    m->inlier[k] = m->error_px[k] < o.ransac_threshold_px;
  }
  m->inliers = static_cast<int>(std::count(m->inlier.begin(), m->inlier.end(), 1));
}

/// Essential matrix (OpenCV RANSAC, Sampson distance) + recoverPose, then (R, unit t) refined on
/// the inliers by minimizing the robust Sampson error.
RotationModel essential_rotation(const std::vector<PoseChangeCorrespondence>& c, const PoseChangeOptions& o) {
  RotationModel m;
  if (static_cast<int>(c.size()) < kEssentialMinPoints) return m;
  std::vector<cv::Point2d> p1, p2;
  p1.reserve(c.size());
  p2.reserve(c.size());
  for (const auto& x : c) {
    p1.emplace_back(x.m_i.x(), x.m_i.y());
    p2.emplace_back(x.m_j.x(), x.m_j.y());
  }
  const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  const double thr = o.ransac_threshold_px / o.focal_px;
  cv::Mat mask, E, Rcv, tcv;
  try {
    E = cv::findEssentialMat(p1, p2, K, o.essential_usac ? cv::USAC_ACCURATE : cv::RANSAC, o.ransac_confidence, thr, o.ransac_max_iterations, mask);
    if (E.rows < 3 || E.cols != 3 || mask.empty()) return m;
    // recoverPose picks among the four (R, t) decompositions by triangulating in front of both
    // cameras; the distance cut is in baselines and far points must still count.
    cv::Mat cheirality = mask.clone();
    if (cv::recoverPose(E.rowRange(0, 3), p1, p2, K, Rcv, tcv, 1e6, cheirality) <= 0) return m;
  } catch (const cv::Exception&) {
    return m;  // degenerate sample sets
  }
  Mat3 R;
  Vec3 t;
  cv::cv2eigen(Rcv, R);
  cv::cv2eigen(tcv, t);
  Quat q(R);
  q.normalize();
  t.normalize();

  ceres::Problem problem;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!mask.at<unsigned char>(static_cast<int>(k))) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SampsonCost, 1, 4, 3>(
                                 new SampsonCost{homogeneous(c[k].m_i), homogeneous(c[k].m_j)}),
                             new ceres::HuberLoss(thr), q.coeffs().data(), t.data());
  }
  if (problem.NumResidualBlocks() >= kEssentialMinPoints) {
    problem.SetManifold(q.coeffs().data(), new ceres::EigenQuaternionManifold);
    problem.SetManifold(t.data(), new ceres::SphereManifold<3>);
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 20;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
  }
  q.normalize();
  m.R = q.toRotationMatrix();
  score_essential(c, q, t.normalized(), o, &m);
  m.ok = m.inliers >= kEssentialMinPoints;
  return m;
}

Vec3 bearing(const Vec2& m) { return homogeneous(m).normalized(); }

/// Least-squares rotation b_j ~ R b_i (Kabsch on unit bearings).
Mat3 kabsch(const std::vector<Vec3>& bi, const std::vector<Vec3>& bj, const std::vector<int>& idx) {
  Mat3 H = Mat3::Zero();
  for (int k : idx) H += bi[k] * bj[k].transpose();
  Eigen::JacobiSVD<Mat3> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixV() * D * svd.matrixU().transpose();
}

/// Geometric error [px] of the infinite homography R: the transfer error of m_i into frame j
/// over sqrt 2, as the correction is shared by both images (comparable with Sampson's).
double rotation_error_px(const Mat3& R, const Vec3& b_i, const Vec2& m_j, double focal_px) {
  const Vec3 x = R * b_i;
  if (!(x.z() > 1e-9)) return std::numeric_limits<double>::infinity();
  return focal_px * (x.head<2>() / x.z() - m_j).norm() / std::sqrt(2.0);
}

/// Rotation-only model (pure rotation or all points far): 2-point RANSAC, refit on the inliers.
/// The essential matrix is degenerate there (any [t]x R fits), so its rotation is unreliable.
RotationModel rotation_only(const std::vector<PoseChangeCorrespondence>& c, const PoseChangeOptions& o,
                            std::mt19937_64& rng) {
  RotationModel m;
  const int n = static_cast<int>(c.size());
  if (n < 2) return m;
  std::vector<Vec3> bi(c.size()), bj(c.size());
  for (int k = 0; k < n; ++k) {
    bi[k] = bearing(c[k].m_i);
    bj[k] = bearing(c[k].m_j);
  }
  const double thr = o.ransac_threshold_px;
  auto score = [&](const Mat3& R, std::vector<int>* inl) {
    double cost = 0;
    if (inl) inl->clear();
    for (int k = 0; k < n; ++k) {
      const double e = rotation_error_px(R, bi[k], c[k].m_j, o.focal_px);
      cost += std::min(e * e, thr * thr);  // MSAC
      if (inl && e < thr) inl->push_back(k);
    }
    return cost;
  };
  std::uniform_int_distribution<int> pick(0, n - 1);
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<int> best_inl, inl;
  int needed = o.ransac_max_iterations;
  for (int it = 0; it < needed; ++it) {
    const int a = pick(rng);
    int b = pick(rng);
    if (a == b) b = (b + 1) % n;
    if (bi[a].cross(bi[b]).norm() < 1e-9) continue;  // same bearing: rotation about it is free
    const Mat3 R = kabsch(bi, bj, {a, b});
    const double cost = score(R, &inl);
    if (cost < best_cost) {
      best_cost = cost;
      best_inl = inl;
      needed = std::min(needed, ransac_iterations(static_cast<double>(inl.size()) / n, 2, o.ransac_confidence,
                                                  o.ransac_max_iterations));
    }
  }
  if (best_inl.size() < 2) return m;
  // Refit on the inliers until the set settles (a few rounds at most).
  for (int round = 0; round < 5; ++round) {
    m.R = kabsch(bi, bj, best_inl);
    score(m.R, &inl);
    if (inl == best_inl || inl.size() < 2) break;
    best_inl = inl;
  }
  m.error_px.resize(c.size());
  m.inlier.assign(c.size(), 0);
  for (int k = 0; k < n; ++k) {
    m.error_px[k] = rotation_error_px(m.R, bi[k], c[k].m_j, o.focal_px);
    m.inlier[k] = m.error_px[k] < thr;
  }
  m.inliers = static_cast<int>(std::count(m.inlier.begin(), m.inlier.end(), 1));
  m.ok = m.inliers >= kEssentialMinPoints;
  return m;
}

/// Torr's geometric robust information criterion for a model of manifold dimension d with k
/// parameters on n two-view correspondences (data dimension r = 4); lower is better.
double gric(const RotationModel& m, int d, int k, double sigma_px) {
  const double r = 4.0, n = static_cast<double>(m.error_px.size());
  double g = 0;
  for (double e : m.error_px) g += std::min(e * e / (sigma_px * sigma_px), 2.0 * (r - d));
  return g + std::log(r) * d * n + std::log(r * n) * k;
}

// --- eq. 3 ------------------------------------------------------------------------------------

/// A_k and b_k of eq. 3.
void eq3(const Mat3& R, const TranslationObservation& o, Eigen::Matrix<double, 2, 3>* A, Vec2* b) {
  const double u = o.m_j.x(), v = o.m_j.y();
  *A << 1, 0, -u, 0, 1, -v;
  *b << (u * R.row(2) - R.row(0)).dot(o.P_i), (v * R.row(2) - R.row(1)).dot(o.P_i);
}

class Eq3Cost : public ceres::SizedCostFunction<2, 3> {
 public:
  Eq3Cost(const Mat3& R, const TranslationObservation& o, bool reprojection)
      : Rp_z_(R.row(2).dot(o.P_i)), reprojection_(reprojection) {
    eq3(R, o, &A_, &b_);
  }
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    const Eigen::Map<const Vec3> t(p[0]);
    Eigen::Map<Vec2> residual(r);
    residual = A_ * t - b_;
    Eigen::Matrix<double, 2, 3> dr = A_;
    if (reprojection_) {
      // (A t - b) / z with z = R3 P + t3: the normalized-plane reprojection error.
      const double z = Rp_z_ + t.z();
      if (!(z > kMinDepthJ)) return false;  // behind camera j: LM shrinks the step
      dr = A_ / z;
      dr.col(2) -= residual / (z * z);
      residual /= z;
    }
    if (J && J[0]) {
      Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> jacobian(J[0]);
      jacobian = dr;
    }
    return true;
  }

 private:
  Eigen::Matrix<double, 2, 3> A_;
  Vec2 b_;
  double Rp_z_;
  bool reprojection_;
};

/// Depth inliers of (R, t) among `candidates` (indices into c) by reprojection.
double depth_threshold(const PoseChangeOptions& o) {
  return o.depth_threshold_px > 0.0 ? o.depth_threshold_px : o.ransac_threshold_px;
}

std::vector<int> depth_inliers(const std::vector<PoseChangeCorrespondence>& c, const std::vector<int>& candidates,
                               const Mat3& R, const Vec3& t, const PoseChangeOptions& o, double* msac = nullptr) {
  std::vector<int> in;
  double cost = 0;
  const double thr = depth_threshold(o);
  for (int k : candidates) {
    const double e = reprojection_px(R, t, point_i(c[k]), c[k].m_j, o.focal_px);
    cost += std::min(e * e, thr * thr);
    if (e < thr) in.push_back(k);
  }
  if (msac) *msac = cost;
  return in;
}

std::vector<TranslationObservation> observations(const std::vector<PoseChangeCorrespondence>& c,
                                                 const std::vector<int>& idx) {
  std::vector<TranslationObservation> obs;
  obs.reserve(idx.size());
  for (int k : idx) obs.push_back({point_i(c[k]), c[k].m_j});
  return obs;
}

/// HPnP translation: 2-point RANSAC on eq. 3 (all pairs when few), closed form on the inliers,
/// LM, re-check. Returns the depth inliers (empty on failure) and t.
std::vector<int> hybrid_translation(const std::vector<PoseChangeCorrespondence>& c, const std::vector<int>& cand,
                                    const Mat3& R, const PoseChangeOptions& o, std::mt19937_64& rng, Vec3* t_out) {
  const int n = static_cast<int>(cand.size());
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<int> best;
  auto try_pair = [&](int a, int b) {
    const auto t = translation_least_squares(R, observations(c, {cand[a], cand[b]}));
    if (!t) return;
    double cost = 0;
    auto in = depth_inliers(c, cand, R, *t, o, &cost);
    if (cost < best_cost) {
      best_cost = cost;
      best = std::move(in);
    }
  };
  const long pairs = static_cast<long>(n) * (n - 1) / 2;
  if (pairs <= o.ransac_max_iterations) {
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) try_pair(a, b);
  } else {
    std::uniform_int_distribution<int> pick(0, n - 1);
    int needed = o.ransac_max_iterations;
    for (int it = 0; it < needed; ++it) {
      const int a = pick(rng);
      int b = pick(rng);
      if (a == b) b = (b + 1) % n;
      const std::size_t before = best.size();
      try_pair(a, b);
      if (best.size() != before)
        needed = std::min(needed, ransac_iterations(static_cast<double>(best.size()) / n, 2, o.ransac_confidence,
                                                    o.ransac_max_iterations));
    }
  }
  if (best.size() < 2) return {};
  // Closed form on the inliers starts LM; the re-check may change the set, then solve once more.
  Vec3 t = Vec3::Zero();
  for (int round = 0; round < 2; ++round) {
    const auto obs = observations(c, best);
    const auto t0 = translation_least_squares(R, obs);
    if (!t0) return {};
    t = translation_levenberg_marquardt(R, obs, *t0, o.robust_translation ? depth_threshold(o) : 0.0, o.focal_px,
                                        o.reprojection_translation);
    auto in = depth_inliers(c, cand, R, t, o);
    if (in == best) break;
    if (in.size() < 2) return {};
    best = std::move(in);
  }
  best = depth_inliers(c, cand, R, t, o);
  *t_out = t;
  return best;
}

std::optional<PoseChange> estimate_hybrid(const std::vector<PoseChangeCorrespondence>& c, const PoseChangeOptions& o,
                                          std::string* why) {
  const int min_depth = std::max(kHybridMinDepth, o.min_depth_inliers);
  if (static_cast<int>(c.size()) < std::max(o.min_correspondences, kEssentialMinPoints))
    return fail(why, "too few correspondences: " + std::to_string(c.size()) + " < " +
                         std::to_string(std::max(o.min_correspondences, kEssentialMinPoints)));
  std::vector<int> with_depth;
  for (std::size_t k = 0; k < c.size(); ++k)
    if (c[k].depth_i) with_depth.push_back(static_cast<int>(k));
  if (static_cast<int>(with_depth.size()) < min_depth)
    return fail(why, "too few features with depth: " + std::to_string(with_depth.size()) + " < " +
                         std::to_string(min_depth));

  std::mt19937_64 rng(o.seed);
  const RotationModel ess = essential_rotation(c, o);
  const RotationModel rot = rotation_only(c, o, rng);
  if (!ess.ok && !rot.ok) return fail(why, "degenerate 2D-2D geometry: no rotation model with 5 inliers");
  // Essential: 3-dim manifold, 5 parameters; rotation (infinite homography): 2-dim, 3 parameters.
  const bool use_rot = rot.ok && (!ess.ok || gric(rot, 2, 3, o.noise_sigma_px) < gric(ess, 3, 5, o.noise_sigma_px));
  const RotationModel& model = use_rot ? rot : ess;
  // Every depth feature is a candidate for the translation, judged by its reprojection under the
  // final (R, t) in the translation RANSAC: the epipolar test depends on the essential model's
  // translation direction, its weakest part when most features are far (and discarded by HPnP),
  // and near depth features are the outliers of the rotation-only model by construction.
  const std::vector<int>& cand = with_depth;
  Vec3 t = Vec3::Zero();
  const std::vector<int> din = hybrid_translation(c, cand, model.R, o, rng, &t);
  if (static_cast<int>(din.size()) < min_depth)
    return fail(why, "too few depth inliers after the translation fit: " + std::to_string(din.size()) + " < " +
                         std::to_string(min_depth));

  PoseChange p;
  p.T_j_i = SE3(model.R, t);
  p.rotation_only = use_rot;
  p.depth_inlier.assign(c.size(), 0);
  for (int k : din) p.depth_inlier[k] = 1;
  p.inlier.assign(c.size(), 0);
  for (std::size_t k = 0; k < c.size(); ++k) p.inlier[k] = c[k].depth_i ? p.depth_inlier[k] : model.inlier[k];
  p.inliers = static_cast<int>(std::count(p.inlier.begin(), p.inlier.end(), 1));
  p.depth_inliers = static_cast<int>(din.size());
  return p;
}

std::optional<PoseChange> estimate_pnp(const std::vector<PoseChangeCorrespondence>& c, const PoseChangeOptions& o,
                                       std::string* why) {
  const int min_depth = std::max(kPnpMinDepth, o.min_depth_inliers);
  std::vector<int> with_depth;
  std::vector<cv::Point3d> obj;
  std::vector<cv::Point2d> img;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!c[k].depth_i) continue;
    with_depth.push_back(static_cast<int>(k));
    const Vec3 P = point_i(c[k]);
    obj.emplace_back(P.x(), P.y(), P.z());
    img.emplace_back(c[k].m_j.x(), c[k].m_j.y());
  }
  if (static_cast<int>(with_depth.size()) < min_depth)
    return fail(why, "too few features with depth: " + std::to_string(with_depth.size()) + " < " +
                         std::to_string(min_depth));
  cv::Mat rvec, tvec;
  std::vector<int> cv_inliers;
  bool solved = false;
  try {
    // OpenCV's RANSAC registrator is seeded with a constant: deterministic by itself.
    solved = cv::solvePnPRansac(obj, img, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), rvec, tvec, false,
                                o.ransac_max_iterations, static_cast<float>(depth_threshold(o) / o.focal_px),
                                o.ransac_confidence, cv_inliers, cv::SOLVEPNP_ITERATIVE);
  } catch (const cv::Exception& e) {
    return fail(why, std::string("solvePnPRansac failed: ") + e.what());
  }
  if (!solved || rvec.empty() || tvec.empty()) return fail(why, "solvePnPRansac found no pose");
  const auto pose = pose_from_rodrigues(rvec, tvec);
  if (!pose) return fail(why, "solvePnPRansac returned a non-finite pose");
  const auto& [R, t] = *pose;
  const std::vector<int> din = depth_inliers(c, with_depth, R, t, o);
  if (static_cast<int>(din.size()) < min_depth)
    return fail(why, "too few PnP inliers: " + std::to_string(din.size()) + " < " + std::to_string(min_depth));
  PoseChange p;
  p.T_j_i = SE3(R, t);
  p.depth_inlier.assign(c.size(), 0);
  for (int k : din) p.depth_inlier[k] = 1;
  p.inlier = p.depth_inlier;  // features without depth take no part in 3D-2D PnP
  p.inliers = p.depth_inliers = static_cast<int>(din.size());
  return p;
}

}  // namespace

void validate(const PoseChangeOptions& o, const std::string& source) {
  if (!(o.focal_px > 0.0) || !std::isfinite(o.focal_px))
    throw ConfigError(source, "focal_px", "expected a finite value > 0 px, found " + number_text(o.focal_px));
  if (!(o.ransac_threshold_px > 0.0) || !std::isfinite(o.ransac_threshold_px))
    throw ConfigError(source, "ransac_threshold_px", "expected a finite value > 0 px, found " + number_text(o.ransac_threshold_px));
  if (!(o.ransac_confidence > 0.0 && o.ransac_confidence < 1.0))
    throw ConfigError(source, "ransac_confidence", "expected a value in (0, 1), found " + number_text(o.ransac_confidence));
  if (o.ransac_max_iterations < 1)
    throw ConfigError(source, "ransac_max_iterations",
                      "expected an integer >= 1, found " + std::to_string(o.ransac_max_iterations));
  if (!(o.depth_threshold_px >= 0.0) || !std::isfinite(o.depth_threshold_px))
    throw ConfigError(source, "depth_threshold_px", "expected a finite value >= 0 px, found " + number_text(o.depth_threshold_px));
  if (o.min_depth_inliers < 0)
    throw ConfigError(source, "min_depth_inliers", "expected an integer >= 0, found " + std::to_string(o.min_depth_inliers));
  if (o.min_correspondences < kEssentialMinPoints)
    throw ConfigError(source, "min_correspondences",
                      "expected an integer >= 5, found " + std::to_string(o.min_correspondences));
  if (!(o.noise_sigma_px > 0.0) || !std::isfinite(o.noise_sigma_px))
    throw ConfigError(source, "noise_sigma_px", "expected a finite value > 0 px, found " + number_text(o.noise_sigma_px));
}

std::optional<PoseChange> estimate_pose_change(const std::vector<PoseChangeCorrespondence>& c, PoseChangeMethod method,
                                               const PoseChangeOptions& options, std::string* why) {
  validate(options);
  check_input(c);
  return method == PoseChangeMethod::kHybrid ? estimate_hybrid(c, options, why) : estimate_pnp(c, options, why);
}

std::string to_string(PoseChangeMethod method) { return method == PoseChangeMethod::kHybrid ? "hpnp" : "pnp"; }

std::optional<Vec3> translation_least_squares(const Mat3& R_j_i, const std::vector<TranslationObservation>& obs) {
  if (obs.size() < 2) return std::nullopt;
  Mat3 N = Mat3::Zero();
  Vec3 g = Vec3::Zero();
  Eigen::Matrix<double, 2, 3> A;
  Vec2 b;
  for (const auto& o : obs) {
    eq3(R_j_i, o, &A, &b);
    N += A.transpose() * A;
    g += A.transpose() * b;
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(N);
  if (!(eig.eigenvalues()(0) > 1e-12 * std::max(1.0, eig.eigenvalues()(2)))) return std::nullopt;
  return Vec3(N.ldlt().solve(g));
}

Vec3 translation_levenberg_marquardt(const Mat3& R_j_i, const std::vector<TranslationObservation>& obs,
                                     const Vec3& t0, double huber_px, double focal_px, bool reprojection) {
  Vec3 t = t0;
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (const auto& o : obs) {
    ceres::LossFunction* loss = nullptr;
    if (huber_px > 0.0) {
      // |r_k| = Z_j * (normalized reprojection error): scale the switch point by the depth in j.
      const double z_j = std::max(R_j_i.row(2).dot(o.P_i) + t0.z(), kMinDepthJ);
      loss = new ceres::HuberLoss(huber_px / focal_px * (reprojection ? 1.0 : z_j));
    }
    problem.AddResidualBlock(new Eq3Cost(R_j_i, o, reprojection), loss, t.data());
  }
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 50;
  so.function_tolerance = 1e-14;
  so.parameter_tolerance = 1e-14;
  so.gradient_tolerance = 1e-16;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return t;
}

}  // namespace navaid::estimation
