// The interaction layer's per-command cost: one GuidanceCommand (or system event) through the cue
// generator, the scheduler and a device adapter, speech timed in text-only mode, over a 100 s
// walk at 10 Hz; and espeak-ng's synthesis of the message templates (real-time factor), fresh
// and from the synthesizer's cache side by side. Target (issue): <= 50 us per command.
#include <benchmark/benchmark.h>

#include <random>

#include "navaid/core/config.hpp"
#include "navaid/interaction/cue_session.hpp"
#include "navaid/interaction/message_templates.hpp"
#include "navaid/interaction/synthesized_speech.hpp"

namespace {

using namespace navaid;
using namespace navaid::interaction;

/// A walk at 10 Hz: the heading wanders (on course, veer, turn), a stop every 20 s, a route
/// instruction every 15 s, a few seconds of locating, a voice command. Each planner fills its own
/// device's field (guidance_command.hpp): rumble states for the BYU cane, steering for the wheel.
std::vector<GuidanceTimelineEntry> walk(int commands, DeviceKind kind) {
  std::vector<GuidanceTimelineEntry> out;
  std::mt19937 rng(7);
  std::normal_distribution<double> step(0.0, 0.08);
  double heading = 0.0;
  for (int i = 0; i < commands; ++i) {
    const Timestamp t = seconds_to_ns(0.1 * i);
    if (i % 150 == 75) out.emplace_back(SystemEvent{t, SystemEventKind::kRouteInstruction, "49;left;Main Street"});
    if (i % 400 == 300) out.emplace_back(SystemEvent{t, SystemEventKind::kVoiceCommand, "repeat"});
    planning::GuidanceCommand c;
    c.t = t;
    c.confidence = (i % 300 >= 280) ? 0.1 : 0.9;  // 2 s of locating every 30 s
    if (i % 200 == 199) {
      c.action = planning::GuidanceAction::kStop;
      c.reason = planning::GuidanceReason::kObstacleAhead;
    } else {
      heading = std::clamp(heading + step(rng), -1.5, 1.5);
      c.action = planning::GuidanceAction::kGo;
      c.reason = planning::GuidanceReason::kPathFound;
      c.heading_rad = heading;
      if (kind == DeviceKind::kWheel) c.steering_rad = 0.5 * heading;
      if (kind == DeviceKind::kRumble) {
        c.rumble = heading > 0.3 ? planning::RumbleState::kLeft : heading < -0.3 ? planning::RumbleState::kRight
                                                                                 : planning::RumbleState::kOff;
      }
    }
    out.emplace_back(c);
  }
  return out;
}

void BM_CueSessionPerCommand(benchmark::State& state, DeviceKind kind) {
  const std::vector<GuidanceTimelineEntry> timeline = walk(1000, kind);
  const Config config = Config::parse("{}", "<defaults>", {});
  const std::unique_ptr<DeviceAdapter> device = make_device_adapter(kind, config);
  SpeechConfig speech_config;
  speech_config.text_only = true;
  const SynthesizedSpeech speech(speech_config);
  std::size_t events = 0, sent = 0, spoken = 0;
  for (auto _ : state) {
    CueSession session(read_cue_generator_config(config), read_cue_policy_config(config), *device, &speech);
    for (const GuidanceTimelineEntry& e : timeline) benchmark::DoNotOptimize(session.feed(e));
    events = session.events().size();
    sent = session.scheduler().counts()[static_cast<std::size_t>(CueOutcome::kSent)];
    spoken = session.scheduler().counts()[static_cast<std::size_t>(CueOutcome::kSpoken)];
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * timeline.size()));
  state.counters["us_per_command"] = benchmark::Counter(
      static_cast<double>(timeline.size()) * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["events"] = static_cast<double>(events);
  state.counters["patterns_sent"] = static_cast<double>(sent);
  state.counters["spoken"] = static_cast<double>(spoken);
}
BENCHMARK_CAPTURE(BM_CueSessionPerCommand, belt, DeviceKind::kBelt)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CueSessionPerCommand, rumble, DeviceKind::kRumble)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CueSessionPerCommand, wheel, DeviceKind::kWheel)->Unit(benchmark::kMillisecond);

void BM_RenderTemplate(benchmark::State& state) {
  const SpokenMessage m{MessageCategory::kRoute, "route", {{"distance_m", "49"}, {"turn", "left"}, {"road", "Main Street"}}};
  for (auto _ : state) benchmark::DoNotOptimize(render_message(m, "en"));
}
BENCHMARK(BM_RenderTemplate);

/// espeak-ng synthesis: rtf = synthesis time / audio length (below 1: faster than speech).
void BM_Synthesize(benchmark::State& state, const char* text, const char* language, bool cached) {
  SpeechConfig config;
  config.language = language;
  const SpeechSynthesizer synth(config);
  const double audio_s = synth.duration_s(text);
  for (auto _ : state) {
    benchmark::DoNotOptimize(cached ? synth.synthesize(text) : synth.synthesize_uncached(text));
  }
  state.counters["audio_s"] = audio_s;
  state.counters["rtf"] = benchmark::Counter(audio_s, benchmark::Counter::kIsIterationInvariantRate |
                                                          benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(BM_Synthesize, stop_en, "Stop!", "en", false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Synthesize, route_en, "In 49 meters, turn left onto Main Street.", "en", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Synthesize, route_de, "In 49 Metern links abbiegen, Hauptstraße.", "de", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Synthesize, route_en_cached, "In 49 meters, turn left onto Main Street.", "en", true)
    ->Unit(benchmark::kMillisecond);

}  // namespace
