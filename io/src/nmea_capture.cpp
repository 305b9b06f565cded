// NMEA line streams (NmeaReader) and capture files (read_nmea_capture).
#include "navaid/io/nmea.hpp"
#include "navaid/io/text_file.hpp"

namespace navaid::io {

struct NmeaReader::Impl {
  Impl(std::string source, NmeaOptions opts)
      : options(opts), parser(source, &report), assembler(opts, source, &report) {}

  NmeaOptions options;
  DataReport report;  // declared before parser and assembler, which keep its address
  NmeaParser parser;
  NmeaEpochAssembler assembler;
  std::vector<NmeaMessage> messages;  // reused between lines
};

NmeaReader::NmeaReader(std::string source, NmeaOptions options)
    : impl_(std::make_unique<Impl>(std::move(source), options)) {}
NmeaReader::~NmeaReader() = default;

void NmeaReader::add_line(std::string_view line) {
  auto& m = *impl_;
  m.messages.clear();
  m.parser.parse_line(line, m.messages);
  for (const auto& message : m.messages) m.assembler.add(message, m.parser.line_number());
}

void NmeaReader::finish() { impl_->assembler.finish(); }
std::vector<NmeaEpoch> NmeaReader::take_epochs() { return impl_->assembler.take_epochs(); }
const NmeaStats& NmeaReader::stats() const { return impl_->parser.stats(); }
const DataReport& NmeaReader::report() const { return impl_->report; }
const NmeaOptions& NmeaReader::options() const { return impl_->options; }

Recording read_nmea_capture(const std::filesystem::path& path, const NmeaOptions& options) {
  TextFile file(path);
  NmeaReader reader(file.path(), options);
  std::string line;
  std::vector<NmeaEpoch> epochs;
  while (file.next(line)) {
    reader.add_line(line);
    // Drain as we go so memory follows the open epochs, not the file size.
    auto done = reader.take_epochs();
    epochs.insert(epochs.end(), std::make_move_iterator(done.begin()), std::make_move_iterator(done.end()));
  }
  reader.finish();
  auto done = reader.take_epochs();
  epochs.insert(epochs.end(), std::make_move_iterator(done.begin()), std::make_move_iterator(done.end()));

  const NmeaStats& stats = reader.stats();
  if (stats.decoded_total() + stats.ignored_total() == 0) {
    throw IoError(file.path(), stats.lines == 0 ? "empty file: no NMEA 0183 sentences"
                                                : "no valid NMEA 0183 sentence in " + std::to_string(stats.lines) +
                                                      " lines (not an NMEA capture?)");
  }

  Recording recording;
  recording.path = file.path();
  recording.format = "nmea";
  recording.report = reader.report();
  recording.gps = nmea_fixes(epochs, options, file.path(), &recording.report);
  return recording;
}

}  // namespace navaid::io
