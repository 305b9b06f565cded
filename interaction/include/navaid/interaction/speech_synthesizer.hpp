#pragma once
// Speech synthesis with espeak-ng (thirdparty-notes/espeak-ng.md): text in, mono 16-bit PCM out
// at espeak-ng's 22050 Hz. eLabrador speaks route, action and system information through a bone
// conduction headset; W-ROMA a voice command every 2 s. The text comes from message_templates.hpp.
//
// espeak-ng keeps global state (one voice, one set of parameters, one callback per process): the
// engine is initialised once per process, on first use, and every call into it is serialized
// behind one mutex, so any number of SpeechSynthesizer objects with different voices may be used
// from any threads. espeak-ng's headers stay in the .cpp.
//
// espeak-ng carries state from one utterance to the next (pitch flutter, wave phase), so the
// same text synthesized twice differs slightly (a few samples in length). Each synthesizer keeps
// the audio of the last texts it spoke (kSpeechCacheEntries, shared by its copies): the same text
// then gives the same samples, duration_s() equals the samples / rate that synthesize() returns,
// and a repeated message ("Stop!", "prepare to turn left") costs a copy instead of a synthesis.
//
// Text-only mode (interaction.speech.mode: text) synthesizes nothing and needs no espeak-ng data:
// synthesize() returns an empty buffer and duration_s() is the estimate
//   duration_s = 12 * (units + 1) / rate_wpm        (0 for blank text)
// in fifths of a word (60 s/min over the typist's five-character word): a letter counts 1 unit,
// a digit 4 (digits are read as words, "49" -> "forty nine"), a pause mark (. , ; : ! ?) with
// more text after it 4, white space and final punctuation nothing; the +1 is the utterance's
// end. Against espeak-ng 1.51's "en" voice on the message templates, at 100..450 wpm, it is
// within 25 % of the synthesized length. So the scheduler still knows when a message ends.
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/interaction/audio_buffer.hpp"

namespace navaid {
class Config;
}

namespace navaid::interaction {

/// espeak-ng's output sample rate.
inline constexpr int kSpeechSampleRateHz = 22050;
/// How many texts' audio a synthesizer keeps (the oldest is dropped first).
inline constexpr std::size_t kSpeechCacheEntries = 64;

struct SpeechConfig {
  /// Template language ("en", "de"): message_templates.hpp.
  std::string language = "en";
  /// espeak-ng voice name ("en", "en-us", "en+f3", "de"); empty means default_voice(language).
  std::string voice;
  /// Speaking rate in words per minute, [80, 450].
  int rate_wpm = 175;
  /// Base pitch, [0, 99].
  int pitch = 50;
  /// No synthesis: durations are the text-only estimate (see above).
  bool text_only = false;
};

/// Reads interaction.speech.language (default "en", "en" or "de"),
/// interaction.speech.voice (default: default_voice(language)), interaction.speech.rate_wpm
/// [80, 450] default 175, interaction.speech.pitch [0, 99] default 50 and
/// interaction.speech.mode "audio" (default) | "text". Throws ConfigError on a bad value.
SpeechConfig read_speech_config(const Config& config);

/// The espeak-ng voice for a template language ("en" -> "en", "de" -> "de"; otherwise the
/// language itself).
std::string default_voice(std::string_view language);

/// The text-only duration estimate [s] (formula above); rate_wpm must be positive.
double estimate_speech_duration_s(std::string_view text, int rate_wpm);

class SpeechSynthesizer {
 public:
  /// Checks the configuration (rate and pitch ranges) and, unless text-only, initialises espeak-ng
  /// (once per process) and selects the voice: throws ConfigError (key interaction.speech.voice)
  /// when espeak-ng cannot start (no data) or does not know the voice.
  explicit SpeechSynthesizer(SpeechConfig config);

  /// The text spoken with this synthesizer's voice, rate and pitch at kSpeechSampleRateHz; an
  /// empty buffer (at that rate) in text-only mode or for blank text. Text is UTF-8. From the
  /// cache when this synthesizer spoke the text lately. Thread-safe.
  AudioBuffer synthesize(std::string_view text) const;
  /// synthesize() without the cache: always runs espeak-ng (benchmarks, fresh test speech).
  AudioBuffer synthesize_uncached(std::string_view text) const;
  /// How long the text lasts when spoken [s]: samples / rate of synthesize(), or the text-only
  /// estimate in text-only mode.
  double duration_s(std::string_view text) const;

  const SpeechConfig& config() const { return config_; }

 private:
  struct Cache;
  SpeechConfig config_;
  std::shared_ptr<Cache> cache_;
};

/// espeak-ng's voice names (espeak_ListVoices), sorted; only those speaking `language` (an espeak
/// language code such as "en" or "de", matching "en-us" too) when it is not empty. Throws
/// ConfigError when espeak-ng cannot start.
std::vector<std::string> available_voices(std::string_view language = "");

}  // namespace navaid::interaction
