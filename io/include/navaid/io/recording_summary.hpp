#pragma once
// What `navaid info` reports about a recording: per-stream timing, ground-truth and GNSS track
// lengths, calibration at a glance, and every counted warning.
#include <optional>
#include <string>
#include <vector>

#include "navaid/io/recording.hpp"
#include "navaid/io/timing_check.hpp"

namespace navaid::io {

struct TrackSummary {
  std::size_t points = 0;
  double duration_s = 0;
  double length_m = 0;        ///< summed along consecutive points
  double max_excursion_m = 0; ///< largest distance from the first point
};

/// Feature observations of one camera.
struct FeatureSummary {
  std::string camera;
  std::size_t frames = 0;
  std::size_t empty_frames = 0;    ///< frames without any feature
  std::size_t observations = 0;
  std::size_t tracks = 0;          ///< distinct track ids
  double mean_per_frame = 0;       ///< observations / frames
  double depth_fraction = 0;       ///< observations with depth / observations (0 without observations)
};

struct RecordingSummary {
  std::string path;
  std::string format;
  std::vector<StreamStats> streams;
  std::optional<TrackSummary> groundtruth;  ///< Euclidean, in the ground truth's frame
  std::optional<TrackSummary> gps_track;    ///< geodesic on WGS84, over fixes with a 2D/3D fix
  std::size_t gps_fixes_without_position = 0;  ///< fixes whose mode is "no fix"
  std::vector<FeatureSummary> features;  ///< per camera, in order of first appearance
  std::size_t landmarks = 0;
  /// Distinct feature track ids (all cameras) without a ground-truth landmark; only counted when
  /// the recording has landmarks.
  std::size_t tracks_without_landmark = 0;
  std::optional<GeodeticOrigin> origin;
  std::vector<std::string> cameras;  ///< "cam0 640x480 radtan"
  bool has_imu_calibration = false;
  DataReport report;  ///< reader warnings plus timing findings
};

RecordingSummary summarize(const Recording& recording);

}  // namespace navaid::io
