// Timing checks: rates, gaps with exact dropped counts, non-monotonic timestamps.
#include <gtest/gtest.h>

#include "navaid/io/timing_check.hpp"

namespace navaid::io {
namespace {

constexpr Timestamp kMs = 1'000'000;

std::vector<Timestamp> regular(Timestamp start, Duration period, int n) {
  std::vector<Timestamp> t;
  for (int i = 0; i < n; ++i) t.push_back(start + i * period);
  return t;
}

bool report_mentions(const DataReport& report, const std::string& source, const std::string& needle) {
  for (const auto& w : report.warnings)
    if (w.source == source && w.message.find(needle) != std::string::npos) return true;
  return false;
}

TEST(TimingCheckTest, RegularStream) {
  DataReport report;
  const StreamStats s = analyze_stream("imu", regular(1000, 5 * kMs, 201), report);
  EXPECT_EQ(s.count, 201u);
  EXPECT_EQ(s.first, 1000);
  EXPECT_EQ(s.last, 1000 + 200 * 5 * kMs);
  EXPECT_DOUBLE_EQ(s.duration_s, 1.0);
  EXPECT_DOUBLE_EQ(s.rate_hz, 200.0);
  EXPECT_EQ(s.gaps, 0u);
  EXPECT_EQ(s.dropped, 0u);
  EXPECT_EQ(s.non_monotonic, 0u);
  EXPECT_EQ(report.total(), 0u);
}

TEST(TimingCheckTest, CameraGapsGiveExactDroppedCount) {
  // 10 Hz camera with jitter; 4 frames lost after t=1.0 s, 2 after t=3.0 s, 1 after t=5.0 s.
  std::vector<Timestamp> t;
  for (int i = 0; i <= 80; ++i) {
    if ((i >= 11 && i <= 14) || (i >= 31 && i <= 32) || i == 51) continue;
    const Duration jitter = (i % 3 - 1) * 2 * kMs;  // +-2 ms
    t.push_back(i * 100 * kMs + jitter);
  }
  Recording r;
  for (const Timestamp ti : t) {
    RgbdFrame f;
    f.t = ti;
    r.frames.push_back(f);
  }
  DataReport report;
  const auto stats = analyze_timing(r, report);
  ASSERT_EQ(stats.size(), 1u);
  const StreamStats& s = stats[0];
  EXPECT_EQ(s.name, "cam0");
  EXPECT_TRUE(s.is_camera);
  EXPECT_NEAR(s.rate_hz, 10.0, 0.25);  // median of the jittered ~100 ms intervals
  EXPECT_EQ(s.gaps, 2u);      // the single lost frame (2x interval) is below the 2.5x threshold
  EXPECT_EQ(s.dropped, 6u);   // 4 + 2
  EXPECT_NEAR(s.longest_gap_s, 0.5, 0.005);
  EXPECT_TRUE(report_mentions(report, "cam0", "from 1.000000000 s to 1.498000000 s"));
  EXPECT_TRUE(report_mentions(report, "cam0", "~4 samples missing"));
  EXPECT_TRUE(report_mentions(report, "cam0", "~2 samples missing"));
  EXPECT_EQ(report.total(), 2u);
  EXPECT_TRUE(timing_ok(stats));
}

TEST(TimingCheckTest, NonMonotonicTimestampsAreErrors) {
  DataReport report;
  std::vector<Timestamp> t = regular(0, 10 * kMs, 20);
  t[5] = t[4];       // duplicate
  t[12] = t[10];     // backwards
  const StreamStats s = analyze_stream("mag", t, report);
  EXPECT_EQ(s.non_monotonic, 2u);
  EXPECT_TRUE(report_mentions(report, "mag", "error: non-monotonic timestamp 0.040000000 s at sample 5"));
  EXPECT_FALSE(timing_ok({s}));
}

TEST(TimingCheckTest, ManyGapsAreSummarised) {
  std::vector<Timestamp> t;
  for (int i = 0; i < 60; ++i) {
    t.push_back(i * 100 * kMs);
    t.push_back(i * 100 * kMs + 10 * kMs);
    t.push_back(i * 100 * kMs + 20 * kMs);  // then 80 ms silence: 7 missing at 100 Hz
  }
  DataReport report;
  TimingOptions options;
  options.max_listed_gaps = 5;
  const StreamStats s = analyze_stream("imu", t, report, options);
  EXPECT_EQ(s.gaps, 59u);
  EXPECT_EQ(s.dropped, 59u * 7u);
  EXPECT_EQ(report.warnings.size(), 6u);
  EXPECT_TRUE(report_mentions(report, "imu", "54 more gaps not listed"));
}

TEST(TimingCheckTest, NominalRateMismatchAndStreamOrder) {
  Recording r;
  for (const Timestamp t : regular(0, 4 * kMs, 100)) r.imu.push_back(ImuSample{t, Vec3::Zero(), Vec3::Zero(), true});
  for (const Timestamp t : regular(0, 200 * kMs, 10)) {
    GpsFix f;
    f.t = t;
    r.gps.push_back(f);
  }
  for (const Timestamp t : regular(0, 20 * kMs, 10)) r.mag.push_back(MagSample{t, Vec3::Zero()});
  r.groundtruth.resize(1);
  ImuCalibration imu;
  imu.rate_hz = 200;  // data runs at 250 Hz
  r.calibration.imu = imu;
  r.calibration.gps_rate_hz = 5;
  DataReport report;
  const auto stats = analyze_timing(r, report);
  ASSERT_EQ(stats.size(), 4u);
  EXPECT_EQ(stats[0].name, "imu");
  EXPECT_EQ(stats[1].name, "gps");
  EXPECT_EQ(stats[2].name, "mag");
  EXPECT_EQ(stats[3].name, "groundtruth");
  EXPECT_EQ(stats[3].rate_hz, 0.0);  // one sample: no rate
  EXPECT_EQ(stats[0].nominal_rate_hz, 200.0);
  EXPECT_TRUE(report_mentions(report, "imu", "median rate 250 Hz differs from the calibrated 200 Hz"));
  EXPECT_EQ(report.total(), 1u);
}

TEST(TimingCheckTest, FeatureFramesAreTimedPerCameraAfterTheImages) {
  Recording r;
  CameraCalibration cam1;
  cam1.name = "cam1";
  cam1.rate_hz = 20;
  r.calibration.cameras = {cam1};
  RgbdFrame image;
  image.camera = "cam1";
  r.frames = {image};
  // cam1 features at 20 Hz with two frames missing after 0.5 s, cam0 features at 10 Hz.
  for (const Timestamp t : regular(0, 50 * kMs, 21)) {
    FeatureFrame f;
    f.t = t < 550 * kMs ? t : t + 100 * kMs;
    f.camera = "cam1";
    r.features.push_back(f);
    if (t % (100 * kMs) == 0) {
      f.t = t;
      f.camera = "cam0";
      r.features.push_back(f);
    }
  }
  DataReport report;
  const auto stats = analyze_timing(r, report);
  ASSERT_EQ(stats.size(), 3u);
  EXPECT_EQ(stats[0].name, "cam1");
  EXPECT_TRUE(stats[0].is_camera);
  EXPECT_EQ(stats[1].name, "cam1 features");
  EXPECT_TRUE(stats[1].is_features);
  EXPECT_FALSE(stats[1].is_camera);
  EXPECT_EQ(stats[1].count, 21u);
  EXPECT_DOUBLE_EQ(stats[1].rate_hz, 20.0);
  EXPECT_EQ(stats[1].nominal_rate_hz, 20.0);
  EXPECT_EQ(stats[1].gaps, 1u);
  EXPECT_EQ(stats[1].dropped, 2u);
  EXPECT_EQ(stats[2].name, "cam0 features");
  EXPECT_EQ(stats[2].count, 11u);
  EXPECT_DOUBLE_EQ(stats[2].rate_hz, 10.0);
  EXPECT_TRUE(report_mentions(report, "cam1 features", "gap of 0.15 s"));
}

TEST(TimingCheckTest, MedianOfEvenCount) {
  DataReport report;
  // intervals 10, 10, 20, 20 ms -> median 15 ms
  const StreamStats s = analyze_stream("x", {0, 10 * kMs, 20 * kMs, 40 * kMs, 60 * kMs}, report);
  EXPECT_NEAR(s.period_s, 0.015, 1e-12);
}

}  // namespace
}  // namespace navaid::io
