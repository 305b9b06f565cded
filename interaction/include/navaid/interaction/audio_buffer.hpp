#pragma once
// Mono 16-bit PCM audio: what speech synthesis produces, what voice recognition reads, what a WAV
// file holds. Plain samples so no audio library leaks into public headers.
#include <cstdint>
#include <vector>

namespace navaid::interaction {

struct AudioBuffer {
  int sample_rate_hz = 16000;
  std::vector<std::int16_t> samples;

  double duration_s() const {
    return sample_rate_hz > 0 ? static_cast<double>(samples.size()) / sample_rate_hz : 0.0;
  }
};

}  // namespace navaid::interaction
