// navaid listen: one spoken command from a WAV file (or a live audio source) through the
// pocketsphinx keyword grammar: prints what was recognised ("go to kitchen", "repeat", ... or "not
// understood") with its score; with --out writes result.json and voice_event.csv, a guidance
// timeline with the command as a voice_command event for `navaid cues`.
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/interaction/voice_command.hpp"
#include "navaid/interaction/wav_file.hpp"

namespace navaid::cli {

namespace {

using namespace navaid::interaction;

struct ListenArgs {
  std::filesystem::path wav;
  std::string device;
  double seconds = 3.0;
  bool live = false;
  std::string places;
  std::filesystem::path out;
  double at_s = 0.0;
  double min_score = VoiceRecognizerConfig{}.min_score;
};

std::vector<std::string> split_places(const std::string& list) {
  std::vector<std::string> places;
  std::stringstream in(list);
  for (std::string p; std::getline(in, p, ',');) places.push_back(p);
  return places;
}

int run(const ListenArgs& a) {
  if (a.wav.empty() == !a.live) throw UsageError("give either --wav FILE or --device NAME (a live audio source)");
  VoiceRecognizerConfig config;
  config.min_score = a.min_score;
  VoiceCommandRecognizer recognizer(split_places(a.places), config);
  const AudioBuffer audio = a.live ? record_from_device(a.device, a.seconds) : read_wav(a.wav);
  const VoiceCommand c = recognizer.recognize(audio);
  const bool understood = c.kind != VoiceCommand::Kind::kNotUnderstood;
  std::cout << describe(c);
  if (!c.heard.empty()) std::cout << fmt::format("  (heard \"{}\", score {:.3f}, threshold {:.3f})", c.heard, c.score, a.min_score);
  std::cout << "\n";
  if (!a.out.empty()) {
    std::filesystem::create_directories(a.out);
    nlohmann::ordered_json j = {{"input", a.live ? "device:" + a.device : a.wav.string()},
                                {"audio_s", audio.duration_s()},
                                {"places", recognizer.places()},
                                {"command", std::string(to_string(c.kind))},
                                {"said", describe(c)},
                                {"place", c.place},
                                {"heard", c.heard},
                                {"score", std::isfinite(c.score) ? nlohmann::ordered_json(c.score) : nlohmann::ordered_json()},
                                {"min_score", a.min_score},
                                {"grammar", recognizer.grammar()}};
    std::ofstream(a.out / "result.json") << j.dump(2) << "\n";
    std::vector<GuidanceTimelineEntry> timeline;
    if (understood) timeline.emplace_back(SystemEvent{seconds_to_ns(a.at_s), SystemEventKind::kVoiceCommand, describe(c)});
    write_guidance_timeline_csv(a.out / "voice_event.csv", timeline);
  }
  return understood ? 0 : 3;
}

}  // namespace

void add_listen_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "listen", "Recognise one voice command (go to <place>, repeat, where am i, stop guidance) from a WAV or a live source");
  auto a = std::make_shared<ListenArgs>();
  cmd->add_option("--wav", a->wav, "WAV file (mono or stereo 16-bit PCM, any rate)")->check(CLI::ExistingFile);
  cmd->add_option("--device", a->device, "Record from this PulseAudio source instead (empty string: the default)")
      ->each([a](const std::string&) { a->live = true; });
  cmd->add_option("--seconds", a->seconds, "With --device: how long to record (default 3)");
  cmd->add_option("--places", a->places, "Comma-separated place names for \"go to <place>\" (e.g. \"kitchen,bus stop\")");
  cmd->add_option("--out", a->out, "Write result.json and voice_event.csv (a guidance timeline for navaid cues) here");
  cmd->add_option("--at", a->at_s, "Time of the voice_command event in voice_event.csv [s] (default 0)");
  cmd->add_option("--min-score", a->min_score, "Rejection threshold [nats per second of speech] (docs/interaction-voice.md)");
  cmd->callback([a] {
    const int status = run(*a);
    if (status != 0) throw CLI::RuntimeError(status);
  });
}

}  // namespace navaid::cli
