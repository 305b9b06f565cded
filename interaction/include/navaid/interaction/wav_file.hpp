#pragma once
// RIFF/WAVE files for AudioBuffer, and sample-rate conversion between the synthesizer's and the
// recognizer's rates.
#include <filesystem>

#include "navaid/interaction/audio_buffer.hpp"

namespace navaid::interaction {

/// Reads a RIFF/WAVE PCM file: 16-bit or 8-bit (unsigned) samples, any number of channels (averaged
/// into mono), format tag PCM (1) or WAVE_FORMAT_EXTENSIBLE with the PCM sub-format. Unknown chunks
/// (LIST, fact, cue, ...) are skipped. Throws IoError naming the file when it cannot be opened, is
/// not RIFF/WAVE, has a truncated header or data, a chunk size beyond the end of the file, an
/// unsupported format tag or sample width, zero channels or a zero sample rate, or no fmt/data chunk.
AudioBuffer read_wav(const std::filesystem::path& file);

/// Writes a 16-bit mono PCM RIFF/WAVE file (44-byte header, little-endian). Throws IoError naming
/// the file when it cannot be written or the buffer's rate is not positive.
void write_wav(const std::filesystem::path& file, const AudioBuffer& audio);

/// Windowed-sinc (Kaiser, 16 zero crossings each side) conversion to `rate_hz`. Going down, the
/// low-pass cuts at 0.95 of the new Nyquist so nothing above it aliases back into the speech band
/// (linear interpolation would fold 8-11 kHz fricative energy of 22050 Hz speech into 5-8 kHz).
/// Same rate returns a copy. Throws std::invalid_argument on a non-positive rate.
AudioBuffer resample(const AudioBuffer& audio, int rate_hz);

/// `audio` with `seconds` of digital silence before and after it (an utterance as a microphone
/// segment would hold it). Throws std::invalid_argument on a negative length.
AudioBuffer pad_with_silence(const AudioBuffer& audio, double seconds);

}  // namespace navaid::interaction
