#include "navaid/interaction/speech_mix.hpp"

#include <algorithm>

namespace navaid::interaction {

AudioBuffer mix_spoken_audio(const std::vector<CueEvent>& events, const SynthesizedSpeech& speech, Timestamp t0) {
  AudioBuffer mix;
  mix.sample_rate_hz = speech.sample_rate_hz();
  const std::size_t rate = static_cast<std::size_t>(mix.sample_rate_hz);
  for (std::size_t i = 0; i < events.size(); ++i) {
    const CueEvent& e = events[i];
    if (e.outcome != CueOutcome::kSpoken || e.t < t0) continue;
    AudioBuffer audio = speech.audio(e.text);
    for (std::size_t j = i + 1; j < events.size(); ++j) {
      const CueEvent& end = events[j];
      if (end.channel == CueChannel::kSpeech &&
          (end.outcome == CueOutcome::kInterrupted || end.outcome == CueOutcome::kFinished)) {
        const auto keep = static_cast<std::size_t>(ns_to_seconds(end.t - e.t) * mix.sample_rate_hz);
        if (audio.samples.size() > keep) audio.samples.resize(keep);
        break;
      }
    }
    const auto start = static_cast<std::size_t>(ns_to_seconds(e.t - t0) * static_cast<double>(rate));
    if (mix.samples.size() < start + audio.samples.size()) mix.samples.resize(start + audio.samples.size(), 0);
    std::copy(audio.samples.begin(), audio.samples.end(), mix.samples.begin() + static_cast<std::ptrdiff_t>(start));
  }
  return mix;
}

}  // namespace navaid::interaction
