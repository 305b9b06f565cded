// The device link (docs/device-protocol.md): host encode + decode of a belt PATTERN (5 actuators,
// 55-byte frame), the host and the controller's C decoder on the same stream and their ratio, the
// latency from handing a pattern to DeviceLink to its first byte readable on the other end of a
// pty, the same from a GuidanceCommand through the cue session, and the round trip to the
// firmware's ACK through the simulated controller. One thread
// (plus the simulated controller's).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/interaction/belt_adapter.hpp"
#include "navaid/interaction/cue_session.hpp"
#include "navaid/interaction/device_link.hpp"
#include "navaid/interaction/device_protocol.hpp"
#include "navaid_link.h"
#include "navaid_link_sim.hpp"

namespace {

using namespace navaid;
using namespace navaid::interaction;

ActuatorPattern belt_pattern(int k) {
  ActuatorPattern p;
  p.device = DeviceKind::kBelt;
  for (std::uint8_t i = 0; i < 5; ++i) {
    p.commands.push_back({i, static_cast<std::int16_t>((k * 37 + i * 100) % 1001), 200, 100, 1100});
  }
  return p;
}

std::vector<std::uint8_t> pattern_stream(int frames) {
  std::vector<std::uint8_t> s;
  FrameBuffer b;
  for (int k = 0; k < frames; ++k) {
    const std::size_t n = encode_pattern(belt_pattern(k), static_cast<std::uint16_t>(k), b.data());
    s.insert(s.end(), b.begin(), b.begin() + static_cast<long>(n));
  }
  return s;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

void BM_HostEncodeDecodePattern(benchmark::State& state) {
  FrameDecoder decoder(FrameDirection::kHostToDevice);
  FrameBuffer b;
  std::size_t got = 0;
  const FrameDecoder::Callback count = [&](const DecodedFrame&) { ++got; };
  const ActuatorPattern p = belt_pattern(1);
  std::uint16_t seq = 0;
  for (auto _ : state) {
    const std::size_t n = encode_pattern(p, seq++, b.data());
    decoder.feed(b.data(), n, count);
  }
  if (got != static_cast<std::size_t>(state.iterations())) state.SkipWithError("frames lost");
  state.SetItemsProcessed(state.iterations());
  state.SetBytesProcessed(state.iterations() * static_cast<long>(encode_pattern(p, 0, b.data())));
}

void BM_HostDecodeStream(benchmark::State& state) {
  const std::vector<std::uint8_t> s = pattern_stream(1000);
  std::size_t got = 0;
  const FrameDecoder::Callback count = [&](const DecodedFrame&) { ++got; };
  for (auto _ : state) {
    FrameDecoder decoder(FrameDirection::kHostToDevice);
    decoder.feed(s.data(), s.size(), count);
  }
  state.SetItemsProcessed(state.iterations() * 1000);
  state.SetBytesProcessed(state.iterations() * static_cast<long>(s.size()));
}

void count_frame(void* ctx, const navaid_link_frame*) { ++*static_cast<std::size_t*>(ctx); }

void BM_FirmwareDecodeStream(benchmark::State& state) {
  const std::vector<std::uint8_t> s = pattern_stream(1000);
  std::size_t got = 0;
  for (auto _ : state) {
    navaid_link_decoder dec;
    navaid_link_decoder_init(&dec);
    navaid_link_decoder_feed(&dec, s.data(), s.size(), &count_frame, &got);
  }
  state.SetItemsProcessed(state.iterations() * 1000);
  state.SetBytesProcessed(state.iterations() * static_cast<long>(s.size()));
}

// Both decoders timed on the same 1000-frame stream in one benchmark so that their ratio is one
// number: host frames/s divided by firmware frames/s.
void BM_DecoderRatioHostOverFirmware(benchmark::State& state) {
  const std::vector<std::uint8_t> s = pattern_stream(1000);
  std::size_t got = 0;
  const FrameDecoder::Callback count = [&](const DecodedFrame&) { ++got; };
  double host_s = 0.0;
  double fw_s = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    FrameDecoder decoder(FrameDirection::kHostToDevice);
    decoder.feed(s.data(), s.size(), count);
    const auto t1 = std::chrono::steady_clock::now();
    navaid_link_decoder dec;
    navaid_link_decoder_init(&dec);
    navaid_link_decoder_feed(&dec, s.data(), s.size(), &count_frame, &got);
    const auto t2 = std::chrono::steady_clock::now();
    host_s += std::chrono::duration<double>(t1 - t0).count();
    fw_s += std::chrono::duration<double>(t2 - t1).count();
  }
  const double frames = static_cast<double>(state.iterations()) * 1000.0;
  state.counters["host_frames_per_s"] = frames / host_s;
  state.counters["firmware_frames_per_s"] = frames / fw_s;
  state.counters["host_over_firmware"] = fw_s / host_s;
}

/// The master end of a new pty: the benchmarks' DeviceLink opens name(), the benchmark reads here.
class PtyMaster {
 public:
  PtyMaster() : fd_(::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK)) {
    if (fd_ < 0 || ::grantpt(fd_) != 0 || ::unlockpt(fd_) != 0 || ::ptsname_r(fd_, name_, sizeof name_) != 0) name_[0] = 0;
  }
  ~PtyMaster() {
    if (fd_ >= 0) ::close(fd_);
  }
  PtyMaster(const PtyMaster&) = delete;
  PtyMaster& operator=(const PtyMaster&) = delete;
  bool ok() const { return name_[0] != 0; }
  const char* name() const { return name_; }
  void drain() {
    while (::read(fd_, buf_, sizeof buf_) > 0) {
    }
  }
  /// Microseconds from `t0` to the first byte readable, or a negative value after 1 s.
  double first_byte_us(std::chrono::steady_clock::time_point t0) const {
    pollfd pf{fd_, POLLIN, 0};
    if (::poll(&pf, 1, 1000) != 1) return -1.0;
    return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  }

 private:
  int fd_;
  char name_[128] = {};
  std::uint8_t buf_[4096];
};

void latency_counters(benchmark::State& state, const std::vector<double>& us) {
  state.counters["p50_us"] = percentile(us, 0.50);
  state.counters["p99_us"] = percentile(us, 0.99);
  state.counters["max_us"] = us.empty() ? 0.0 : *std::max_element(us.begin(), us.end());
}

/// Drains the pty, runs `act` and appends the microseconds to its first byte; false (and the
/// benchmark marked failed) when no byte came within 1 s.
template <class Act>
bool time_first_byte(benchmark::State& state, PtyMaster& pty, std::vector<double>& us, Act act) {
  pty.drain();
  const auto t0 = std::chrono::steady_clock::now();
  act();
  us.push_back(pty.first_byte_us(t0));
  if (us.back() >= 0) return true;
  state.SkipWithError("no byte within 1 s");
  return false;
}

/// Latency from DeviceLink::send() to the first byte readable on the pty master. Nobody answers:
/// each new pattern supersedes the last, which does not change what is measured.
void BM_PatternToFirstBytePty(benchmark::State& state) {
  PtyMaster pty;
  if (!pty.ok()) {
    state.SkipWithError("no pty");
    return;
  }
  DeviceLink link(pty.name(), DeviceKind::kBelt, LinkConfig{});
  std::vector<double> us;
  int k = 0;
  for (auto _ : state) {
    const ActuatorPattern p = belt_pattern(k++);
    if (!time_first_byte(state, pty, us, [&] { link.send(p); })) break;
  }
  pty.drain();
  link.close();
  latency_counters(state, us);
}

/// The whole host path: a GuidanceCommand into a CueSession (cue generator, scheduler, belt
/// adapter) whose sink is the DeviceLink, to the first byte readable on the pty master. Each
/// iteration is a fresh session, so the command's pattern goes out at once (a turn: the first
/// pattern; a stop: pre-empts). The target: p99 <= 1 ms.
void BM_GuidanceCommandToFirstBytePty(benchmark::State& state, bool stop) {
  PtyMaster pty;
  if (!pty.ok()) {
    state.SkipWithError("no pty");
    return;
  }
  DeviceLink link(pty.name(), DeviceKind::kBelt, LinkConfig{});
  const BeltAdapter belt;
  const Config defaults = Config::parse("{}", "<defaults>", {});
  const CueGeneratorConfig generator = read_cue_generator_config(defaults);
  const CuePolicyConfig policy = read_cue_policy_config(defaults);
  std::vector<double> us;
  int k = 0;
  for (auto _ : state) {
    CueSession session(generator, policy, belt, nullptr, [&link](const CueEvent& e) { link.on_event(e); });
    planning::GuidanceCommand c;
    c.t = seconds_to_ns(1.0);
    c.confidence = 1.0;
    if (stop) {
      c.action = planning::GuidanceAction::kStop;
      c.reason = planning::GuidanceReason::kObstacleAhead;
    } else {
      c.action = planning::GuidanceAction::kGo;
      c.reason = planning::GuidanceReason::kPathFound;
      c.heading_rad = (k++ % 2 == 0 ? 0.8 : -0.8);
    }
    if (!time_first_byte(state, pty, us, [&] { session.feed(c); })) break;
  }
  pty.drain();
  link.close();
  latency_counters(state, us);
}

/// Pattern handed to DeviceLink -> the simulated controller's ACK back, over a pty, as the
/// LinkReport measures it.
void BM_PatternRoundTripFirmwarePty(benchmark::State& state) {
  navaid::firmware_sim::SimulatedController sim(NAVAID_LINK_DEVICE_BELT, 5);
  DeviceLink link(sim.host_path(), DeviceKind::kBelt, LinkConfig{});
  int k = 0;
  for (auto _ : state) {
    link.send(belt_pattern(k++));
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (link.awaiting_ack() && std::chrono::steady_clock::now() < limit) link.poll(0, 5);
    if (link.awaiting_ack()) {
      state.SkipWithError("no ACK within 1 s");
      break;
    }
  }
  const LinkReport r = link.report();
  std::vector<double> us;
  for (double ms : r.latency_ms) us.push_back(ms * 1000.0);
  link.close();
  state.counters["p50_us"] = percentile(us, 0.50);
  state.counters["p99_us"] = percentile(us, 0.99);
  state.counters["retransmits"] = static_cast<double>(r.retransmits);
}

}  // namespace

BENCHMARK(BM_HostEncodeDecodePattern);
BENCHMARK(BM_HostDecodeStream);
BENCHMARK(BM_FirmwareDecodeStream);
BENCHMARK(BM_DecoderRatioHostOverFirmware);
BENCHMARK(BM_PatternToFirstBytePty)->Iterations(5000)->UseRealTime();
BENCHMARK_CAPTURE(BM_GuidanceCommandToFirstBytePty, turn, false)->Iterations(5000)->UseRealTime();
BENCHMARK_CAPTURE(BM_GuidanceCommandToFirstBytePty, stop, true)->Iterations(5000)->UseRealTime();
BENCHMARK(BM_PatternRoundTripFirmwarePty)->Iterations(2000)->UseRealTime();
