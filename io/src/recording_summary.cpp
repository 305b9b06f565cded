#include "navaid/io/recording_summary.hpp"

#include <algorithm>
#include <map>
#include <set>

#include "navaid/core/geodesy.hpp"

namespace navaid::io {
namespace {

std::string distortion_name(DistortionModel d) {
  switch (d) {
    case DistortionModel::kRadialTangential:
      return "radtan";
    case DistortionModel::kEquidistant:
      return "equidistant";
    case DistortionModel::kNone:
      break;
  }
  return "none";
}

std::optional<TrackSummary> groundtruth_track(const std::vector<GroundTruthState>& states) {
  if (states.empty()) return std::nullopt;
  TrackSummary s;
  s.points = states.size();
  s.duration_s = ns_to_seconds(states.back().t - states.front().t);
  for (std::size_t i = 1; i < states.size(); ++i) {
    s.length_m += (states[i].T_W_B.t - states[i - 1].T_W_B.t).norm();
    s.max_excursion_m = std::max(s.max_excursion_m, (states[i].T_W_B.t - states.front().T_W_B.t).norm());
  }
  return s;
}

std::optional<TrackSummary> gps_track(const std::vector<GpsFix>& fixes, std::size_t& without_position) {
  std::vector<const GpsFix*> located;
  for (const auto& f : fixes) {
    if (f.mode == GpsFixMode::kNoFix)
      ++without_position;
    else
      located.push_back(&f);
  }
  if (located.empty()) return std::nullopt;
  TrackSummary s;
  s.points = located.size();
  s.duration_s = ns_to_seconds(located.back()->t - located.front()->t);
  const GpsFix& first = *located.front();
  for (std::size_t i = 1; i < located.size(); ++i) {
    const GpsFix& a = *located[i - 1];
    const GpsFix& b = *located[i];
    s.length_m += geodesic_inverse(a.latitude_deg, a.longitude_deg, b.latitude_deg, b.longitude_deg).distance_m;
    s.max_excursion_m = std::max(
        s.max_excursion_m,
        geodesic_inverse(first.latitude_deg, first.longitude_deg, b.latitude_deg, b.longitude_deg).distance_m);
  }
  return s;
}

std::vector<FeatureSummary> feature_summaries(const std::vector<FeatureFrame>& frames) {
  std::vector<FeatureSummary> out;
  std::map<std::string, std::size_t> slot;
  std::vector<std::set<std::uint64_t>> tracks;
  std::vector<std::size_t> with_depth;
  for (const auto& f : frames) {
    const auto [it, inserted] = slot.try_emplace(f.camera, out.size());
    if (inserted) {
      out.push_back(FeatureSummary{f.camera});
      tracks.emplace_back();
      with_depth.push_back(0);
    }
    FeatureSummary& s = out[it->second];
    ++s.frames;
    s.empty_frames += f.features.empty();
    s.observations += f.features.size();
    for (const auto& o : f.features) {
      tracks[it->second].insert(o.track_id);
      with_depth[it->second] += o.depth_m.has_value();
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    FeatureSummary& s = out[i];
    s.tracks = tracks[i].size();
    s.mean_per_frame = static_cast<double>(s.observations) / static_cast<double>(s.frames);
    if (s.observations > 0) s.depth_fraction = static_cast<double>(with_depth[i]) / static_cast<double>(s.observations);
  }
  return out;
}

std::size_t tracks_without_landmark(const Recording& recording) {
  if (recording.landmarks.empty()) return 0;
  std::set<std::uint64_t> missing;
  for (const auto& f : recording.features)
    for (const auto& o : f.features) {
      // Landmarks are sorted by id (the reader and writer enforce it).
      const auto it = std::lower_bound(recording.landmarks.begin(), recording.landmarks.end(), o.track_id,
                                       [](const Landmark& l, std::uint64_t id) { return l.id < id; });
      if (it == recording.landmarks.end() || it->id != o.track_id) missing.insert(o.track_id);
    }
  return missing.size();
}

}  // namespace

RecordingSummary summarize(const Recording& recording) {
  RecordingSummary s;
  s.path = recording.path;
  s.format = recording.format;
  s.report = recording.report;
  s.streams = analyze_timing(recording, s.report);
  s.groundtruth = groundtruth_track(recording.groundtruth);
  s.gps_track = gps_track(recording.gps, s.gps_fixes_without_position);
  s.features = feature_summaries(recording.features);
  s.landmarks = recording.landmarks.size();
  s.tracks_without_landmark = tracks_without_landmark(recording);
  if (s.tracks_without_landmark > 0)
    s.report.warn("landmarks", std::to_string(s.tracks_without_landmark) +
                                   " feature track ids have no ground-truth landmark");
  s.origin = recording.origin;
  for (const auto& cam : recording.calibration.cameras)
    s.cameras.push_back(cam.name + " " + std::to_string(cam.width) + "x" + std::to_string(cam.height) + " " +
                        distortion_name(cam.distortion));
  s.has_imu_calibration = recording.calibration.imu.has_value();
  return s;
}

}  // namespace navaid::io
