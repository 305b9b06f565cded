#pragma once
// The scheduler's SpeechRenderer for a device: message templates in the configured language,
// spoken by espeak-ng (or, in text-only mode, only timed by the duration estimate). The scheduler
// learns each message's length from here, and `navaid cues` takes its audio for speech.wav.
#include <string>

#include "navaid/interaction/audio_buffer.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/interaction/speech_synthesizer.hpp"

namespace navaid::interaction {

class SynthesizedSpeech final : public SpeechRenderer {
 public:
  /// Throws what SpeechSynthesizer throws, and ConfigError (interaction.speech.language) for a
  /// language without message templates.
  explicit SynthesizedSpeech(SpeechConfig config);

  /// render_message() in the configured language.
  std::string text(const SpokenMessage& message) const override;
  /// The synthesized length of `text` (the text-only estimate in text-only mode).
  double duration_s(const SpokenMessage& message, const std::string& text) const override;
  /// The audio of `text`: the same samples duration_s() measured (empty in text-only mode).
  AudioBuffer audio(const std::string& text) const { return synthesizer_.synthesize(text); }

  int sample_rate_hz() const { return kSpeechSampleRateHz; }
  const SpeechConfig& config() const { return synthesizer_.config(); }

 private:
  SpeechSynthesizer synthesizer_;
};

}  // namespace navaid::interaction
