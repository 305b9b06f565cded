// Event-stream merge throughput and navaid-recording CSV reading, on a synthetic 10-minute
// recording: 200 Hz IMU, 30 Hz frames, 5 Hz GPS, 50 Hz magnetometer (no image loading).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>
#include <string>

#include "navaid/core/random_draws.hpp"
#include "navaid/io/event_stream.hpp"
#include "navaid/io/navaid_recording.hpp"

namespace {

using namespace navaid;
using namespace navaid::io;

constexpr Timestamp kT0 = 1'700'000'000'000'000'000;
constexpr Duration kDuration = 600 * kNanosecondsPerSecond;

// Periods chosen so that the streams do not all fall on the same instants (real rates rarely
// divide each other exactly); timestamps carry a little jitter like real drivers.
Recording make_recording() {
  std::mt19937 rng(1);
  std::uniform_int_distribution<Duration> jitter(-20'000, 20'000);
  std::normal_distribution<double> normal;
  Recording r;
  for (Timestamp t = kT0; t < kT0 + kDuration; t += 5'000'000) {
    ImuSample s;
    s.t = t + jitter(rng);
    s.gyro = draw_vector<3>([&] { return normal(rng); }) * 0.1;
    s.accel = draw_vector<3>([&] { return normal(rng); });
    s.accel.z() += 9.81;
    r.imu.push_back(s);
  }
  std::uint64_t index = 0;
  for (Timestamp t = kT0 + 1'000'000; t < kT0 + kDuration; t += 33'333'333) {
    RgbdFrame f;
    f.t = t + jitter(rng);
    f.index = index++;
    r.frames.push_back(f);  // no image files: CSV cost only
  }
  for (Timestamp t = kT0 + 3'000'000; t < kT0 + kDuration; t += 200'000'000) {
    GpsFix f;
    f.t = t;
    f.latitude_deg = 46.5 + 1e-5 * normal(rng);
    f.longitude_deg = 6.6 + 1e-5 * normal(rng);
    f.altitude_m = 400 + normal(rng);
    f.satellites = 9;
    f.hdop = 0.8;
    r.gps.push_back(f);
  }
  for (Timestamp t = kT0 + 2'000'000; t < kT0 + kDuration; t += 20'000'000) {
    r.mag.push_back(MagSample{t + jitter(rng), draw_vector<3>([&] { return normal(rng); }) * 2e-5});
  }
  return r;
}

std::filesystem::path scratch_folder(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "-" + std::to_string(std::random_device{}()));
}

const Recording& recording() {
  static const Recording r = make_recording();
  return r;
}

void BM_MergeEvents(benchmark::State& state) {
  const Recording& r = recording();
  std::size_t events = 0;
  for (auto _ : state) {
    SensorEventStream stream(r);
    Timestamp last = 0;
    while (auto e = stream.next()) {
      last = event_time(*e);
      ++events;
    }
    benchmark::DoNotOptimize(last);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(events));
  state.counters["events_per_pass"] = static_cast<double>(SensorEventStream(r).total());
}
BENCHMARK(BM_MergeEvents)->Unit(benchmark::kMillisecond);

void BM_ReadNavaidRecordingCsv(benchmark::State& state) {
  const auto folder = scratch_folder("navaid-bench-read");
  NavaidWriteOptions options;
  options.overwrite = true;
  write_navaid_recording(recording(), folder, options);
  std::size_t rows = 0;
  std::uintmax_t bytes = 0;
  for (const auto& e : std::filesystem::directory_iterator(folder))
    if (e.is_regular_file()) bytes += e.file_size();
  for (auto _ : state) {
    const Recording r = read_navaid_recording(folder);
    rows += r.imu.size() + r.frames.size() + r.gps.size() + r.mag.size();
    benchmark::DoNotOptimize(r.imu.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(rows));
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes * state.iterations()));
  std::filesystem::remove_all(folder);
}
BENCHMARK(BM_ReadNavaidRecordingCsv)->Unit(benchmark::kMillisecond);

void BM_WriteNavaidRecordingCsv(benchmark::State& state) {
  const auto folder = scratch_folder("navaid-bench-write");
  NavaidWriteOptions options;
  options.overwrite = true;
  for (auto _ : state) write_navaid_recording(recording(), folder, options);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(SensorEventStream(recording()).total()));
  std::filesystem::remove_all(folder);
}
BENCHMARK(BM_WriteNavaidRecordingCsv)->Unit(benchmark::kMillisecond);

}  // namespace
