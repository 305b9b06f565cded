// WAV reading and writing: round trips, stereo and 8-bit files, skipped chunks, and one corrupt
// file for every error the reader raises; windowed-sinc resampling (length, tone preserved,
// aliasing suppressed).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/interaction/wav_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::IoError;
using navaid::interaction::AudioBuffer;
using navaid::interaction::read_wav;
using navaid::interaction::resample;
using navaid::interaction::write_wav;
using navaid::testing::error_message;
using navaid::testing::ScratchDir;

namespace {

constexpr double kPi = 3.14159265358979323846;

void put16(std::string& s, unsigned v) {
  s.push_back(static_cast<char>(v & 0xFF));
  s.push_back(static_cast<char>((v >> 8) & 0xFF));
}
void put32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

std::string chunk(const std::string& id, const std::string& body, std::uint32_t declared_size) {
  std::string s = id;
  put32(s, declared_size);
  s += body;
  return s;
}
std::string chunk(const std::string& id, const std::string& body) {
  std::string s = chunk(id, body, static_cast<std::uint32_t>(body.size()));
  if (body.size() % 2) s.push_back('\0');
  return s;
}

std::string fmt_body(unsigned tag, unsigned channels, std::uint32_t rate, unsigned bits) {
  std::string s;
  put16(s, tag);
  put16(s, channels);
  put32(s, rate);
  put32(s, rate * channels * bits / 8);
  put16(s, channels * bits / 8);
  put16(s, bits);
  return s;
}

std::string riff(const std::string& chunks) {
  std::string s = "RIFF";
  put32(s, static_cast<std::uint32_t>(4 + chunks.size()));
  return s + "WAVE" + chunks;
}

std::string samples16(const std::vector<int>& v) {
  std::string s;
  for (const int x : v) put16(s, static_cast<unsigned>(static_cast<std::uint16_t>(x)));
  return s;
}

fs::path write_bytes(const ScratchDir& dir, const std::string& name, const std::string& bytes) {
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

/// The error message, which must name the file.
std::string wav_error(const fs::path& p) {
  const std::string m = error_message<IoError>([&] { read_wav(p); }, p.string());
  EXPECT_NE(m.find(p.string()), std::string::npos) << m;
  return m;
}

AudioBuffer tone(int rate, double hz, double seconds, double amplitude) {
  AudioBuffer a;
  a.sample_rate_hz = rate;
  const auto n = static_cast<std::size_t>(seconds * rate);
  for (std::size_t i = 0; i < n; ++i)
    a.samples.push_back(static_cast<std::int16_t>(std::lround(amplitude * std::sin(2 * kPi * hz * i / rate))));
  return a;
}

/// RMS of the middle half (away from the filter's edge effects).
double rms_middle(const AudioBuffer& a) {
  const std::size_t n = a.samples.size();
  double s = 0;
  std::size_t count = 0;
  for (std::size_t i = n / 4; i < 3 * n / 4; ++i, ++count) s += static_cast<double>(a.samples[i]) * a.samples[i];
  return std::sqrt(s / static_cast<double>(count));
}

}  // namespace

TEST(WavFile, RoundTripIsExact) {
  ScratchDir dir("wav_roundtrip");
  AudioBuffer a;
  a.sample_rate_hz = 22050;
  a.samples = {0, 1, -1, 32767, -32768, 12345, -54, 7};
  write_wav(dir / "a.wav", a);
  EXPECT_EQ(fs::file_size(dir / "a.wav"), 44u + 2 * a.samples.size());
  const AudioBuffer b = read_wav(dir / "a.wav");
  EXPECT_EQ(b.sample_rate_hz, 22050);
  EXPECT_EQ(b.samples, a.samples);
}

TEST(WavFile, EmptyBufferRoundTrips) {
  ScratchDir dir("wav_empty");
  AudioBuffer a;
  a.sample_rate_hz = 16000;
  write_wav(dir / "e.wav", a);
  const AudioBuffer b = read_wav(dir / "e.wav");
  EXPECT_EQ(b.sample_rate_hz, 16000);
  EXPECT_TRUE(b.samples.empty());
}

TEST(WavFile, HeaderIsTheCanonical44Bytes) {
  ScratchDir dir("wav_header");
  AudioBuffer a;
  a.sample_rate_hz = 16000;
  a.samples = {1, 2};
  write_wav(dir / "h.wav", a);
  const std::string expected = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)) + chunk("data", samples16({1, 2})));
  EXPECT_EQ(navaid::testing::read_text(dir / "h.wav"), expected);
}

TEST(WavFile, StereoIsAveraged) {
  ScratchDir dir("wav_stereo");
  const fs::path p = write_bytes(dir, "s.wav",
                                 riff(chunk("fmt ", fmt_body(1, 2, 44100, 16)) +
                                      chunk("data", samples16({100, 200, -1000, 1000, 32767, 32767, -3, -4}))));
  const AudioBuffer a = read_wav(p);
  EXPECT_EQ(a.sample_rate_hz, 44100);
  EXPECT_EQ(a.samples, (std::vector<std::int16_t>{150, 0, 32767, -4}));  // -3.5 rounds away from zero
}

TEST(WavFile, EightBitIsUnsignedAndScaled) {
  ScratchDir dir("wav_8bit");
  const std::string data = {static_cast<char>(128), static_cast<char>(255), static_cast<char>(0)};
  const fs::path p = write_bytes(dir, "u8.wav", riff(chunk("fmt ", fmt_body(1, 1, 8000, 8)) + chunk("data", data)));
  const AudioBuffer a = read_wav(p);
  EXPECT_EQ(a.sample_rate_hz, 8000);
  EXPECT_EQ(a.samples, (std::vector<std::int16_t>{0, 127 * 256, -128 * 256}));
}

TEST(WavFile, SkipsUnknownAndOddSizedChunks) {
  ScratchDir dir("wav_list");
  const fs::path p = write_bytes(dir, "l.wav",
                                 riff(chunk("LIST", "INFOISFT\x05\0\0\0navai") + chunk("fmt ", fmt_body(1, 1, 16000, 16)) +
                                      chunk("fact", "abc") + chunk("data", samples16({5, -5})) + chunk("LIST", "xy")));
  const AudioBuffer a = read_wav(p);
  EXPECT_EQ(a.samples, (std::vector<std::int16_t>{5, -5}));
}

TEST(WavFile, ReadsExtensiblePcm) {
  ScratchDir dir("wav_ext");
  std::string body = fmt_body(0xFFFE, 1, 16000, 16);
  put16(body, 22);     // cbSize
  put16(body, 16);     // valid bits
  put32(body, 0x4);    // channel mask
  put16(body, 1);      // sub-format GUID starts with the PCM tag
  body += std::string("\x00\x00\x00\x00\x10\x00\x80\x00\x00\xAA\x00\x38\x9B\x71", 14);
  const fs::path p = write_bytes(dir, "x.wav", riff(chunk("fmt ", body) + chunk("data", samples16({9}))));
  EXPECT_EQ(read_wav(p).samples, (std::vector<std::int16_t>{9}));
}

TEST(WavFileErrors, MissingFile) {
  ScratchDir dir("wav_missing");
  EXPECT_NE(wav_error(dir / "nope.wav").find("cannot open"), std::string::npos);
}

TEST(WavFileErrors, NotRiff) {
  ScratchDir dir("wav_notriff");
  EXPECT_NE(wav_error(write_bytes(dir, "t.wav", "hello, this is text not audio")).find("not a RIFF"), std::string::npos);
  EXPECT_NE(wav_error(write_bytes(dir, "short.wav", "OggS")).find("not a RIFF"), std::string::npos);
  std::string avi = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)));
  avi.replace(8, 4, "AVI ");
  EXPECT_NE(wav_error(write_bytes(dir, "avi.wav", avi)).find("not WAVE"), std::string::npos);
}

TEST(WavFileErrors, EmptyAndTruncatedRiffHeader) {
  ScratchDir dir("wav_trunc_header");
  EXPECT_NE(wav_error(write_bytes(dir, "empty.wav", "")).find("truncated RIFF header"), std::string::npos);
  EXPECT_NE(wav_error(write_bytes(dir, "r.wav", "RIFF\x04\0\0")).find("truncated RIFF header"), std::string::npos);
}

TEST(WavFileErrors, RiffSizeBeyondFile) {
  ScratchDir dir("wav_riff_size");
  std::string good = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)) + chunk("data", samples16({1, 2})));
  good.resize(good.size() - 2);  // cut the file short, header unchanged
  EXPECT_NE(wav_error(write_bytes(dir, "cut.wav", good)).find("truncated"), std::string::npos);
}

TEST(WavFileErrors, TruncatedChunkHeader) {
  ScratchDir dir("wav_chunk_header");
  const std::string bytes = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)) + "dat");
  EXPECT_NE(wav_error(write_bytes(dir, "c.wav", bytes)).find("truncated chunk header"), std::string::npos);
}

TEST(WavFileErrors, TruncatedFmtChunk) {
  ScratchDir dir("wav_fmt_short");
  const std::string bytes = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16).substr(0, 14)) + chunk("data", ""));
  EXPECT_NE(wav_error(write_bytes(dir, "f.wav", bytes)).find("fmt chunk of 14 bytes is truncated"), std::string::npos);
  const std::string ext = riff(chunk("fmt ", fmt_body(0xFFFE, 1, 16000, 16)) + chunk("data", ""));
  EXPECT_NE(wav_error(write_bytes(dir, "e.wav", ext)).find("EXTENSIBLE"), std::string::npos);
}

TEST(WavFileErrors, TruncatedData) {
  ScratchDir dir("wav_data_short");
  // data chunk declares 8 bytes, only 4 are there (RIFF size consistent with the file)
  const std::string bytes = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)) + chunk("data", samples16({1, 2}), 8));
  EXPECT_NE(wav_error(write_bytes(dir, "d.wav", bytes)).find("truncated data"), std::string::npos);
  // partial frame: 3 bytes of 16-bit mono
  const std::string odd = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)) + chunk("data", std::string("\1\0\2", 3)));
  EXPECT_NE(wav_error(write_bytes(dir, "o.wav", odd)).find("whole number of 2-byte frames"), std::string::npos);
}

TEST(WavFileErrors, ChunkSizeBeyondFile) {
  ScratchDir dir("wav_chunk_size");
  const std::string bytes = riff(chunk("LIST", "abcd", 1000) + chunk("fmt ", fmt_body(1, 1, 16000, 16)));
  const std::string m = wav_error(write_bytes(dir, "l.wav", bytes));
  EXPECT_NE(m.find("'LIST' chunk"), std::string::npos) << m;
  EXPECT_NE(m.find("beyond the end"), std::string::npos) << m;
  const std::string huge = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)) + chunk("data", "", 0xFFFFFFF0u));
  EXPECT_NE(wav_error(write_bytes(dir, "h.wav", huge)).find("truncated data"), std::string::npos);
}

TEST(WavFileErrors, UnsupportedFormatAndBits) {
  ScratchDir dir("wav_unsupported");
  const std::string flt = riff(chunk("fmt ", fmt_body(3, 1, 16000, 32)) + chunk("data", ""));
  EXPECT_NE(wav_error(write_bytes(dir, "f.wav", flt)).find("format tag 0x0003"), std::string::npos);
  const std::string b24 = riff(chunk("fmt ", fmt_body(1, 1, 16000, 24)) + chunk("data", ""));
  EXPECT_NE(wav_error(write_bytes(dir, "b.wav", b24)).find("24 bits"), std::string::npos);
  std::string align = fmt_body(1, 2, 16000, 16);
  align[12] = 3;  // block align 3 for 2 x 16 bit
  EXPECT_NE(wav_error(write_bytes(dir, "a.wav", riff(chunk("fmt ", align) + chunk("data", "")))).find("block align"),
            std::string::npos);
}

TEST(WavFileErrors, ZeroChannelsOrRate) {
  ScratchDir dir("wav_zero");
  const std::string ch = riff(chunk("fmt ", fmt_body(1, 0, 16000, 16)) + chunk("data", ""));
  EXPECT_NE(wav_error(write_bytes(dir, "c.wav", ch)).find("0 channels"), std::string::npos);
  const std::string rate = riff(chunk("fmt ", fmt_body(1, 1, 0, 16)) + chunk("data", ""));
  EXPECT_NE(wav_error(write_bytes(dir, "r.wav", rate)).find("sample rate of 0 Hz"), std::string::npos);
}

TEST(WavFileErrors, MissingOrMisplacedChunks) {
  ScratchDir dir("wav_chunks");
  EXPECT_NE(wav_error(write_bytes(dir, "nofmt.wav", riff(chunk("LIST", "ab")))).find("no fmt chunk"), std::string::npos);
  EXPECT_NE(wav_error(write_bytes(dir, "nodata.wav", riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)))))
                .find("no data chunk"),
            std::string::npos);
  const std::string order = riff(chunk("data", samples16({1})) + chunk("fmt ", fmt_body(1, 1, 16000, 16)));
  EXPECT_NE(wav_error(write_bytes(dir, "order.wav", order)).find("before the fmt chunk"), std::string::npos);
  const std::string twice = riff(chunk("fmt ", fmt_body(1, 1, 16000, 16)) + chunk("fmt ", fmt_body(1, 1, 8000, 16)) +
                                 chunk("data", ""));
  EXPECT_NE(wav_error(write_bytes(dir, "twice.wav", twice)).find("second fmt chunk"), std::string::npos);
}

TEST(WavFileErrors, WriteFailuresNameTheFile) {
  ScratchDir dir("wav_write");
  AudioBuffer a;
  a.samples = {1};
  const fs::path bad = dir / "no-such-folder" / "x.wav";
  EXPECT_NE(error_message<IoError>([&] { write_wav(bad, a); }).find(bad.string()), std::string::npos);
  a.sample_rate_hz = 0;
  EXPECT_NE(error_message<IoError>([&] { write_wav(dir / "z.wav", a); }).find("0 Hz"), std::string::npos);
}

TEST(Resample, LengthAndIdentity) {
  const AudioBuffer a = tone(22050, 440, 1.0, 8000);
  const AudioBuffer b = resample(a, 16000);
  EXPECT_EQ(b.sample_rate_hz, 16000);
  EXPECT_EQ(b.samples.size(), 16000u);
  EXPECT_EQ(resample(a, 22050).samples, a.samples);
  EXPECT_THROW(resample(a, 0), std::invalid_argument);
  EXPECT_TRUE(resample(AudioBuffer{22050, {}}, 16000).samples.empty());
}

TEST(Resample, KeepsAToneInTheBand) {
  // 1 kHz at 22050 Hz -> 16000 Hz: the same tone sample for sample (within a few LSB).
  const AudioBuffer a = tone(22050, 1000, 0.5, 10000);
  const AudioBuffer b = resample(a, 16000);
  const AudioBuffer expected = tone(16000, 1000, 0.5, 10000);
  double max_err = 0;
  for (std::size_t i = 100; i + 100 < b.samples.size(); ++i)
    max_err = std::max(max_err, std::abs(static_cast<double>(b.samples[i]) - expected.samples[i]));
  EXPECT_LT(max_err, 20.0);  // 0.2 % of the amplitude
  // and going up
  const AudioBuffer c = resample(expected, 22050);
  double max_up = 0;
  for (std::size_t i = 100; i + 100 < c.samples.size(); ++i)
    max_up = std::max(max_up, std::abs(static_cast<double>(c.samples[i]) - a.samples[i]));
  EXPECT_LT(max_up, 20.0);
}

TEST(Resample, SuppressesWhatWouldAlias) {
  // 10 kHz is above the new Nyquist (8 kHz): linear interpolation would fold it to 6 kHz at
  // about a third of its level; the windowed sinc removes it.
  const AudioBuffer a = tone(22050, 10000, 0.5, 10000);
  const AudioBuffer b = resample(a, 16000);
  EXPECT_LT(rms_middle(b), 10000 / std::sqrt(2.0) * 0.01);  // at least 40 dB down
}

namespace navaid::interaction {
namespace {

TEST(PadWithSilence, ZerosEitherSideAndTheRateKept) {
  AudioBuffer a;
  a.sample_rate_hz = 1000;
  a.samples = {5, -7, 9};
  const AudioBuffer p = pad_with_silence(a, 0.002);
  EXPECT_EQ(p.sample_rate_hz, 1000);
  EXPECT_EQ(p.samples, (std::vector<std::int16_t>{0, 0, 5, -7, 9, 0, 0}));
  EXPECT_EQ(pad_with_silence(a, 0.0).samples, a.samples);
  EXPECT_THROW(pad_with_silence(a, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::interaction
