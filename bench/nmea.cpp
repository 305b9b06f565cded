// NMEA 0183 throughput on a real receiver capture (u-blox / Quectel multi-GNSS, 2296 lines):
// sentences per second for the sentence parser alone, for parser + epoch assembly, and for
// read_nmea_capture from the file. A receiver sends ~10-40 sentences per second, so anything in
// the hundreds of thousands leaves the estimator's budget untouched.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "navaid/io/nmea.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kCapture = fs::path(NAVAID_SHARED_DATA_DIR) / "gpsd-nmea" / "quectel-l76k-nmea.log";

const std::vector<std::string>& capture_lines() {
  static const std::vector<std::string> lines = [] {
    std::vector<std::string> out;
    std::ifstream in(kCapture, std::ios::binary);
    std::string line;
    while (std::getline(in, line)) out.push_back(line);
    return out;
  }();
  return lines;
}

std::size_t sentence_count() {
  navaid::io::NmeaParser parser;
  std::vector<navaid::io::NmeaMessage> out;
  for (const auto& l : capture_lines()) parser.parse_line(l, out);
  return parser.stats().sentences;
}

void BM_NmeaParseSentences(benchmark::State& state) {
  if (capture_lines().empty()) return state.SkipWithError("gpsd-nmea capture not found under NAVAID_SHARED_DATA_DIR");
  const std::size_t sentences = sentence_count();
  std::vector<navaid::io::NmeaMessage> out;
  for (auto _ : state) {
    navaid::io::NmeaParser parser;
    out.clear();
    for (const auto& l : capture_lines()) parser.parse_line(l, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sentences));
  state.counters["sentences"] = static_cast<double>(sentences);
}
BENCHMARK(BM_NmeaParseSentences)->Unit(benchmark::kMicrosecond);

void BM_NmeaParseAndAssembleEpochs(benchmark::State& state) {
  if (capture_lines().empty()) return state.SkipWithError("gpsd-nmea capture not found under NAVAID_SHARED_DATA_DIR");
  const std::size_t sentences = sentence_count();
  std::size_t epochs = 0;
  for (auto _ : state) {
    navaid::io::NmeaReader reader("bench");
    for (const auto& l : capture_lines()) reader.add_line(l);
    reader.finish();
    const auto e = reader.take_epochs();
    epochs = e.size();
    benchmark::DoNotOptimize(e.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sentences));
  state.counters["epochs"] = static_cast<double>(epochs);
}
BENCHMARK(BM_NmeaParseAndAssembleEpochs)->Unit(benchmark::kMicrosecond);

void BM_NmeaReadCaptureFile(benchmark::State& state) {
  if (capture_lines().empty()) return state.SkipWithError("gpsd-nmea capture not found under NAVAID_SHARED_DATA_DIR");
  const std::size_t sentences = sentence_count();
  std::size_t fixes = 0;
  for (auto _ : state) {
    const auto recording = navaid::io::read_nmea_capture(kCapture);
    fixes = recording.gps.size();
    benchmark::DoNotOptimize(recording.gps.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sentences));
  state.counters["fixes"] = static_cast<double>(fixes);
}
BENCHMARK(BM_NmeaReadCaptureFile)->Unit(benchmark::kMicrosecond);

}  // namespace
