#include "navaid/io/timing_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace navaid::io {
namespace {

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::string seconds(Timestamp t) { return format_seconds(t) + " s"; }

double median_positive_interval(const std::vector<Timestamp>& times) {
  std::vector<Duration> intervals;
  intervals.reserve(times.size());
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (times[i] > times[i - 1]) intervals.push_back(times[i] - times[i - 1]);
  }
  if (intervals.empty()) return 0;
  const std::size_t mid = intervals.size() / 2;
  std::nth_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(mid), intervals.end());
  const double upper = static_cast<double>(intervals[mid]);
  if (intervals.size() % 2 == 1) return upper;
  const double lower = static_cast<double>(
      *std::max_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(mid)));
  return 0.5 * (lower + upper);
}

}  // namespace

StreamStats analyze_stream(const std::string& name, const std::vector<Timestamp>& times, DataReport& report,
                           const TimingOptions& options, double nominal_rate_hz) {
  StreamStats s;
  s.name = name;
  s.count = times.size();
  s.nominal_rate_hz = nominal_rate_hz;
  if (times.empty()) return s;
  s.first = times.front();
  s.last = times.back();
  s.duration_s = ns_to_seconds(s.last - s.first);

  const double period_ns = median_positive_interval(times);
  if (period_ns > 0) {
    s.period_s = period_ns * 1e-9;
    s.rate_hz = 1.0 / s.period_s;
  }

  std::size_t listed_gaps = 0;
  std::size_t listed_backwards = 0;
  for (std::size_t i = 1; i < times.size(); ++i) {
    const Duration dt = times[i] - times[i - 1];
    if (dt <= 0) {
      ++s.non_monotonic;
      if (listed_backwards++ < options.max_listed_gaps)
        report.warn(name, "error: non-monotonic timestamp " + seconds(times[i]) + " at sample " + std::to_string(i) +
                              " (previous " + seconds(times[i - 1]) + ")");
      continue;
    }
    if (period_ns <= 0 || static_cast<double>(dt) <= options.gap_factor * period_ns) continue;
    ++s.gaps;
    const auto missing = static_cast<std::size_t>(std::llround(static_cast<double>(dt) / period_ns) - 1);
    s.dropped += missing;
    s.longest_gap_s = std::max(s.longest_gap_s, ns_to_seconds(dt));
    if (listed_gaps++ < options.max_listed_gaps)
      report.warn(name, "gap of " + number(ns_to_seconds(dt)) + " s from " + seconds(times[i - 1]) + " to " +
                            seconds(times[i]) + " (~" + std::to_string(missing) + " samples missing at " +
                            number(s.rate_hz) + " Hz)");
  }
  if (s.non_monotonic > options.max_listed_gaps)
    report.warn(name, "error: " + std::to_string(s.non_monotonic - options.max_listed_gaps) +
                          " more non-monotonic timestamps not listed");
  if (s.gaps > options.max_listed_gaps)
    report.warn(name, std::to_string(s.gaps - options.max_listed_gaps) + " more gaps not listed (" +
                          std::to_string(s.gaps) + " in total, ~" + std::to_string(s.dropped) + " samples missing)");

  if (nominal_rate_hz > 0 && s.rate_hz > 0 &&
      std::abs(s.rate_hz - nominal_rate_hz) > options.rate_mismatch_tolerance * nominal_rate_hz)
    report.warn(name, "median rate " + number(s.rate_hz) + " Hz differs from the calibrated " +
                          number(nominal_rate_hz) + " Hz by more than " +
                          number(100 * options.rate_mismatch_tolerance) + "%");
  return s;
}

std::vector<StreamStats> analyze_timing(const Recording& recording, DataReport& report, const TimingOptions& options) {
  std::vector<StreamStats> out;
  const auto times_of = [](const auto& samples) {
    std::vector<Timestamp> t;
    t.reserve(samples.size());
    for (const auto& sample : samples) t.push_back(sample.t);
    return t;
  };
  const auto& calibration = recording.calibration;

  if (!recording.imu.empty())
    out.push_back(analyze_stream("imu", times_of(recording.imu), report, options,
                                 calibration.imu ? calibration.imu->rate_hz : 0.0));

  // Cameras in order of first appearance; each camera is its own stream, and so are its features.
  const auto per_camera = [&](const auto& frames, const std::string& suffix, bool features) {
    std::vector<std::string> cameras;
    std::map<std::string, std::vector<Timestamp>> camera_times;
    for (const auto& frame : frames) {
      auto [it, inserted] = camera_times.try_emplace(frame.camera);
      if (inserted) cameras.push_back(frame.camera);
      it->second.push_back(frame.t);
    }
    for (const auto& name : cameras) {
      double nominal = 0;
      for (const auto& c : calibration.cameras)
        if (c.name == name) nominal = c.rate_hz;
      StreamStats s = analyze_stream(name + suffix, camera_times[name], report, options, nominal);
      s.is_camera = !features;
      s.is_features = features;
      out.push_back(std::move(s));
    }
  };
  per_camera(recording.frames, "", false);
  per_camera(recording.features, " features", true);

  if (!recording.gps.empty())
    out.push_back(analyze_stream("gps", times_of(recording.gps), report, options, calibration.gps_rate_hz.value_or(0)));
  if (!recording.mag.empty())
    out.push_back(analyze_stream("mag", times_of(recording.mag), report, options, calibration.mag_rate_hz.value_or(0)));
  if (!recording.groundtruth.empty())
    out.push_back(analyze_stream("groundtruth", times_of(recording.groundtruth), report, options));
  return out;
}

bool timing_ok(const std::vector<StreamStats>& stats) {
  return std::all_of(stats.begin(), stats.end(), [](const StreamStats& s) { return s.non_monotonic == 0; });
}

}  // namespace navaid::io
