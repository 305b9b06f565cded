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

struct RecordingSummary {
  std::string path;
  std::string format;
  std::vector<StreamStats> streams;
  std::optional<TrackSummary> groundtruth;  ///< Euclidean, in the ground truth's frame
  std::optional<TrackSummary> gps_track;    ///< geodesic on WGS84, over fixes with a 2D/3D fix
  std::size_t gps_fixes_without_position = 0;  ///< fixes whose mode is "no fix"
  std::optional<GeodeticOrigin> origin;
  std::vector<std::string> cameras;  ///< "cam0 640x480 radtan"
  bool has_imu_calibration = false;
  DataReport report;  ///< reader warnings plus timing findings
};

RecordingSummary summarize(const Recording& recording);

}  // namespace navaid::io
