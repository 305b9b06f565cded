#pragma once
// Timing health of a recording, per sensor stream: counts, rates, gaps, dropped frames and
// non-monotonic timestamps. Used by `navaid info` and before replays.
//
// Definitions (also in docs/recording-format.md):
//  - period: median of the positive intervals between consecutive samples; rate_hz = 1 / period.
//  - gap: an interval longer than kGapFactor x period (2.5x: far beyond timestamp jitter, so a
//    gap is never noise; the price is that a single missing sample, a 2x interval, is not a gap).
//  - dropped: sum over gaps of round(interval / period) - 1, the samples that would have filled
//    the gaps at the median rate (meaningful for cameras; computed for every stream). Because of
//    the 2.5x threshold it counts runs of two or more missing samples only: a lower bound.
//  - non-monotonic: an interval <= 0 (a repeated or backwards timestamp). Readers reject these,
//    so any count here means the recording was built or edited wrongly: treat it as an error.
#include <cstddef>
#include <string>
#include <vector>

#include "navaid/core/time.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::io {

constexpr double kGapFactor = 2.5;

struct TimingOptions {
  double gap_factor = kGapFactor;
  /// Gaps beyond this many per stream are counted but not listed one by one in the report.
  std::size_t max_listed_gaps = 20;
  /// Warn when the median rate differs from the calibrated nominal rate by more than this ratio.
  double rate_mismatch_tolerance = 0.1;
};

struct StreamStats {
  std::string name;          ///< "imu", a camera ("cam0"), its features ("cam0 features"), "gps", ...
  bool is_camera = false;
  bool is_features = false;  ///< feature frames of one camera
  std::size_t count = 0;
  Timestamp first = 0;       ///< first and last timestamp (0 when count == 0)
  Timestamp last = 0;
  double duration_s = 0;     ///< (last - first) in seconds
  double period_s = 0;       ///< median positive interval; 0 with fewer than two samples
  double rate_hz = 0;        ///< 1 / period_s; 0 when unknown
  double nominal_rate_hz = 0;  ///< from the calibration when known, else 0
  std::size_t non_monotonic = 0;
  std::size_t gaps = 0;
  double longest_gap_s = 0;  ///< longest interval classified as a gap (0 without gaps)
  std::size_t dropped = 0;   ///< estimated missing samples over all gaps
};

/// Stats of one stream of timestamps (in recording order, not re-sorted). Gaps, non-monotonic
/// timestamps and a median rate far from `nominal_rate_hz` (when > 0) are reported into `report`
/// under `name`, with their times.
StreamStats analyze_stream(const std::string& name, const std::vector<Timestamp>& times, DataReport& report,
                           const TimingOptions& options = {}, double nominal_rate_hz = 0);

/// Stats of every non-empty stream of the recording, in the order imu, cameras (by first
/// appearance in `frames`), feature frames per camera (by first appearance in `features`, named
/// "<camera> features"), gps, mag, groundtruth.
std::vector<StreamStats> analyze_timing(const Recording& recording, DataReport& report,
                                        const TimingOptions& options = {});

/// True when no stream has non-monotonic timestamps.
bool timing_ok(const std::vector<StreamStats>& stats);

}  // namespace navaid::io
