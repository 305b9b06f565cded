// SensorEventStream: global time order, documented tie-breaking, skipping, lazy image loading.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <tuple>

#include "navaid/io/event_stream.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

using Sensor = SensorEventStream::Sensor;

// (t, kind) of an event, kind = variant index: 0 imu, 1 frame, 2 gps, 3 mag, 4 features.
std::pair<Timestamp, std::size_t> key(const SensorEvent& e) { return {event_time(e), e.index()}; }

std::vector<std::pair<Timestamp, std::size_t>> drain(SensorEventStream& stream) {
  std::vector<std::pair<Timestamp, std::size_t>> out;
  while (auto e = stream.next()) out.push_back(key(*e));
  return out;
}

ImuSample imu(Timestamp t) { return ImuSample{t, Vec3::Zero(), Vec3::Zero(), true}; }
MagSample mag(Timestamp t) { return MagSample{t, Vec3::Zero()}; }
GpsFix gps(Timestamp t) {
  GpsFix f;
  f.t = t;
  return f;
}
RgbdFrame frame(Timestamp t, std::uint64_t index = 0) {
  RgbdFrame f;
  f.t = t;
  f.index = index;
  return f;
}

FeatureFrame features(Timestamp t) {
  FeatureFrame f;
  f.t = t;
  return f;
}

constexpr std::size_t kImu = 0, kFrame = 1, kGps = 2, kMag = 3, kFeatures = 4;

TEST(EventStreamTest, MergesInTimeOrderWithFixedTieBreak) {
  Recording r;
  r.imu = {imu(0), imu(10), imu(20)};
  r.frames = {frame(10), frame(20)};
  r.gps = {gps(10), gps(25)};
  r.mag = {mag(5), mag(10)};
  r.features = {features(10), features(22)};
  r.groundtruth.resize(3);  // never emitted
  r.landmarks.resize(4);    // never emitted
  SensorEventStream stream(r);
  EXPECT_EQ(stream.total(), 11u);
  const std::vector<std::pair<Timestamp, std::size_t>> expected = {
      {0, kImu},      {5, kMag},   {10, kImu},  {10, kMag},      {10, kGps},
      {10, kFeatures}, {10, kFrame}, {20, kImu}, {20, kFrame}, {22, kFeatures}, {25, kGps}};
  EXPECT_EQ(drain(stream), expected);
  EXPECT_EQ(stream.remaining(), 0u);
  EXPECT_FALSE(stream.next().has_value());
  EXPECT_FALSE(stream.peek_time().has_value());
}

TEST(EventStreamTest, EqualTimesWithinOneSensorKeepVectorOrder) {
  Recording r;
  r.frames = {frame(7, 1), frame(7, 2), frame(9, 3)};  // two cameras firing together
  r.frames[1].camera = "cam1";
  SensorEventStream stream(r);
  std::vector<std::uint64_t> order;
  while (auto e = stream.next()) order.push_back(std::get<RgbdFrame>(*e).index);
  EXPECT_EQ(order, (std::vector<std::uint64_t>{1, 2, 3}));
}

TEST(EventStreamTest, EmptyRecording) {
  Recording r;
  SensorEventStream stream(r);
  EXPECT_EQ(stream.total(), 0u);
  EXPECT_FALSE(stream.next().has_value());
}

TEST(EventStreamTest, PeekSkipAndReset) {
  Recording r;
  for (int i = 0; i < 100; ++i) r.imu.push_back(imu(i * 10));
  for (int i = 0; i < 10; ++i) r.frames.push_back(frame(i * 100 + 5));
  for (int i = 0; i < 10; ++i) r.features.push_back(features(i * 100 + 5));
  SensorEventStream stream(r);
  EXPECT_EQ(stream.peek_time(), Timestamp{0});
  EXPECT_EQ(stream.peek_sensor(), Sensor::kImu);
  stream.skip_until(500);
  EXPECT_EQ(stream.consumed(), 50u + 5u + 5u);
  EXPECT_EQ(stream.peek_time(), Timestamp{500});
  stream.skip_until(505);
  EXPECT_EQ(stream.peek_sensor(), Sensor::kFeatures);  // features 505, then frame 505, before imu 510
  auto e = stream.next();
  ASSERT_TRUE(e);
  EXPECT_EQ(key(*e), std::make_pair(Timestamp{505}, kFeatures));
  e = stream.next();
  ASSERT_TRUE(e);
  EXPECT_EQ(key(*e), std::make_pair(Timestamp{505}, kFrame));
  stream.skip_until(100);  // backwards: no effect
  EXPECT_EQ(stream.peek_time(), Timestamp{510});
  stream.skip_until(1'000'000);
  EXPECT_EQ(stream.remaining(), 0u);
  stream.reset();
  EXPECT_EQ(drain(stream).size(), 120u);
}

TEST(EventStreamTest, MatchesStableSortOnRandomData) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> step(0, 3);  // zero steps make ties
  Recording r;
  Timestamp t = 0;
  for (int i = 0; i < 500; ++i) r.imu.push_back(imu(t += step(rng)));
  t = 0;
  for (int i = 0; i < 100; ++i) r.frames.push_back(frame(t += 1 + 5 * step(rng), static_cast<std::uint64_t>(i)));
  t = 0;
  for (int i = 0; i < 50; ++i) r.gps.push_back(gps(t += 1 + 10 * step(rng)));
  t = 0;
  for (int i = 0; i < 200; ++i) r.mag.push_back(mag(t += 1 + 2 * step(rng)));
  t = 0;
  for (int i = 0; i < 100; ++i) r.features.push_back(features(t += 5 * step(rng)));  // two cameras: equal times

  // Reference: everything in one vector, stably sorted by (t, documented sensor rank).
  const auto rank = [](std::size_t kind) {
    return kind == kImu ? 0 : kind == kMag ? 1 : kind == kGps ? 2 : kind == kFeatures ? 3 : 4;
  };
  std::vector<std::pair<Timestamp, std::size_t>> reference;
  for (const auto& s : r.imu) reference.emplace_back(s.t, kImu);
  for (const auto& s : r.frames) reference.emplace_back(s.t, kFrame);
  for (const auto& s : r.gps) reference.emplace_back(s.t, kGps);
  for (const auto& s : r.mag) reference.emplace_back(s.t, kMag);
  for (const auto& s : r.features) reference.emplace_back(s.t, kFeatures);
  std::stable_sort(reference.begin(), reference.end(), [&](const auto& a, const auto& b) {
    return std::make_pair(a.first, rank(a.second)) < std::make_pair(b.first, rank(b.second));
  });
  SensorEventStream stream(r);
  EXPECT_EQ(drain(stream), reference);
}

TEST(EventStreamTest, RejectsUnsortedInput) {
  Recording r;
  r.gps = {gps(10), gps(5)};
  const std::string message =
      navaid::testing::error_message<std::invalid_argument>([&] { SensorEventStream stream(r); });
  EXPECT_NE(message.find("gps[1]"), std::string::npos) << message;
}

TEST(EventStreamTest, LoadsImagesOnlyWhenAsked) {
  navaid::testing::ScratchDir dir("event-stream");
  const std::string png = (dir / "grey.png").string();
  ASSERT_TRUE(cv::imwrite(png, cv::Mat(2, 3, CV_8UC1, cv::Scalar(42))));
  Recording r;
  r.frames = {frame(1)};
  r.frames[0].intensity_path = png;

  SensorEventStream lazy(r);
  auto e = lazy.next();
  ASSERT_TRUE(e);
  EXPECT_TRUE(std::get<RgbdFrame>(*e).intensity.empty());

  SensorEventStream eager(r, EventStreamOptions{true});
  e = eager.next();
  ASSERT_TRUE(e);
  const auto& f = std::get<RgbdFrame>(*e);
  ASSERT_EQ(f.intensity.width, 3);
  EXPECT_EQ(f.intensity.at(2, 1), 42);
  EXPECT_TRUE(r.frames[0].intensity.empty());  // the recording itself is untouched
}

}  // namespace
}  // namespace navaid::io
