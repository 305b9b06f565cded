#include "navaid/interaction/wav_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::interaction {

namespace {

constexpr std::uint16_t kFormatPcm = 1;
constexpr std::uint16_t kFormatExtensible = 0xFFFE;

std::uint16_t le16(const unsigned char* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t le32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

struct Format {
  std::uint16_t channels = 0;
  std::uint32_t rate = 0;
  std::uint16_t bits = 0;
  std::uint16_t block_align = 0;
};

Format parse_fmt(const std::string& name, const unsigned char* p, std::uint32_t size) {
  if (size < 16) throw IoError(name, fmt::format("fmt chunk of {} bytes is truncated (needs 16)", size));
  std::uint16_t tag = le16(p);
  Format f;
  f.channels = le16(p + 2);
  f.rate = le32(p + 4);
  f.block_align = le16(p + 12);
  f.bits = le16(p + 14);
  if (tag == kFormatExtensible) {
    // cbSize (2), valid bits (2), channel mask (4), sub-format GUID (16): its first two bytes are
    // the format tag.
    if (size < 40) throw IoError(name, fmt::format("WAVE_FORMAT_EXTENSIBLE fmt chunk of {} bytes is truncated (needs 40)", size));
    tag = le16(p + 24);
  }
  if (tag != kFormatPcm)
    throw IoError(name, fmt::format("unsupported WAVE format tag {:#06x} (only PCM, 0x0001, is read)", tag));
  if (f.channels == 0) throw IoError(name, "fmt chunk says 0 channels");
  if (f.rate == 0) throw IoError(name, "fmt chunk says a sample rate of 0 Hz");
  if (f.rate > 1'000'000) throw IoError(name, fmt::format("sample rate {} Hz is not audio", f.rate));
  if (f.bits != 8 && f.bits != 16)
    throw IoError(name, fmt::format("unsupported sample width of {} bits (8 and 16 are read)", f.bits));
  const unsigned expected_align = f.channels * (f.bits / 8u);
  if (f.block_align != expected_align)
    throw IoError(name, fmt::format("block align {} does not match {} channels of {} bits (expected {})",
                                    f.block_align, f.channels, f.bits, expected_align));
  return f;
}

void put16(std::string& out, std::uint16_t v) {
  out.push_back(static_cast<char>(v & 0xFF));
  out.push_back(static_cast<char>(v >> 8));
}
void put32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

double bessel_i0(double x) {
  // Power series; converges fast for the Kaiser window's argument range (|x| <= beta).
  double sum = 1.0;
  double term = 1.0;
  const double q = x * x / 4.0;
  for (int k = 1; k < 64; ++k) {
    term *= q / (static_cast<double>(k) * k);
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return sum;
}

}  // namespace

AudioBuffer read_wav(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw IoError(name, "cannot open WAV file");
  const std::streamoff length = in.tellg();
  if (length < 0) throw IoError(name, "cannot tell the file's size");
  std::string bytes(static_cast<std::size_t>(length), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), length)) throw IoError(name, "read failed");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t n = bytes.size();

  if (n < 12) {
    if (n >= 4 && std::memcmp(data, "RIFF", 4) != 0) throw IoError(name, "not a RIFF file (no 'RIFF' tag)");
    throw IoError(name, fmt::format("truncated RIFF header ({} bytes, needs 12)", n));
  }
  if (std::memcmp(data, "RIFF", 4) != 0) throw IoError(name, "not a RIFF file (no 'RIFF' tag)");
  if (std::memcmp(data + 8, "WAVE", 4) != 0) throw IoError(name, "RIFF file is not WAVE (no 'WAVE' form type)");
  const std::uint64_t riff_end = 8 + static_cast<std::uint64_t>(le32(data + 4));
  if (riff_end > n)
    throw IoError(name, fmt::format("RIFF size says {} bytes but the file has {} (truncated)", riff_end, n));

  std::optional<Format> format;
  std::size_t pos = 12;
  while (true) {
    if (pos + 8 > riff_end) {
      if (pos < riff_end) throw IoError(name, fmt::format("truncated chunk header at byte {}", pos));
      break;
    }
    const std::string id(reinterpret_cast<const char*>(data + pos), 4);
    const std::uint32_t size = le32(data + pos + 4);
    const std::size_t body = pos + 8;
    const bool beyond = body + static_cast<std::uint64_t>(size) > riff_end;
    if (id == "data") {
      if (!format) throw IoError(name, "data chunk comes before the fmt chunk");
      if (beyond)
        throw IoError(name, fmt::format("truncated data: data chunk says {} bytes, {} remain in the file", size,
                                        riff_end - body));
      if (size % format->block_align != 0)
        throw IoError(name, fmt::format("truncated data: {} bytes is not a whole number of {}-byte frames", size,
                                        format->block_align));
      AudioBuffer out;
      out.sample_rate_hz = static_cast<int>(format->rate);
      const std::size_t frames = size / format->block_align;
      out.samples.resize(frames);
      const unsigned char* p = data + body;
      for (std::size_t i = 0; i < frames; ++i) {
        long sum = 0;
        for (unsigned c = 0; c < format->channels; ++c) {
          if (format->bits == 16) {
            sum += static_cast<std::int16_t>(le16(p));
            p += 2;
          } else {
            sum += (static_cast<int>(*p) - 128) * 256;  // 8-bit WAV is unsigned, 128 = 0
            p += 1;
          }
        }
        // Round half away from zero so an average of identical channels is exact.
        const double mean = static_cast<double>(sum) / format->channels;
        out.samples[i] = static_cast<std::int16_t>(std::lround(mean));
      }
      return out;
    }
    if (beyond)
      throw IoError(name, fmt::format("'{}' chunk at byte {} says {} bytes, beyond the end of the file ({} bytes)",
                                      id, pos, size, riff_end));
    if (id == "fmt ") {
      if (format) throw IoError(name, "second fmt chunk");
      format = parse_fmt(name, data + body, size);
    }
    // Unknown chunks (LIST, fact, cue, ...) are skipped; chunks are padded to an even size.
    pos = body + size + (size & 1u);
  }
  if (!format) throw IoError(name, "no fmt chunk");
  throw IoError(name, "no data chunk");
}

void write_wav(const std::filesystem::path& file, const AudioBuffer& audio) {
  const std::string name = file.string();
  if (audio.sample_rate_hz <= 0)
    throw IoError(name, fmt::format("cannot write a WAV file at a sample rate of {} Hz", audio.sample_rate_hz));
  const std::uint64_t data_bytes = 2 * static_cast<std::uint64_t>(audio.samples.size());
  if (data_bytes > 0xFFFFFFFFull - 36) throw IoError(name, "audio too long for a RIFF file (4 GiB)");
  std::string out;
  out.reserve(44 + data_bytes);
  out += "RIFF";
  put32(out, static_cast<std::uint32_t>(36 + data_bytes));
  out += "WAVEfmt ";
  put32(out, 16);
  put16(out, kFormatPcm);
  put16(out, 1);
  put32(out, static_cast<std::uint32_t>(audio.sample_rate_hz));
  put32(out, static_cast<std::uint32_t>(audio.sample_rate_hz) * 2);
  put16(out, 2);
  put16(out, 16);
  out += "data";
  put32(out, static_cast<std::uint32_t>(data_bytes));
  for (const std::int16_t s : audio.samples) put16(out, static_cast<std::uint16_t>(s));
  std::ofstream f(file, std::ios::binary | std::ios::trunc);
  if (!f) throw IoError(name, "cannot open for writing");
  f.write(out.data(), static_cast<std::streamsize>(out.size()));
  f.close();
  if (!f) throw IoError(name, "write failed");
}

AudioBuffer resample(const AudioBuffer& audio, int rate_hz) {
  if (rate_hz <= 0) throw std::invalid_argument(fmt::format("resample: target rate {} Hz is not positive", rate_hz));
  if (audio.sample_rate_hz <= 0)
    throw std::invalid_argument(fmt::format("resample: source rate {} Hz is not positive", audio.sample_rate_hz));
  if (rate_hz == audio.sample_rate_hz) return audio;
  const auto in_rate = static_cast<std::int64_t>(audio.sample_rate_hz);
  const auto out_rate = static_cast<std::int64_t>(rate_hz);
  const std::vector<std::int16_t>& x = audio.samples;
  const auto in_n = static_cast<std::int64_t>(x.size());

  // All in units of input samples. fc: cut-off in cycles per input sample.
  constexpr double kZeroCrossings = 16.0;
  constexpr double kBeta = 8.0;  // Kaiser beta: about 80 dB stop-band
  const double ratio = static_cast<double>(out_rate) / static_cast<double>(in_rate);
  const double fc = 0.5 * std::min(1.0, ratio) * (ratio < 1.0 ? 0.95 : 1.0);
  const double half_width = kZeroCrossings / (2.0 * fc);
  const double i0_beta = bessel_i0(kBeta);

  AudioBuffer out;
  out.sample_rate_hz = rate_hz;
  const std::int64_t out_n = in_n * out_rate / in_rate;
  out.samples.resize(static_cast<std::size_t>(out_n));
  for (std::int64_t m = 0; m < out_n; ++m) {
    const double t = static_cast<double>(m * in_rate) / static_cast<double>(out_rate);  // exact up to double
    const auto k0 = static_cast<std::int64_t>(std::ceil(t - half_width));
    const auto k1 = static_cast<std::int64_t>(std::floor(t + half_width));
    double acc = 0.0;
    for (std::int64_t k = std::max<std::int64_t>(0, k0); k <= std::min(in_n - 1, k1); ++k) {
      const double d = t - static_cast<double>(k);
      const double r = d / half_width;
      const double w = bessel_i0(kBeta * std::sqrt(std::max(0.0, 1.0 - r * r))) / i0_beta;
      const double arg = 2.0 * fc * d;
      const double sinc = std::abs(arg) < 1e-12 ? 1.0 : std::sin(M_PI * arg) / (M_PI * arg);
      acc += static_cast<double>(x[static_cast<std::size_t>(k)]) * 2.0 * fc * sinc * w;
    }
    // A band-limited signal near full scale can overshoot by a few LSB (Gibbs); saturate it.
    out.samples[static_cast<std::size_t>(m)] = static_cast<std::int16_t>(std::clamp(std::lround(acc), -32768L, 32767L));
  }
  return out;
}

AudioBuffer pad_with_silence(const AudioBuffer& audio, double seconds) {
  if (!(seconds >= 0.0)) throw std::invalid_argument("pad_with_silence: the length must not be negative");
  AudioBuffer out;
  out.sample_rate_hz = audio.sample_rate_hz;
  const auto pad = static_cast<std::size_t>(std::lround(seconds * audio.sample_rate_hz));
  out.samples.reserve(audio.samples.size() + 2 * pad);
  out.samples.assign(pad, 0);
  out.samples.insert(out.samples.end(), audio.samples.begin(), audio.samples.end());
  out.samples.insert(out.samples.end(), pad, 0);
  return out;
}

}  // namespace navaid::interaction
