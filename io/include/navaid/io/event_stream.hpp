#pragma once
// One time-ordered stream of sensor events from a Recording's per-sensor vectors: a k-way merge
// (a binary heap holding one cursor per sensor), O(log k) per event, no copy of the recording.
//
// Order: by timestamp; equal timestamps are broken by the fixed sensor order
//   ImuSample < MagSample < GpsFix < FeatureFrame < RgbdFrame
// (inertial data first, so that a consumer has propagated up to t before it sees the frame taken
// at t; features before the images of the same instant, so a consumer that tracks its own
// features from the images sees any external ones first), and within one sensor by position in
// its vector. Replay is therefore deterministic. Ground truth and landmarks are not sensor events
// and are never emitted.
#include <array>
#include <cstddef>
#include <optional>

#include "navaid/io/recording.hpp"

namespace navaid::io {

struct EventStreamOptions {
  /// Load each frame's images (load_frame_images) as it is emitted; otherwise frames carry only
  /// their paths. Loading errors propagate as IoError.
  bool load_images = false;
};

class SensorEventStream {
 public:
  /// Tie-break rank of each sensor (lower first at equal timestamps).
  enum class Sensor : int { kImu = 0, kMag = 1, kGps = 2, kFeatures = 3, kFrame = 4 };

  /// The recording must outlive the stream and stay unchanged while it is used. Throws
  /// std::invalid_argument when a sensor vector is not in non-decreasing time order.
  explicit SensorEventStream(const Recording& recording, EventStreamOptions options = {});

  /// The next event in global time order; nullopt when all streams are exhausted.
  std::optional<SensorEvent> next();
  /// Time of the next event without consuming it.
  std::optional<Timestamp> peek_time() const;
  /// Sensor of the next event without consuming it.
  std::optional<Sensor> peek_sensor() const;
  /// Skips every remaining event with t < `t` (O(k log n); skipped frames' images are not loaded).
  void skip_until(Timestamp t);
  /// Starts again from the first event.
  void reset();

  std::size_t total() const { return total_; }
  /// Events emitted or skipped so far.
  std::size_t consumed() const { return consumed_; }
  std::size_t remaining() const { return total_ - consumed_; }

 private:
  static constexpr std::size_t kSensors = 5;
  struct Head {
    Timestamp t;
    int sensor;
  };
  Timestamp time_at(int sensor, std::size_t index) const;
  std::size_t size_of(int sensor) const;
  void push(int sensor);
  Head pop();

  const Recording& recording_;
  EventStreamOptions options_;
  std::array<std::size_t, kSensors> cursor_{};
  // At most one entry per sensor, kept as a binary min-heap on (t, sensor).
  std::array<Head, kSensors> heap_{};
  std::size_t heap_size_ = 0;
  std::size_t total_ = 0;
  std::size_t consumed_ = 0;
};

}  // namespace navaid::io
