#include "navaid/estimation/frontend/feature_tracker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>
#include <thread>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/frontend/depth_association.hpp"

namespace navaid::estimation {

struct FeatureTracker::State {
  std::vector<cv::Mat> prev_pyramid;
  std::vector<cv::Mat> cur_pyramid;
  std::vector<cv::Mat> patches;  // per track (parallel to ids_): its birth patch (empty without the drift check)
};

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point& t) {
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

cv::Point2f to_cv(const Eigen::Vector2d& p) { return {static_cast<float>(p.x()), static_cast<float>(p.y())}; }

// Grey view of the frame's intensity (wraps the buffer when it already is grey).
cv::Mat grey_image(const RgbdFrame& frame, const CameraModel& camera, cv::Mat& storage) {
  const ImageU8& img = frame.intensity;
  const std::string what = "front end: frame " + std::to_string(frame.index) + " of camera '" + frame.camera + "': ";
  if (img.empty()) throw Error(what + "no intensity image loaded");
  if (img.width != camera.width() || img.height != camera.height())
    throw Error(what + "intensity is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                ", the camera is " + std::to_string(camera.width()) + "x" + std::to_string(camera.height()));
  // cv::Mat wraps without copying; OpenCV only reads it.
  auto* data = const_cast<std::uint8_t*>(img.data());
  if (img.channels == 1) return cv::Mat(img.height, img.width, CV_8UC1, data);
  if (img.channels == 3) {
    cv::cvtColor(cv::Mat(img.height, img.width, CV_8UC3, data), storage, cv::COLOR_RGB2GRAY);
    return storage;
  }
  throw Error(what + "intensity has " + std::to_string(img.channels) + " channels (expected 1 or 3)");
}

// Marks (0) the pixels within `margin` of a depth discontinuity: a 3x3 neighbourhood whose valid
// depths jump by more than `relative_jump` of the nearer one. Corners there are usually occlusion
// junctions (foreground edge over background texture) that slide as the viewpoint changes.
void mask_depth_edges(const ImageF32& depth, double relative_jump, int margin, cv::Mat& mask) {
  const cv::Mat d(depth.height, depth.width, CV_32FC1, const_cast<float*>(depth.data()));
  cv::Mat invalid_high;  // invalid -> +large so that the minimum ignores it
  cv::Mat invalid = d <= 0.0f;
  d.copyTo(invalid_high);
  invalid_high.setTo(cv::Scalar(1e9), invalid);
  cv::Mat lo, hi;
  const cv::Mat box = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  cv::erode(invalid_high, lo, box);
  cv::dilate(d, hi, box);
  cv::Mat edge = (hi - lo) > (lo * relative_jump);
  edge.setTo(cv::Scalar(0), lo > 1e8f);  // no valid depth around: unknown, not an edge
  if (margin > 0)
    cv::dilate(edge, edge, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * margin + 1, 2 * margin + 1)));
  mask.setTo(cv::Scalar(0), edge);
}

// Drops the tracks whose keep flag is 0 from the parallel arrays, preserving order.
template <class... Arrays>
void keep_where(const std::vector<char>& keep, Arrays&... arrays) {
  std::size_t m = 0;
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) {
      ((arrays[m] = arrays[i]), ...);
      ++m;
    }
  (arrays.resize(m), ...);
}

// Pyramidal KLT of `from` into `to` (started at `to`), the points split into `threads` contiguous
// chunks tracked concurrently. Each point is tracked on its own window of the shared read-only
// pyramids, so the result is the same for any split.
void track_split(const std::vector<cv::Mat>& from_pyramid, const std::vector<cv::Mat>& to_pyramid,
                 const std::vector<cv::Point2f>& from, std::vector<cv::Point2f>& to, std::vector<uchar>& status,
                 cv::Size window, int max_level, const cv::TermCriteria& stop, int threads) {
  const std::size_t n = from.size();
  status.assign(n, 0);
  const std::size_t chunks = std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(threads), n / 16));
  auto run = [&](std::size_t c) {
    const std::size_t begin = n * c / chunks, end = n * (c + 1) / chunks;
    if (begin == end) return;
    const std::vector<cv::Point2f> f(from.begin() + static_cast<std::ptrdiff_t>(begin),
                                     from.begin() + static_cast<std::ptrdiff_t>(end));
    std::vector<cv::Point2f> t(to.begin() + static_cast<std::ptrdiff_t>(begin), to.begin() + static_cast<std::ptrdiff_t>(end));
    std::vector<uchar> st;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(from_pyramid, to_pyramid, f, t, st, err, window, max_level, stop,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    std::copy(t.begin(), t.end(), to.begin() + static_cast<std::ptrdiff_t>(begin));
    std::copy(st.begin(), st.end(), status.begin() + static_cast<std::ptrdiff_t>(begin));
  };
  std::vector<std::thread> workers;
  for (std::size_t c = 1; c < chunks; ++c) workers.emplace_back(run, c);
  run(0);
  for (auto& w : workers) w.join();
}

// The birth patch's side: the KLT window and 5 px around it, so the window stays on the patch.
int patch_side(const FrontendConfig& config) { return config.klt_window_px + 10; }

// Aligns each track's birth patch into the frame (KLT at full resolution, from the tracked
// position): within max_px the track moves there, farther or unconverged it is dropped (keep = 0).
// OpenCV's KLT wants both images of one size: the patches are laid out on a frame-sized canvas
// (as many calls as the canvas needs), each point tracked from its patch's centre.
void align_to_birth_patches(const std::vector<cv::Mat>& patches, const std::vector<std::size_t>& which,
                            const std::vector<cv::Mat>& frame_pyramid, const FrontendConfig& config,
                            std::vector<Eigen::Vector2d>& uv, std::vector<char>& keep, FrontendStats& stats) {
  if (which.empty()) return;
  const cv::Size frame = frame_pyramid.front().size();
  const int side = patch_side(config);
  const int per_row = frame.width / side, per_call = per_row * (frame.height / side);
  if (per_call == 0) return;  // an image smaller than one patch: nothing to align against
  const float centre = 0.5f * static_cast<float>(side - 1);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, config.klt_max_iterations,
                              config.klt_epsilon);
  const double max2 = config.drift_max_px * config.drift_max_px;
  cv::Mat canvas(frame, CV_8UC1, cv::Scalar(0));
  for (std::size_t begin = 0; begin < which.size(); begin += static_cast<std::size_t>(per_call)) {
    const std::size_t end = std::min(which.size(), begin + static_cast<std::size_t>(per_call));
    std::vector<cv::Point2f> from, to;
    for (std::size_t k = begin; k < end; ++k) {
      const int slot = static_cast<int>(k - begin);
      const cv::Point corner(side * (slot % per_row), side * (slot / per_row));
      patches[which[k]].copyTo(canvas(cv::Rect(corner, cv::Size(side, side))));
      from.emplace_back(static_cast<float>(corner.x) + centre, static_cast<float>(corner.y) + centre);
      to.push_back(to_cv(uv[which[k]]));
    }
    std::vector<uchar> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(canvas, frame_pyramid, from, to, status, err,
                             cv::Size(config.klt_window_px, config.klt_window_px), 0, stop,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    for (std::size_t k = begin; k < end; ++k) {
      Eigen::Vector2d& p = uv[which[k]];
      const cv::Point2f& q = to[k - begin];
      const Eigen::Vector2d aligned(q.x, q.y);
      ++stats.drift_checked;
      if (!status[k - begin] || !aligned.allFinite() || !((aligned - p).squaredNorm() <= max2)) {
        keep[which[k]] = 0;
        ++stats.rejected_drift;
        continue;
      }
      if ((aligned - p).norm() > 0.05) ++stats.drift_corrected;
      p = aligned;
    }
  }
}

}  // namespace

FeatureTracker::FeatureTracker(std::shared_ptr<const CameraModel> camera, const FrontendConfig& config)
    : camera_(std::move(camera)), config_(config), state_(std::make_unique<State>()) {
  if (!camera_) throw Error("front end: no camera model");
  validate(config_);
}

FeatureTracker::~FeatureTracker() = default;
FeatureTracker::FeatureTracker(FeatureTracker&&) noexcept = default;
FeatureTracker& FeatureTracker::operator=(FeatureTracker&&) noexcept = default;

void FeatureTracker::reset() {
  ids_.clear();
  uv_.clear();
  age_.clear();
  state_->prev_pyramid.clear();
  state_->patches.clear();
}

KeyframeDecision FeatureTracker::decide_keyframe(const FeatureFrame& last_keyframe, const FeatureFrame& current,
                                                 const std::optional<Eigen::Matrix3d>& R_cur_kf) const {
  KeyframeCriteria criteria;
  criteria.min_parallax_px = config_.keyframe_parallax_px;
  criteria.min_tracked = static_cast<std::size_t>(config_.keyframe_min_tracked);
  return estimation::decide_keyframe(last_keyframe, current, *camera_, criteria, R_cur_kf);
}

FeatureFrame FeatureTracker::track(const RgbdFrame& frame, const std::optional<Eigen::Matrix3d>& R_cur_prev) {
  const Clock::time_point start = Clock::now();
  Clock::time_point t = start;
  stats_ = FrontendStats{};
  const CameraModel& cam = *camera_;
  if (!frame.depth.empty() && (frame.depth.width != cam.width() || frame.depth.height != cam.height()))
    throw Error("front end: frame " + std::to_string(frame.index) + ": depth image is " +
                std::to_string(frame.depth.width) + "x" + std::to_string(frame.depth.height) + ", the camera is " +
                std::to_string(cam.width()) + "x" + std::to_string(cam.height()));
  cv::Mat grey_storage;
  const cv::Mat grey = grey_image(frame, cam, grey_storage);

  const cv::Size window(config_.klt_window_px, config_.klt_window_px);
  cv::buildOpticalFlowPyramid(grey, state_->cur_pyramid, window, config_.klt_max_level, true);
  stats_.ms_pyramid = ms_since(t);

  // Surviving tracks: id, age, position in this frame.
  std::vector<std::uint64_t> ids;
  std::vector<int> ages;
  std::vector<Eigen::Vector2d> uv;
  std::vector<cv::Mat> patches;  // birth patches, parallel to ids (empty Mats without the drift check)
  const bool drift_check = config_.drift_check_interval > 0;
  if (!ids_.empty() && !state_->prev_pyramid.empty()) {
    const std::size_t n = ids_.size();
    std::vector<cv::Point2f> prev(n), cur(n);
    for (std::size_t i = 0; i < n; ++i) {
      prev[i] = to_cv(uv_[i]);
      cur[i] = prev[i];
      if (R_cur_prev && config_.imu_prediction) {
        // A distant point moves by the infinite homography K R K^-1 (through the lens model).
        if (const std::optional<Vec3> ray = cam.unproject(uv_[i]))
          if (const std::optional<Eigen::Vector2d> p = cam.project(*R_cur_prev * *ray); p && p->allFinite())
            cur[i] = to_cv(*p);
      }
    }
    const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, config_.klt_max_iterations,
                                config_.klt_epsilon);
    std::vector<uchar> status, back_status;
    track_split(state_->prev_pyramid, state_->cur_pyramid, prev, cur, status, window, config_.klt_max_level, stop,
                config_.klt_threads);
    std::vector<cv::Point2f> back;
    if (config_.forward_backward_check) {
      back = prev;
      track_split(state_->cur_pyramid, state_->prev_pyramid, cur, back, back_status, window,
                  std::min(config_.fb_max_level, config_.klt_max_level), stop, config_.klt_threads);
    }
    const double fb2 = config_.fb_threshold_px * config_.fb_threshold_px;
    for (std::size_t i = 0; i < n; ++i) {
      if (!status[i] || !std::isfinite(cur[i].x) || !std::isfinite(cur[i].y)) {
        ++stats_.lost_klt;
        continue;
      }
      if (config_.forward_backward_check) {
        const double dx = back[i].x - prev[i].x, dy = back[i].y - prev[i].y;
        if (!back_status[i] || !(dx * dx + dy * dy <= fb2)) {
          ++stats_.rejected_fb;
          continue;
        }
      }
      ids.push_back(ids_[i]);
      ages.push_back(age_[i] + 1);
      uv.emplace_back(cur[i].x, cur[i].y);
      patches.push_back(state_->patches[i]);
    }
    stats_.ms_klt = ms_since(t);

    if (hook_) {
      const std::size_t before = uv.size();
      hook_(ids, uv);
      if (uv.size() != before) throw Error("front end: the track hook changed the number of tracks");
    }

    std::vector<char> keep(ids.size(), 1);
    if (drift_check) {
      std::vector<std::size_t> due;
      for (std::size_t i = 0; i < ids.size(); ++i)
        if (ages[i] % config_.drift_check_interval == 0) due.push_back(i);
      align_to_birth_patches(patches, due, state_->cur_pyramid, config_, uv, keep, stats_);
    }
    // Border and fundamental-matrix RANSAC, on undistorted points scaled back to pixels so that the
    // threshold is an epipolar distance in pixels.
    std::vector<cv::Point2f> p_prev, p_cur;
    std::vector<std::size_t> which;
    std::size_t prev_index = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (!keep[i]) continue;
      if (!cam.in_image(uv[i], config_.border_px)) {
        keep[i] = 0;
        ++stats_.rejected_border;
        continue;
      }
      while (ids_[prev_index] != ids[i]) ++prev_index;  // both lists are sorted by id
      const std::optional<Eigen::Vector2d> a = cam.undistort(cam.distorted_from_pixel(uv_[prev_index]));
      const std::optional<Eigen::Vector2d> b = cam.undistort(cam.distorted_from_pixel(uv[i]));
      if (!a || !b) {  // outside what the lens model images: cannot be an inlier
        keep[i] = 0;
        ++stats_.rejected_ransac;
        continue;
      }
      p_prev.push_back(to_cv(cam.pixel_from_distorted(*a)));
      p_cur.push_back(to_cv(cam.pixel_from_distorted(*b)));
      which.push_back(i);
    }
    if (config_.ransac && p_prev.size() >= 8) {
      std::vector<uchar> inlier;
      const cv::Mat F = cv::findFundamentalMat(p_prev, p_cur, cv::FM_RANSAC, config_.ransac_threshold_px,
                                               config_.ransac_confidence, inlier);
      // An empty F (degenerate input) rejects nothing rather than everything.
      if (!F.empty() && inlier.size() == which.size())
        for (std::size_t k = 0; k < which.size(); ++k)
          if (!inlier[k]) {
            keep[which[k]] = 0;
            ++stats_.rejected_ransac;
          }
    }
    keep_where(keep, ids, ages, uv, patches);
    stats_.ms_ransac = ms_since(t);
  }

  // Minimum distance: older tracks claim their neighbourhood first; then new corners fill the gaps.
  cv::Mat mask(grey.rows, grey.cols, CV_8UC1, cv::Scalar(255));
  {
    std::vector<std::size_t> order(ids.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ages[a] > ages[b]; });
    std::vector<char> keep(ids.size(), 0);
    const int radius = static_cast<int>(std::lround(config_.min_distance_px));
    for (std::size_t i : order) {
      const cv::Point p(static_cast<int>(std::lround(uv[i].x())), static_cast<int>(std::lround(uv[i].y())));
      if (mask.at<uchar>(p) == 0) {
        ++stats_.pruned_close;
        continue;
      }
      keep[i] = 1;
      if (radius > 0) cv::circle(mask, p, radius, cv::Scalar(0), cv::FILLED);
    }
    keep_where(keep, ids, ages, uv, patches);
  }
  stats_.tracked = ids.size();

  const int wanted = config_.max_features - static_cast<int>(ids.size());
  if (wanted >= config_.detect_min_missing) {
    const int b = static_cast<int>(std::ceil(config_.border_px));
    if (b > 0) cv::rectangle(mask, cv::Rect(0, 0, mask.cols, mask.rows), cv::Scalar(0), 2 * b);
    if (config_.depth_edge_margin_px > 0 && !frame.depth.empty())
      mask_depth_edges(frame.depth, config_.depth_edge_relative_jump, config_.depth_edge_margin_px, mask);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(grey, corners, wanted, config_.quality_level, config_.min_distance_px, mask,
                            config_.corner_block_size, false);
    for (const cv::Point2f& c : corners) {
      const Eigen::Vector2d p(c.x, c.y);
      if (!cam.in_image(p, config_.border_px)) continue;
      ids.push_back(next_id_++);
      ages.push_back(1);
      uv.push_back(p);
      patches.emplace_back();
      if (drift_check) cv::getRectSubPix(grey, cv::Size(patch_side(config_), patch_side(config_)), c, patches.back());
      ++stats_.new_features;
    }
  }
  stats_.ms_detect = ms_since(t);

  FeatureFrame out;
  out.t = frame.t;
  out.camera = frame.camera;
  out.features.resize(ids.size());
  const CameraCalibration& calib = cam.calibration();
  const bool depth = !frame.depth.empty() && calib.depth_max_m > 0.0;
  DepthPatchOptions patch;
  patch.patch_size = config_.depth_patch_size;
  patch.min_valid = config_.depth_min_valid;
  patch.max_relative_spread = config_.depth_max_relative_spread;
  patch.min_depth_m = calib.depth_min_m;
  patch.max_depth_m = calib.depth_max_m;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    FeatureObservation& o = out.features[i];
    o.track_id = ids[i];
    o.uv = uv[i];
    if (depth) o.depth_m = associate_depth(frame.depth, uv[i], patch);
    stats_.with_depth += o.depth_m.has_value();
  }
  stats_.ms_depth = ms_since(t);

  ids_ = std::move(ids);
  age_ = std::move(ages);
  uv_ = std::move(uv);
  state_->patches = std::move(patches);
  std::swap(state_->prev_pyramid, state_->cur_pyramid);
  stats_.ms_total = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return out;
}

}  // namespace navaid::estimation
