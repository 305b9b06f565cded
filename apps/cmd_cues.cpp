// navaid cues: a guidance timeline (CSV of GuidanceCommands and system events, one file or several
// merged by time) through the cue generator, the scheduler and one device's adapter; writes the
// cue timeline (cues.csv), a timeline figure (cues.png), everything spoken (speech.wav) and
// summary.json. With --port the timeline is played out in real time to the vibration controller
// over the device link.
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/experiments/figure_script.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/interaction/cue_session.hpp"
#include "navaid/interaction/cue_timeline_csv.hpp"
#include "navaid/interaction/device_link.hpp"
#include "navaid/interaction/speech_mix.hpp"
#include "navaid/interaction/synthesized_speech.hpp"
#include "navaid/interaction/wav_file.hpp"

namespace navaid::cli {

using experiments::run_figure_script;


namespace {

using namespace navaid::interaction;

struct CuesArgs {
  std::vector<std::filesystem::path> guidance;
  std::string device;
  std::string speech = "on";
  std::filesystem::path out;
  std::filesystem::path config_file;
  std::vector<std::string> overrides;
  bool no_figure = false;
  std::string port;
  double speed = 1.0;
};

/// The timelines of all files on one clock: by time, a tie in the order the files were given.
std::vector<GuidanceTimelineEntry> merged_timeline(const std::vector<std::filesystem::path>& files) {
  std::vector<GuidanceTimelineEntry> all;
  for (const std::filesystem::path& f : files) {
    std::vector<GuidanceTimelineEntry> one = read_guidance_timeline_csv(f);
    all.insert(all.end(), std::make_move_iterator(one.begin()), std::make_move_iterator(one.end()));
  }
  std::stable_sort(all.begin(), all.end(), [](const GuidanceTimelineEntry& x, const GuidanceTimelineEntry& y) {
    return entry_time(x) < entry_time(y);
  });
  return all;
}

/// An entry moved to `t` (when the playback reaches it late).
GuidanceTimelineEntry at_time(GuidanceTimelineEntry entry, Timestamp t) {
  std::visit([&](auto& e) { e.t = std::max(e.t, t); }, entry);
  return entry;
}

/// Plays the timeline out on the wall clock (`speed` times faster) with every pattern sent over
/// the device link: the link's own events (lost, restored) go back into the session, so they
/// are spoken like any other system event. Returns when the timeline and its last cues are done.
void play_to_device(CueSession& session, DeviceLink& link, const std::vector<GuidanceTimelineEntry>& timeline,
                    double speed) {
  const Timestamp t0 = timeline.empty() ? 0 : entry_time(timeline.front());
  const Timestamp end = (timeline.empty() ? t0 : entry_time(timeline.back())) + seconds_to_ns(2.0);
  const Timestamp wall0 = DeviceLink::steady_now();
  const auto now = [&] {
    return t0 + static_cast<Timestamp>(static_cast<double>(DeviceLink::steady_now() - wall0) * speed);
  };
  std::size_t next = 0;
  Timestamp t = t0;
  while (t <= end) {
    t = std::max(t, now());
    while (next < timeline.size() && entry_time(timeline[next]) <= t) session.feed(at_time(timeline[next++], t));
    session.advance(t);
    for (const SystemEvent& e : link.poll(t, 2)) session.feed(SystemEvent{std::max(e.t, t), e.kind, e.value});
  }
  link.close();
}

void run(const CuesArgs& a) {
  const std::optional<DeviceKind> kind = device_kind_from_string(a.device);
  if (!kind) throw UsageError(fmt::format("--device must be belt, hand, rumble or wheel, not '{}'", a.device));
  if (a.speech != "on" && a.speech != "off" && a.speech != "text") {
    throw UsageError(fmt::format("--speech must be on, off or text, not '{}'", a.speech));
  }
  std::vector<std::string> overrides = a.overrides;
  if (a.speech == "text") overrides.push_back("interaction.speech.mode=text");
  const Config config = a.config_file.empty() ? Config::parse("{}", "<defaults>", overrides)
                                              : Config::load(a.config_file, overrides);
  const ConfigReads reads(config);
  const CueGeneratorConfig generator = read_cue_generator_config(config);
  const CuePolicyConfig policy = read_cue_policy_config(config);
  const std::unique_ptr<DeviceAdapter> device = make_device_adapter(*kind, config);
  const SpeechConfig speech_config = read_speech_config(config);
  if (!(a.speed > 0.0)) throw UsageError(fmt::format("--speed must be positive, not {}", a.speed));
  std::unique_ptr<DeviceLink> link;
  if (!a.port.empty()) link = std::make_unique<DeviceLink>(a.port, *kind, config);
  ConfigSchema schema = cue_generator_config_schema();
  schema.add(cue_policy_config_schema()).add(device_adapter_schema(*kind)).add(speech_config_schema());
  if (!a.port.empty()) schema.add(link_config_schema());
  config.reject_unknown_keys(schema);
  std::unique_ptr<SynthesizedSpeech> speech;
  if (a.speech != "off") speech = std::make_unique<SynthesizedSpeech>(speech_config);
  const std::vector<GuidanceTimelineEntry> timeline = merged_timeline(a.guidance);

  CueSession::Sink sink;
  if (link) sink = [&link](const CueEvent& e) { link->on_event(e); };
  CueSession session(generator, policy, *device, speech.get(), sink);
  if (link) {
    play_to_device(session, *link, timeline, a.speed);
  } else {
    for (const GuidanceTimelineEntry& entry : timeline) session.feed(entry);
    session.drain();
  }
  const std::vector<CueEvent>& events = session.events();

  std::filesystem::create_directories(a.out);
  write_cue_timeline_csv(a.out / "cues.csv", events);
  std::vector<std::string> spoken;
  for (const CueEvent& e : events) {
    if (e.outcome == CueOutcome::kSpoken) spoken.push_back(e.text);
  }
  double speech_s = 0.0;
  if (speech && !speech_config.text_only) {
    const AudioBuffer mix = mix_spoken_audio(events, *speech, timeline.empty() ? 0 : entry_time(timeline.front()));
    write_wav(a.out / "speech.wav", mix);
    speech_s = mix.duration_s();
  }
  std::vector<std::string> names;
  for (int i = 0; i < device->actuator_count(); ++i) names.emplace_back(device->actuator_name(i));

  std::vector<std::string> files;
  for (const std::filesystem::path& f : a.guidance) files.push_back(f.string());
  nlohmann::ordered_json counts = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < kCueOutcomeCount; ++i) {
    counts[std::string(to_string(static_cast<CueOutcome>(i)))] = session.scheduler().counts()[i];
  }
  nlohmann::ordered_json summary = {
      {"guidance_files", files},
      {"device", std::string(to_string(*kind))},
      {"actuators", names},
      {"speech", a.speech},
      {"language", speech_config.language},
      {"timeline_entries", timeline.size()},
      {"events", events.size()},
      {"outcomes", counts},
      {"spoken", spoken},
      {"speech_wav_s", speech_s},
  };
  if (link) summary["link"] = link->report().to_json();
  std::ofstream(a.out / "summary.json") << summary.dump(2) << "\n";
  std::ofstream(a.out / "config.yaml") << config.dump(reads.defaults());
  if (!a.no_figure) {
    std::string joined;
    for (const std::string& n : names) joined += (joined.empty() ? "" : ",") + n;
    run_figure_script("plot_cues.py", {(a.out / "cues.csv").string(), "--actuators", joined, "--device",
                                       std::string(to_string(*kind)), "--out", (a.out / "cues.png").string()});
  }
  std::cout << fmt::format("{}: {} timeline entries -> {} cue events; sent {}, refreshed {}, switched off {}; "
                           "spoken {}, interrupted {}, rate-limited {}, duplicates {}, expired {}\n",
                           to_string(*kind), timeline.size(), events.size(), counts["sent"].get<int>(),
                           counts["refreshed"].get<int>(), counts["switched-off"].get<int>(),
                           counts["spoken"].get<int>(), counts["interrupted"].get<int>(),
                           counts["rate-limited"].get<int>(), counts["duplicate"].get<int>(),
                           counts["expired"].get<int>());
  for (const std::string& s : spoken) std::cout << "  said: " << s << "\n";
  if (link) {
    const LinkReport r = link->report();
    std::cout << fmt::format("link {}: {} patterns and {} all-off sent, {} acknowledged, {} retransmitted, {} refused, "
                             "{} given up; link lost {} times\n",
                             a.port, r.patterns_sent, r.all_off_sent, r.acked, r.retransmits, r.naks, r.failed,
                             r.link_lost_events);
  }
  std::cout << fmt::format("wrote {}\n", a.out.string());
}

}  // namespace

void add_cues_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("cues", "Guidance timeline -> cues, actuator patterns, speech (docs/interaction.md)");
  auto a = std::make_shared<CuesArgs>();
  cmd->add_option("--guidance", a->guidance,
                  "Guidance timeline CSV (docs/interaction.md); repeat to merge several (a planner's and "
                  "navaid map's system_events.csv) on one clock")
      ->required();
  cmd->add_option("--device", a->device, "belt | hand | rumble | wheel")->required();
  cmd->add_option("--speech", a->speech, "on (synthesize, speech.wav) | text (no audio) | off");
  cmd->add_option("--out", a->out, "Output folder (cues.csv, cues.png, speech.wav, summary.json)")->required();
  cmd->add_option("--config", a->config_file, "YAML configuration (interaction.* keys)")->check(CLI::ExistingFile);
  cmd->add_option("--set", a->overrides, "Override a key, e.g. --set interaction.belt.intensity=low (repeatable)");
  cmd->add_flag("--no-figure", a->no_figure, "Skip cues.png");
  cmd->add_option("--port", a->port,
                  "Serial port of the vibration controller (e.g. /dev/ttyUSB0, or navaid device-sim's link): "
                  "plays the timeline out in real time and sends every pattern (docs/device-protocol.md)");
  cmd->add_option("--speed", a->speed, "With --port: play this many times faster than real time (default 1)");
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
