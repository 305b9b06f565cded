#include "navaid/io/event_stream.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "navaid/io/image_io.hpp"

namespace navaid::io {
namespace {

constexpr const char* kSensorNames[] = {"imu", "mag", "gps", "features", "frames"};

// std heap functions build a max-heap; "later" as less-than puts the earliest (t, rank) on top.
struct Later {
  template <typename H>
  bool operator()(const H& a, const H& b) const {
    return a.t != b.t ? a.t > b.t : a.sensor > b.sensor;
  }
};

template <typename V>
void require_sorted(const V& samples, int sensor) {
  for (std::size_t i = 1; i < samples.size(); ++i) {
    if (samples[i].t < samples[i - 1].t)
      throw std::invalid_argument(std::string("SensorEventStream: ") + kSensorNames[sensor] + "[" + std::to_string(i) +
                                  "] has t=" + format_seconds(samples[i].t) + " s, before the previous sample (" +
                                  format_seconds(samples[i - 1].t) + " s)");
  }
}

}  // namespace

SensorEventStream::SensorEventStream(const Recording& recording, EventStreamOptions options)
    : recording_(recording), options_(options) {
  require_sorted(recording.imu, static_cast<int>(Sensor::kImu));
  require_sorted(recording.mag, static_cast<int>(Sensor::kMag));
  require_sorted(recording.gps, static_cast<int>(Sensor::kGps));
  require_sorted(recording.features, static_cast<int>(Sensor::kFeatures));
  require_sorted(recording.frames, static_cast<int>(Sensor::kFrame));
  for (std::size_t s = 0; s < kSensors; ++s) total_ += size_of(static_cast<int>(s));
  reset();
}

std::size_t SensorEventStream::size_of(int sensor) const {
  switch (static_cast<Sensor>(sensor)) {
    case Sensor::kImu: return recording_.imu.size();
    case Sensor::kMag: return recording_.mag.size();
    case Sensor::kGps: return recording_.gps.size();
    case Sensor::kFeatures: return recording_.features.size();
    case Sensor::kFrame: return recording_.frames.size();
  }
  return 0;
}

Timestamp SensorEventStream::time_at(int sensor, std::size_t index) const {
  switch (static_cast<Sensor>(sensor)) {
    case Sensor::kImu: return recording_.imu[index].t;
    case Sensor::kMag: return recording_.mag[index].t;
    case Sensor::kGps: return recording_.gps[index].t;
    case Sensor::kFeatures: return recording_.features[index].t;
    case Sensor::kFrame: return recording_.frames[index].t;
  }
  return 0;
}

void SensorEventStream::push(int sensor) {
  const std::size_t i = cursor_[static_cast<std::size_t>(sensor)];
  if (i >= size_of(sensor)) return;
  heap_[heap_size_++] = Head{time_at(sensor, i), sensor};
  std::push_heap(heap_.begin(), heap_.begin() + static_cast<std::ptrdiff_t>(heap_size_), Later{});
}

SensorEventStream::Head SensorEventStream::pop() {
  std::pop_heap(heap_.begin(), heap_.begin() + static_cast<std::ptrdiff_t>(heap_size_), Later{});
  return heap_[--heap_size_];
}

void SensorEventStream::reset() {
  cursor_.fill(0);
  heap_size_ = 0;
  consumed_ = 0;
  for (std::size_t s = 0; s < kSensors; ++s) push(static_cast<int>(s));
}

std::optional<Timestamp> SensorEventStream::peek_time() const {
  if (heap_size_ == 0) return std::nullopt;
  return heap_[0].t;
}

std::optional<SensorEventStream::Sensor> SensorEventStream::peek_sensor() const {
  if (heap_size_ == 0) return std::nullopt;
  return static_cast<Sensor>(heap_[0].sensor);
}

std::optional<SensorEvent> SensorEventStream::next() {
  if (heap_size_ == 0) return std::nullopt;
  const Head head = pop();
  const std::size_t i = cursor_[static_cast<std::size_t>(head.sensor)]++;
  push(head.sensor);
  ++consumed_;
  switch (static_cast<Sensor>(head.sensor)) {
    case Sensor::kImu: return SensorEvent(recording_.imu[i]);
    case Sensor::kMag: return SensorEvent(recording_.mag[i]);
    case Sensor::kGps: return SensorEvent(recording_.gps[i]);
    case Sensor::kFeatures: return SensorEvent(recording_.features[i]);
    case Sensor::kFrame: {
      SensorEvent event(recording_.frames[i]);
      if (options_.load_images) load_frame_images(std::get<RgbdFrame>(event));
      return event;
    }
  }
  return std::nullopt;
}

void SensorEventStream::skip_until(Timestamp t) {
  // Binary search per sensor, then rebuild the heap: O(k log n) however far we jump.
  const auto first_not_before = [t](const auto& samples, std::size_t from) {
    const auto it = std::lower_bound(samples.begin() + static_cast<std::ptrdiff_t>(from), samples.end(), t,
                                     [](const auto& sample, Timestamp value) { return sample.t < value; });
    return static_cast<std::size_t>(it - samples.begin());
  };
  const std::array<std::size_t, kSensors> target = {
      first_not_before(recording_.imu, cursor_[0]), first_not_before(recording_.mag, cursor_[1]),
      first_not_before(recording_.gps, cursor_[2]), first_not_before(recording_.features, cursor_[3]),
      first_not_before(recording_.frames, cursor_[4])};
  heap_size_ = 0;
  for (std::size_t s = 0; s < kSensors; ++s) {
    consumed_ += target[s] - cursor_[s];
    cursor_[s] = target[s];
    push(static_cast<int>(s));
  }
}

}  // namespace navaid::io
