// Voice commands (pocketsphinx keyword grammar + word-loop rejection) on espeak-ng speech:
// decode time per utterance, and the recognition study: per voice and signal-to-noise ratio (white
// noise, fixed seed) the share of the 7 commands recognised correctly, and the share of 6 other
// sentences falsely accepted. Prints the table that docs/interaction-voice.md quotes.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "navaid/interaction/speech_synthesizer.hpp"
#include "navaid/interaction/voice_command.hpp"
#include "navaid/interaction/wav_file.hpp"

namespace {

using namespace navaid::interaction;

const std::vector<std::string> kPlaces{"kitchen", "main entrance", "bus stop", "library"};
const std::vector<std::string> kCommands{"go to kitchen", "go to main entrance", "go to bus stop", "go to library",
                                         "repeat", "where am i", "stop guidance"};
const std::vector<std::string> kOther{"the weather is nice today", "what time is it", "call my sister",
                                      "turn on the light", "hello", "thank you very much"};
const std::vector<std::string> kVoices{"en", "en-us", "en-gb-x-rp", "en+m3", "en+f3", "en+f5"};

AudioBuffer padded(const AudioBuffer& a) { return pad_with_silence(a, 0.3); }

/// White noise at `snr_db` below the speech's power (measured over the speech samples).
AudioBuffer with_noise(const AudioBuffer& a, double snr_db, std::mt19937& rng) {
  if (!std::isfinite(snr_db)) return a;
  double power = 0.0;
  std::size_t n = 0;
  for (const std::int16_t s : a.samples) {
    if (s != 0) {
      power += static_cast<double>(s) * s;
      ++n;
    }
  }
  const double sigma = std::sqrt(power / std::max<std::size_t>(n, 1) / std::pow(10.0, snr_db / 10.0));
  std::normal_distribution<double> noise(0.0, sigma);
  AudioBuffer out = a;
  for (auto& s : out.samples) s = static_cast<std::int16_t>(std::clamp(s + noise(rng), -32768.0, 32767.0));
  return out;
}

void BM_RecognizeCommand(benchmark::State& state) {
  VoiceCommandRecognizer rec(kPlaces);
  SpeechConfig c;
  c.voice = "en+f5";
  const AudioBuffer a = padded(SpeechSynthesizer(c).synthesize("go to main entrance"));
  for (auto _ : state) benchmark::DoNotOptimize(rec.recognize(a));
  state.counters["audio_s"] = a.duration_s();
  state.counters["rtf"] = benchmark::Counter(a.duration_s(), benchmark::Counter::kIsIterationInvariantRate |
                                                                 benchmark::Counter::kInvert);
}
BENCHMARK(BM_RecognizeCommand)->Unit(benchmark::kMillisecond)->Iterations(10);

void BM_RecognitionStudy(benchmark::State& state) {
  VoiceCommandRecognizer rec(kPlaces);
  const std::vector<double> snrs{INFINITY, 20.0, 10.0, 5.0, 0.0};
  for (auto _ : state) {
    std::printf("\nvoice        | commands recognised at SNR clean / 20 / 10 / 5 / 0 dB | other speech accepted (clean)\n");
    std::vector<int> total(snrs.size(), 0);
    int other_total = 0;
    for (const std::string& voice : kVoices) {
      SpeechConfig c;
      c.voice = voice;
      const SpeechSynthesizer synth(c);
      std::mt19937 rng(42);
      std::printf("%-12s |", voice.c_str());
      for (std::size_t k = 0; k < snrs.size(); ++k) {
        int ok = 0;
        for (const std::string& command : kCommands) {
          ok += describe(rec.recognize(with_noise(padded(synth.synthesize(command)), snrs[k], rng))) == command;
        }
        total[k] += ok;
        std::printf(" %d/7", ok);
      }
      int other = 0;
      for (const std::string& s : kOther) other += rec.recognize(padded(synth.synthesize(s))).kind != VoiceCommand::Kind::kNotUnderstood;
      other_total += other;
      std::printf(" | %d/6\n", other);
    }
    std::printf("all          |");
    for (const int t : total) std::printf(" %.0f%%", 100.0 * t / (7.0 * kVoices.size()));
    std::printf(" | %.0f%%\n", 100.0 * other_total / (6.0 * kVoices.size()));
  }
}
BENCHMARK(BM_RecognitionStudy)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
