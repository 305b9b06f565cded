#pragma once
// The feature tracks of the sliding window: for each track id, its observations in the window's
// frames (oldest first; the first is the anchor, where the inverse depth is defined) and its
// inverse depth. Ordered containers only, so iteration (and hence the estimator) is deterministic.
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace navaid::estimation {

struct TrackObservation {
  std::uint64_t frame_id = 0;
  Eigen::Vector2d m = Eigen::Vector2d::Zero();   ///< undistorted normalized coordinates (x/z, y/z)
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< measured pixel (parallax)
  std::optional<double> depth_m;                 ///< measured depth along the optical axis
  // For the online time offset (estimator.time_offset.estimate): the feature's image velocity and
  // depth rate from its previous frame, and the offset the frame's time was corrected with.
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< dm/dt [1/s]
  double depth_rate_mps = 0;                           ///< dZ/dt [m/s] (0 unknown)
  double td0_s = 0;
};

struct FeatureTrack {
  std::uint64_t id = 0;
  std::vector<TrackObservation> observations;  ///< increasing frame_id; front() is the anchor
  /// [x_a, y_a, lambda]: the bearing on the anchor camera's normalized plane and the inverse depth
  /// lambda = 1 / z in the anchor camera [1/m]. The bearing is the anchor's measurement, or an
  /// estimate of it (estimator.features.anchor_bearing = estimated): one contiguous parameter block.
  double landmark[3] = {0, 0, 0};
  bool initialized = false;  ///< landmark holds an estimate
  /// Handed over (estimator.features.leaving_anchor = hand_over): the anchor keyframe left the
  /// window while the track was alive. The landmark stays anchored at that keyframe's pose as it
  /// was then, held constant here (a fixed frame, so the landmark keeps its meaning in the
  /// marginalization prior), and every remaining observation is a target.
  bool handed_over = false;
  double frozen_anchor_pose[7] = {0, 0, 0, 0, 0, 0, 1};  ///< T_W_B of the left anchor ([p, q])

  const TrackObservation& anchor() const { return observations.front(); }
  double& inverse_depth() { return landmark[2]; }
  double inverse_depth() const { return landmark[2]; }
  Eigen::Vector2d bearing() const { return Eigen::Vector2d(landmark[0], landmark[1]); }
};

class FeatureTrackStore {
 public:
  /// Adds the observations of a new frame; frame ids must increase from call to call (Error otherwise).
  void add_frame(std::uint64_t frame_id, const std::vector<std::pair<std::uint64_t, TrackObservation>>& observations);

  /// Erases the frame's observations; tracks left without observations disappear. Tracks whose
  /// anchor was this frame now have their next observation as anchor: their inverse depth is
  /// no longer valid unless the caller re-expresses it (see anchored_at()).
  void remove_frame(std::uint64_t frame_id);

  /// Ids of the tracks whose anchor is `frame_id`.
  std::vector<std::uint64_t> anchored_at(std::uint64_t frame_id) const;

  /// Mean pixel displacement of the tracks seen in both frames, and how many there are
  /// (0 and 0 when none).
  double mean_parallax_px(std::uint64_t frame_a, std::uint64_t frame_b, int* common = nullptr) const;

  /// Removes a track (e.g. after a failed triangulation or a negative depth).
  void erase(std::uint64_t track_id) { tracks_.erase(track_id); }

  std::map<std::uint64_t, FeatureTrack>& tracks() { return tracks_; }
  const std::map<std::uint64_t, FeatureTrack>& tracks() const { return tracks_; }

 private:
  static const TrackObservation* find(const FeatureTrack& track, std::uint64_t frame_id);

  std::map<std::uint64_t, FeatureTrack> tracks_;
  std::optional<std::uint64_t> last_frame_;
};

}  // namespace navaid::estimation
