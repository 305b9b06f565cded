#include "navaid/io/recording_summary.hpp"

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

}  // namespace

RecordingSummary summarize(const Recording& recording) {
  RecordingSummary s;
  s.path = recording.path;
  s.format = recording.format;
  s.report = recording.report;
  s.streams = analyze_timing(recording, s.report);
  s.groundtruth = groundtruth_track(recording.groundtruth);
  s.gps_track = gps_track(recording.gps, s.gps_fixes_without_position);
  s.origin = recording.origin;
  for (const auto& cam : recording.calibration.cameras)
    s.cameras.push_back(cam.name + " " + std::to_string(cam.width) + "x" + std::to_string(cam.height) + " " +
                        distortion_name(cam.distortion));
  s.has_imu_calibration = recording.calibration.imu.has_value();
  return s;
}

}  // namespace navaid::io
