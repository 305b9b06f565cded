#pragma once
// A recording in memory: per-sensor, time-ordered sample vectors plus calibration, as every reader
// (navaid format, EuRoC/ASL, TUM RGB-D, NMEA captures) produces it. Images stay on disk until a
// consumer loads them (load_frame_images). SensorEventStream merges the vectors into one stream.
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/messages.hpp"

namespace navaid::io {

/// Counted, skippable problems found while reading (documented skip behaviour), plus timing issues
/// (gaps, dropped frames) found by check_timing. Errors that make data wrong throw instead.
struct DataReport {
  struct Entry {
    std::string source;   ///< file or stream name
    std::string message;  ///< what was found
    std::size_t count = 1;
  };
  std::vector<Entry> warnings;
  void warn(const std::string& source, const std::string& message);  // merges equal messages
  std::size_t total() const;
};

struct Recording {
  std::string path;    ///< folder or file it was read from
  std::string format;  ///< "navaid", "euroc", "tum-rgbd", "nmea", "tum-trajectory"
  RigCalibration calibration;
  std::optional<GeodeticOrigin> origin;
  std::vector<ImuSample> imu;
  std::vector<RgbdFrame> frames;  ///< images not loaded
  std::vector<GpsFix> gps;
  std::vector<MagSample> mag;
  std::vector<GroundTruthState> groundtruth;
  std::vector<FeatureFrame> features;  ///< feature observations per camera frame
  std::vector<Landmark> landmarks;     ///< ground-truth landmarks, ids strictly increasing (not replayed)
  DataReport report;

  bool empty() const {
    return imu.empty() && frames.empty() && gps.empty() && mag.empty() && groundtruth.empty() && features.empty() &&
           landmarks.empty();
  }
};

}  // namespace navaid::io
