#pragma once
// Everything a session said as one audio track: each spoken message at its start on the
// timeline's clock, cut where it was interrupted (speech.wav of navaid cues and of a full-device run).
#include <vector>

#include "navaid/core/time.hpp"
#include "navaid/interaction/audio_buffer.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/interaction/synthesized_speech.hpp"

namespace navaid::interaction {

/// The spoken events from `t0` on, mixed (later messages overwrite the overlap of earlier ones).
AudioBuffer mix_spoken_audio(const std::vector<CueEvent>& events, const SynthesizedSpeech& speech, Timestamp t0);

}  // namespace navaid::interaction
