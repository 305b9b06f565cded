// NMEA 0183: known-answer decodes, corrupt input, epoch assembly, dates and covariances.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "navaid/io/nmea.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using testing::expect_throw;
using testing::ScratchDir;
using testing::write_text;

constexpr Duration kSecond = kNanosecondsPerSecond;
constexpr double kPi = 3.14159265358979323846;

// "$" + body + "*hh" with the right checksum.
std::string with_checksum(const std::string& body) {
  unsigned sum = 0;
  for (const char c : body) sum ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X", sum);
  return "$" + body + tail;
}

template <typename T>
T decode_one(const std::string& sentence, NmeaParser* parser = nullptr) {
  NmeaParser local;
  NmeaParser& p = parser ? *parser : local;
  const auto message = p.parse_sentence(sentence);
  EXPECT_TRUE(message.has_value()) << sentence;
  if (!message) return T{};
  EXPECT_TRUE(std::holds_alternative<T>(*message)) << sentence;
  return std::holds_alternative<T>(*message) ? std::get<T>(*message) : T{};
}

bool report_mentions(const DataReport& report, const std::string& text) {
  for (const auto& w : report.warnings) {
    if (w.message.find(text) != std::string::npos || w.source.find(text) != std::string::npos) return true;
  }
  return false;
}

std::vector<NmeaEpoch> epochs_of(const std::vector<std::string>& lines, NmeaOptions options = {},
                                 DataReport* report_out = nullptr) {
  NmeaReader reader("test.nmea", options);
  for (const auto& l : lines) reader.add_line(l);
  reader.finish();
  if (report_out) *report_out = reader.report();
  return reader.take_epochs();
}

// ---------------------------------------------------------------- known answers

TEST(NmeaSentence, GgaKnownAnswer) {
  const auto gga = decode_one<NmeaGga>("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47");
  EXPECT_EQ(gga.talker, "GP");
  ASSERT_TRUE(gga.time_of_day);
  EXPECT_EQ(*gga.time_of_day, (12 * 3600 + 35 * 60 + 19) * kSecond);
  ASSERT_TRUE(gga.latitude_deg && gga.longitude_deg);
  EXPECT_NEAR(*gga.latitude_deg, 48.1173, 1e-12);
  EXPECT_NEAR(*gga.longitude_deg, 11.0 + 31.0 / 60.0, 1e-12);
  EXPECT_EQ(gga.quality, 1);
  EXPECT_EQ(gga.satellites, 8);
  EXPECT_DOUBLE_EQ(*gga.hdop, 0.9);
  EXPECT_DOUBLE_EQ(*gga.altitude_msl_m, 545.4);
  EXPECT_DOUBLE_EQ(*gga.geoid_separation_m, 46.9);
  EXPECT_FALSE(gga.dgps_age_s);  // empty fields are absent, never 0
  EXPECT_FALSE(gga.dgps_station);
}

TEST(NmeaSentence, SurveyGradePositionKeepsItsDigits) {
  const auto gga = decode_one<NmeaGga>(
      with_checksum("GPGGA,132820.60,4134.49821229,N,09345.03351845,W,2,09,1.0,278.020,M,-31.442,M,7.6,0133"));
  EXPECT_NEAR(*gga.latitude_deg, 41.0 + 34.49821229 / 60.0, 1e-13);
  EXPECT_NEAR(*gga.longitude_deg, -(93.0 + 45.03351845 / 60.0), 1e-13);
  EXPECT_EQ(*gga.time_of_day, (13 * 3600 + 28 * 60 + 20) * kSecond + 600'000'000);
  EXPECT_DOUBLE_EQ(*gga.dgps_age_s, 7.6);
  EXPECT_EQ(gga.dgps_station, 133);
}

TEST(NmeaSentence, RmcKnownAnswer) {
  const auto rmc = decode_one<NmeaRmc>("$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A");
  EXPECT_EQ(rmc.status, 'A');
  EXPECT_NEAR(*rmc.latitude_deg, 48.1173, 1e-12);
  EXPECT_NEAR(*rmc.speed_mps, 22.4 * 1852.0 / 3600.0, 1e-12);
  EXPECT_DOUBLE_EQ(*rmc.course_rad, 84.4 * kPi / 180.0);
  ASSERT_TRUE(rmc.date);
  EXPECT_EQ(*rmc.date, (NmeaDate{1994, 3, 23}));
  EXPECT_DOUBLE_EQ(*rmc.magnetic_variation_rad, -3.1 * kPi / 180.0);
  EXPECT_FALSE(rmc.mode_indicator);
}

TEST(NmeaSentence, TwoDigitYearsPivotOnTheGpsEpoch) {
  const auto year_of = [](const char* ddmmyy) {
    const auto rmc = decode_one<NmeaRmc>(
        with_checksum(std::string("GPRMC,000000,A,4807.038,N,01131.000,E,0,0,") + ddmmyy + ",,"));
    return rmc.date ? rmc.date->year : -1;
  };
  EXPECT_EQ(year_of("010180"), 1980);
  EXPECT_EQ(year_of("311299"), 1999);
  EXPECT_EQ(year_of("010100"), 2000);
  EXPECT_EQ(year_of("311279"), 2079);
  EXPECT_EQ(year_of("290224"), 2024);  // leap day
  EXPECT_EQ(year_of("290223"), -1);    // not a date: dropped
}

TEST(NmeaSentence, GsaGstZdaKnownAnswers) {
  const auto gsa = decode_one<NmeaGsa>("$GPGSA,A,3,04,05,,09,12,,,24,,,,,2.5,1.3,2.1*39");
  EXPECT_EQ(gsa.selection, 'A');
  EXPECT_EQ(gsa.fix_mode, 3);
  EXPECT_EQ(gsa.satellites_used, (std::vector<int>{4, 5, 9, 12, 24}));
  EXPECT_DOUBLE_EQ(*gsa.pdop, 2.5);
  EXPECT_DOUBLE_EQ(*gsa.hdop, 1.3);
  EXPECT_DOUBLE_EQ(*gsa.vdop, 2.1);
  EXPECT_FALSE(gsa.system_id);

  const auto gsa410 = decode_one<NmeaGsa>("$GNGSA,A,3,82,73,74,67,81,83,68,,,,,,0.99,0.54,0.83,2*08");
  EXPECT_EQ(gsa410.system_id, 2);
  EXPECT_DOUBLE_EQ(*gsa410.vdop, 0.83);
  // Navior CH-4701: 24 satellite fields; the DOPs are the last three.
  const auto wide = decode_one<NmeaGsa>("$GPGSA,A,3,23,13,07,25,,,,,,,,,,,,,,,,,,,,,09.2,07.2,05.7*0D");
  EXPECT_EQ(wide.satellites_used.size(), 4u);
  EXPECT_DOUBLE_EQ(*wide.hdop, 7.2);

  const auto gst = decode_one<NmeaGst>("$GPGST,172814.0,0.006,0.023,0.020,273.6,0.023,0.020,0.031*6A");
  EXPECT_EQ(*gst.time_of_day, (17 * 3600 + 28 * 60 + 14) * kSecond);
  EXPECT_DOUBLE_EQ(*gst.semi_major_orientation_rad, 273.6 * kPi / 180.0);
  EXPECT_DOUBLE_EQ(*gst.latitude_sd_m, 0.023);
  EXPECT_DOUBLE_EQ(*gst.longitude_sd_m, 0.020);
  EXPECT_DOUBLE_EQ(*gst.altitude_sd_m, 0.031);

  const auto zda = decode_one<NmeaZda>("$GPZDA,201530.00,04,07,2002,00,00*60");
  EXPECT_EQ(*zda.date, (NmeaDate{2002, 7, 4}));
  EXPECT_EQ(zda.local_zone_hours, 0);
}

TEST(NmeaSentence, AnyTalkerIdIsDecoded) {
  for (const char* talker : {"GP", "GN", "GL", "GA", "GB", "BD", "GQ", "QZ", "GI", "PQ"}) {
    NmeaParser parser;
    const auto m = parser.parse_sentence(with_checksum(std::string(talker) + "GSA,A,3,04,05,,,,,,,,,,,2.5,1.3,2.1"));
    ASSERT_TRUE(m) << talker;
    EXPECT_EQ(std::get<NmeaGsa>(*m).talker, talker);
  }
}

TEST(NmeaSentence, OtherTypesAreIgnoredAndCountedByType) {
  NmeaParser parser;
  std::vector<NmeaMessage> out;
  parser.parse_line(with_checksum("GPGSV,3,1,12,17,72,207,32,28,59,095,31,06,35,347,25,01,29,132,23"), out);
  parser.parse_line(with_checksum("GLGSV,1,1,01,66,37,078,27"), out);
  parser.parse_line(with_checksum("GPVTG,054.7,T,034.4,M,005.5,N,010.2,K"), out);
  parser.parse_line(with_checksum("PGRME,15.0,M,45.0,M,25.0,M"), out);
  parser.parse_line("!AIVDM,1,1,,A,15MgK45P3@G?fl0E`JbR0OwT0@MS,0*4E", out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(parser.stats().ignored.at("GSV"), 2u);
  EXPECT_EQ(parser.stats().ignored.at("VTG"), 1u);
  EXPECT_EQ(parser.stats().ignored.at("PGRME"), 1u);
  EXPECT_EQ(parser.stats().ignored.at("VDM"), 1u);
  EXPECT_EQ(parser.stats().bad_checksum, 0u);
}

// ---------------------------------------------------------------- corrupt input

TEST(NmeaCorrupt, BadChecksumIsSkippedAndCountedWithFileAndLine) {
  DataReport report;
  NmeaParser parser("capture.nmea", &report);
  std::vector<NmeaMessage> out;
  parser.parse_line("# header", out);
  parser.parse_line("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*48", out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(parser.stats().bad_checksum, 1u);
  ASSERT_EQ(report.total(), 1u);
  EXPECT_EQ(report.warnings[0].source, "capture.nmea");
  EXPECT_NE(report.warnings[0].message.find("line 2"), std::string::npos) << report.warnings[0].message;
  EXPECT_NE(report.warnings[0].message.find("checksum"), std::string::npos);
  // A checksum that is not two hex digits is as bad.
  parser.parse_line("$GPGSA,A,1,,,,,,,,,,,,,,,*1E0,*4E", out);
  EXPECT_EQ(parser.stats().bad_checksum, 2u);
}

TEST(NmeaCorrupt, MissingChecksumIsAcceptedAndCounted) {
  DataReport report;
  NmeaParser parser("x", &report);
  const auto m = parser.parse_sentence("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,");
  ASSERT_TRUE(m);
  EXPECT_NEAR(*std::get<NmeaGga>(*m).latitude_deg, 48.1173, 1e-12);
  EXPECT_EQ(parser.stats().missing_checksum, 1u);
  EXPECT_EQ(report.total(), 1u);
}

TEST(NmeaCorrupt, TruncatedSentencesAreSkipped) {
  NmeaParser parser;
  // Cut without a checksum: nothing vouches for the fields that are there.
  EXPECT_FALSE(parser.parse_sentence("$GPGGA,123519,4807.038,N,01131.000,E,1,08"));
  EXPECT_FALSE(parser.parse_sentence("$GPRMC,000346.03,A,4808"));
  // Checksummed but too short for its type.
  EXPECT_FALSE(parser.parse_sentence("$GPGGA,123519,4807.038,N*27"));
  EXPECT_FALSE(parser.parse_sentence(with_checksum("GPGSA,A,1,,,")));  // i.Trek M3 quirk
  EXPECT_EQ(parser.stats().malformed, 4u);
  EXPECT_EQ(parser.stats().decoded_total(), 0u);
}

TEST(NmeaCorrupt, NonNumericLatitudeDropsThePositionWithAWarning) {
  DataReport report;
  NmeaParser parser("f.nmea", &report);
  const auto gga = decode_one<NmeaGga>("$GPGGA,123519,48x7.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*0F", &parser);
  EXPECT_FALSE(gga.latitude_deg);
  EXPECT_FALSE(gga.longitude_deg);  // half a position is no position
  EXPECT_DOUBLE_EQ(*gga.altitude_msl_m, 545.4);
  EXPECT_EQ(parser.stats().bad_fields, 1u);
  EXPECT_TRUE(report_mentions(report, "latitude '48x7.038'"));
}

TEST(NmeaCorrupt, LatitudeBeyond90IsRejected) {
  DataReport report;
  NmeaParser parser("f.nmea", &report);
  const auto gga = decode_one<NmeaGga>("$GPGGA,123519,9107.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*43", &parser);
  EXPECT_FALSE(gga.latitude_deg);
  EXPECT_TRUE(report_mentions(report, "beyond 90 degrees"));
  // SiRF's no-fix placeholder "36000.0000,N,72000.0000,E" (tn200 capture).
  const auto rmc = decode_one<NmeaRmc>(with_checksum("GPRMC,000416.984,V,36000.0000,N,72000.0000,E,0.000000,,260120,,"),
                                       &parser);
  EXPECT_FALSE(rmc.latitude_deg);
  // 60 minutes is not a valid minute value either.
  const auto sixty = decode_one<NmeaGga>(with_checksum("GPGGA,123519,4860.000,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
                                         &parser);
  EXPECT_FALSE(sixty.latitude_deg);
}

TEST(NmeaCorrupt, NanAndInfTextAreNotNumbers) {
  DataReport report;
  NmeaParser parser("f.nmea", &report);
  const auto gga = decode_one<NmeaGga>("$GPGGA,123519,4807.038,N,01131.000,E,1,08,nan,NaN,M,inf,M,,*3A", &parser);
  EXPECT_FALSE(gga.hdop);
  EXPECT_FALSE(gga.altitude_msl_m);
  EXPECT_FALSE(gga.geoid_separation_m);
  EXPECT_TRUE(gga.latitude_deg);
  EXPECT_EQ(parser.stats().bad_fields, 3u);
  // Exponents are not NMEA either.
  const auto exp = decode_one<NmeaGga>(with_checksum("GPGGA,123519,4807.038,N,01131.000,E,1,08,1e1,545.4,M,46.9,M,,"),
                                       &parser);
  EXPECT_FALSE(exp.hdop);
}

TEST(NmeaCorrupt, EmptyFieldsAreAbsentNeverZero) {
  const auto gga = decode_one<NmeaGga>("$GPGGA,,,,,,0,,,,M,,M,,*66");
  EXPECT_FALSE(gga.time_of_day);
  EXPECT_FALSE(gga.latitude_deg);
  EXPECT_EQ(gga.quality, 0);
  EXPECT_FALSE(gga.satellites);
  EXPECT_FALSE(gga.hdop);
  EXPECT_FALSE(gga.altitude_msl_m);
  EXPECT_FALSE(gga.geoid_separation_m);
  const auto rmc = decode_one<NmeaRmc>(with_checksum("GPRMC,,V,,,,,,,,,,N"));
  EXPECT_FALSE(rmc.time_of_day);
  EXPECT_FALSE(rmc.date);
  EXPECT_FALSE(rmc.speed_mps);
}

TEST(NmeaCorrupt, BadTimesAndDatesAreDropped) {
  NmeaParser parser;
  EXPECT_FALSE(decode_one<NmeaGga>(with_checksum("GPGGA,246000,4807.038,N,01131.000,E,1,08,0.9,1,M,1,M,,"), &parser)
                   .time_of_day);
  EXPECT_FALSE(decode_one<NmeaGga>(with_checksum("GPGGA,12:35:19,4807.038,N,01131.000,E,1,08,0.9,1,M,1,M,,"), &parser)
                   .time_of_day);
  // Telit HE910 sends year "-1" before it knows the date.
  EXPECT_FALSE(decode_one<NmeaRmc>(with_checksum("GPRMC,000000,A,4807.038,N,01131.000,E,0,0,0101-1,,"), &parser).date);
  EXPECT_FALSE(decode_one<NmeaZda>(with_checksum("GPZDA,201530.00,31,02,2002,00,00"), &parser).date);
  EXPECT_FALSE(decode_one<NmeaZda>(with_checksum("GPZDA,201530.00,01,01,1970,00,00"), &parser).date);
  // Found by fuzz_nmea_capture: year 8205 overflowed the int64 nanosecond clock.
  EXPECT_FALSE(decode_one<NmeaZda>(with_checksum("GPZDA,201530.00,01,01,8205,00,00"), &parser).date);
  EXPECT_TRUE(decode_one<NmeaZda>(with_checksum("GPZDA,201530.00,31,12,2261,00,00"), &parser).date);
  EXPECT_EQ(parser.stats().bad_fields, 6u);
}

TEST(NmeaCorrupt, BinaryGarbageIsToleratedAndCounted) {
  DataReport report;
  NmeaParser parser("g.nmea", &report);
  std::vector<NmeaMessage> out;
  std::string garbage;
  for (int i = 0; i < 300; ++i) garbage.push_back(static_cast<char>((i * 37 + 11) % 256));
  garbage.erase(std::remove(garbage.begin(), garbage.end(), '\n'), garbage.end());
  garbage.erase(std::remove(garbage.begin(), garbage.end(), '$'), garbage.end());
  garbage.erase(std::remove(garbage.begin(), garbage.end(), '!'), garbage.end());
  parser.parse_line(garbage, out);
  parser.parse_line(std::string("$GPRMC,000346.03,A,4808") + std::string(12, '\0') + "      ", out);
  // Two sentences glued on one line (a lost line end), the first after some noise.
  parser.parse_line("\x01\x02xx" + with_checksum("GPGSA,A,1,,,,,,,,,,,,,,,") +
                        "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A",
                    out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(std::holds_alternative<NmeaGsa>(out[0]));
  EXPECT_TRUE(std::holds_alternative<NmeaRmc>(out[1]));
  EXPECT_EQ(parser.stats().garbage_lines, 1u);
  EXPECT_EQ(parser.stats().garbage_fragments, 1u);
  EXPECT_EQ(parser.stats().malformed, 1u);  // the NUL-filled RMC
  EXPECT_GE(report.total(), 3u);
}

TEST(NmeaCorrupt, WarningsStayBoundedOnHugeCorruptInput) {
  DataReport report;
  NmeaParser parser("big.nmea", &report, 5);
  std::vector<NmeaMessage> out;
  for (int i = 0; i < 10000; ++i) parser.parse_line("\x7f\x7f garbage \x01", out);
  EXPECT_EQ(report.total(), 10000u);   // every occurrence counted ...
  EXPECT_LE(report.warnings.size(), 6u);  // ... in a handful of entries
}

TEST(NmeaCorrupt, MissingFileRaisesIoErrorNamingIt) {
  const fs::path missing = "/nonexistent/dir/capture.nmea";
  const auto e = expect_throw<IoError>([&] { read_nmea_capture(missing); });
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->file(), missing.string());
}

TEST(NmeaCorrupt, EmptyOrNonNmeaFileRaisesIoError) {
  ScratchDir dir("nmea-empty");
  write_text(dir / "empty.nmea", "");
  EXPECT_THROW(read_nmea_capture(dir / "empty.nmea"), IoError);
  write_text(dir / "comments.nmea", "# only a header\n#\n");
  EXPECT_THROW(read_nmea_capture(dir / "comments.nmea"), IoError);
  write_text(dir / "binary.nmea", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
  const auto e = expect_throw<IoError>([&] { read_nmea_capture(dir / "binary.nmea"); });
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->file(), (dir / "binary.nmea").string());
}

// ---------------------------------------------------------------- epochs and fixes

std::vector<std::string> one_cycle(const std::string& hhmmss, const std::string& ddmmyy,
                                   const std::string& lat = "4807.038") {
  return {with_checksum("GPGGA," + hhmmss + "," + lat + ",N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
          with_checksum("GPRMC," + hhmmss + ",A," + lat + ",N,01131.000,E,0.0,0.0," + ddmmyy + ",,,A"),
          with_checksum("GPGSA,A,3,04,05,09,12,24,,,,,,,,2.5,1.3,2.1")};
}

std::vector<std::string> concat(std::initializer_list<std::vector<std::string>> parts) {
  std::vector<std::string> all;
  for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

TEST(NmeaDates, UtcTimestampKnownAnswersAndRoundTrip) {
  EXPECT_EQ(utc_timestamp({1970, 1, 1}, 0), 0);
  EXPECT_EQ(utc_timestamp({2014, 12, 31}, (3 * 3600 + 7 * 60 + 19) * kSecond), 1419995239LL * kSecond);
  EXPECT_EQ(utc_timestamp({2000, 2, 29}, 0), 951782400LL * kSecond);
  EXPECT_EQ(utc_timestamp({1980, 1, 6}, 0), 315964800LL * kSecond);  // GPS epoch
  for (std::int64_t d = -800000; d <= 800000; d += 37) {
    EXPECT_EQ(days_since_unix_epoch(date_from_days(d)), d);
  }
}

TEST(NmeaEpochs, OneCyclePerTimeOfDayWithDateModeAndPosition) {
  const auto epochs = epochs_of(concat({one_cycle("123519", "230394"), one_cycle("123520", "230394")}));
  ASSERT_EQ(epochs.size(), 2u);
  const auto& e = epochs[0];
  EXPECT_EQ(e.date_source, NmeaEpoch::DateSource::kSentence);
  EXPECT_EQ(*e.t, utc_timestamp({1994, 3, 23}, (12 * 3600 + 35 * 60 + 19) * kSecond));
  EXPECT_EQ(e.mode, GpsFixMode::k3D);
  EXPECT_NEAR(*e.latitude_deg, 48.1173, 1e-12);
  EXPECT_EQ(e.gsa.size(), 1u);
  EXPECT_EQ(*epochs[1].t - *epochs[0].t, kSecond);

  const auto fix = to_gps_fix(e);
  ASSERT_TRUE(fix);
  EXPECT_EQ(fix->t, *e.t);
  EXPECT_DOUBLE_EQ(fix->altitude_m, 545.4);
  EXPECT_DOUBLE_EQ(fix->geoid_separation_m, 46.9);
  EXPECT_EQ(fix->satellites, 8);
  EXPECT_DOUBLE_EQ(fix->hdop, 0.9);
  EXPECT_EQ(fix->quality, 1);
}

TEST(NmeaEpochs, GsaBelongsToTheCycleOfTheTimedSentenceBeforeIt) {
  const std::vector<std::string> lines = {
      with_checksum("GPGSA,A,2,04,05,09,,,,,,,,,,2.5,1.3,2.1"),  // tail of a cycle before the capture
      with_checksum("GPRMC,123519,A,4807.038,N,01131.000,E,0.0,0.0,230394,,,A"),
      with_checksum("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
      with_checksum("GPGSA,A,2,04,05,09,,,,,,,,,,2.5,1.3,2.1"),
      with_checksum("GPRMC,123520,A,4807.038,N,01131.000,E,0.0,0.0,230394,,,A"),
      with_checksum("GPGGA,123520,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
      with_checksum("GPGSA,A,3,04,05,09,12,,,,,,,,,2.5,1.3,2.1"),
  };
  DataReport report;
  const auto epochs = epochs_of(lines, {}, &report);
  ASSERT_EQ(epochs.size(), 2u);
  EXPECT_EQ(epochs[0].mode, GpsFixMode::k2D);  // the receiver says 2D: altitude not solved
  EXPECT_EQ(epochs[1].mode, GpsFixMode::k3D);
  EXPECT_TRUE(report_mentions(report, "GSA before any timed sentence"));
  const auto fix = to_gps_fix(epochs[0]);
  ASSERT_TRUE(fix);
  EXPECT_TRUE(std::isnan(fix->altitude_m));
}

TEST(NmeaEpochs, NoFixEpochsHaveNoPositionAndGiveNoGpsFix) {
  const auto epochs = epochs_of({
      with_checksum("GPGGA,000416.984,0000.0000,N,00000.0000,E,0,00,50.0,0.0,M,0.0,M,0.0,0000"),
      with_checksum("GPGSA,A,1,,,,,,,,,,,,,50.0,50.0,50.0"),
      with_checksum("GPRMC,000416.984,V,0000.0000,N,00000.0000,E,0.0,,260120,,"),
      with_checksum("GPRMC,000417.984,A,4807.038,N,01131.000,E,0.0,0.0,260120,,,E"),  // dead reckoning
      with_checksum("GPGGA,000418.984,4807.038,N,01131.000,E,8,08,0.9,545.4,M,46.9,M,,"),  // simulator
  });
  ASSERT_EQ(epochs.size(), 3u);
  for (const auto& e : epochs) {
    EXPECT_EQ(e.mode, GpsFixMode::kNoFix);
    EXPECT_FALSE(e.latitude_deg);
    EXPECT_FALSE(to_gps_fix(e));
  }
  // RMC 'V' dates are not trusted (bogus on some chips): alone, they date nothing.
  const auto void_only = epochs_of({with_checksum("GPRMC,000416.984,V,,,,,0.0,,260120,,")});
  ASSERT_EQ(void_only.size(), 1u);
  EXPECT_FALSE(void_only[0].t);
}

TEST(NmeaEpochs, EpochsBeforeTheFirstDateAreBackfilled) {
  const auto epochs = epochs_of({
      with_checksum("GPGGA,235958,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
      with_checksum("GPGGA,235959,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
      with_checksum("GPGGA,000000,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
      with_checksum("GPZDA,000000.00,01,01,2024,00,00"),
  });
  ASSERT_EQ(epochs.size(), 3u);
  EXPECT_EQ(epochs[0].date_source, NmeaEpoch::DateSource::kBackfilled);
  EXPECT_EQ(*epochs[0].date, (NmeaDate{2023, 12, 31}));
  EXPECT_EQ(*epochs[2].date, (NmeaDate{2024, 1, 1}));
  EXPECT_EQ(*epochs[1].t + kSecond, *epochs[2].t);
}

TEST(NmeaEpochs, MidnightRolloverAdvancesTheCarriedDate) {
  // GGA-only cycles carry the last RMC date; the time of day wraps at midnight.
  const auto epochs = epochs_of({
      with_checksum("GPRMC,235959,A,4807.038,N,01131.000,E,0.0,0.0,311299,,,A"),
      with_checksum("GPGGA,000000,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
      with_checksum("GPGGA,000001,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"),
  });
  ASSERT_EQ(epochs.size(), 3u);
  EXPECT_EQ(*epochs[1].date, (NmeaDate{2000, 1, 1}));
  EXPECT_EQ(epochs[1].date_source, NmeaEpoch::DateSource::kCarried);
  EXPECT_EQ(*epochs[1].t - *epochs[0].t, kSecond);
  EXPECT_EQ(*epochs[2].t - *epochs[1].t, kSecond);
}

TEST(NmeaEpochs, DateUpdatedOneCycleLateAtMidnightIsCorrected) {
  DataReport report;
  const auto epochs = epochs_of(concat({one_cycle("235959", "311299"), one_cycle("000000", "311299"),
                                        one_cycle("000001", "010100")}),
                                {}, &report);
  ASSERT_EQ(epochs.size(), 3u);
  EXPECT_EQ(*epochs[1].date, (NmeaDate{2000, 1, 1}));
  EXPECT_EQ(*epochs[1].t - *epochs[0].t, kSecond);
  EXPECT_TRUE(report_mentions(report, "wrapped past midnight"));
}

TEST(NmeaEpochs, WeekRolloverInTheStreamIsCorrected) {
  // gp-320fw capture: 2019-04-07 before a cold start, 1999-08-22 (week 0 again) after it.
  DataReport report;
  const auto epochs = epochs_of(concat({one_cycle("000345", "070419"), one_cycle("000429", "220899")}), {}, &report);
  ASSERT_EQ(epochs.size(), 2u);
  EXPECT_EQ(*epochs[1].date, (NmeaDate{2019, 4, 7}));
  EXPECT_TRUE(epochs[1].rollover_corrected);
  EXPECT_TRUE(report_mentions(report, "1024 weeks"));
}

TEST(NmeaEpochs, EarliestValidDateUndoesAReceiverRollover) {
  NmeaOptions options;
  options.earliest_valid_date = NmeaDate{2019, 4, 7};
  const auto kept = epochs_of(one_cycle("120000", "220899"));
  EXPECT_EQ(*kept[0].date, (NmeaDate{1999, 8, 22}));  // default: as reported
  const auto moved = epochs_of(one_cycle("120000", "220899"), options);
  EXPECT_EQ(*moved[0].date, (NmeaDate{2019, 4, 7}));
  EXPECT_TRUE(moved[0].rollover_corrected);
}

TEST(NmeaEpochs, RepeatedStaleCycleIsDropped) {
  DataReport report;
  const auto epochs =
      epochs_of(concat({one_cycle("123519", "230394"), one_cycle("123520", "230394"), one_cycle("123520", "230394")}),
                {}, &report);
  // The third cycle has the same time as the second but follows it directly: it merges, not
  // repeats. A repeat is a time seen again after another one:
  EXPECT_EQ(epochs.size(), 2u);
  const auto stale = epochs_of(concat({one_cycle("123519", "230394"), {with_checksum("GPZDA,123520.00,23,03,1994,,")},
                                       one_cycle("123519", "230394")}),
                               {}, &report);
  EXPECT_EQ(stale.size(), 2u);  // 12:35:19 and the ZDA-only 12:35:20; the repeated 12:35:19 is dropped
  EXPECT_TRUE(report_mentions(report, "repeats the previous cycle"));
}

TEST(NmeaCovariance, FromGstLatLonAltDeviations) {
  auto lines = one_cycle("172814", "230394");
  lines.push_back("$GPGST,172814.0,0.006,0.023,0.020,273.6,0.023,0.020,0.031*6A");
  const auto epochs = epochs_of(lines);
  ASSERT_EQ(epochs.size(), 1u);
  ASSERT_TRUE(epochs[0].gst);
  const Mat3 cov = nmea_covariance_enu(epochs[0]);
  EXPECT_DOUBLE_EQ(cov(0, 0), 0.020 * 0.020);  // east = longitude
  EXPECT_DOUBLE_EQ(cov(1, 1), 0.023 * 0.023);  // north = latitude
  EXPECT_DOUBLE_EQ(cov(2, 2), 0.031 * 0.031);
  // The ellipse (a^2 + b^2 = lat^2 + lon^2 here) adds the east-north correlation.
  const double s = std::sin(273.6 * kPi / 180.0), c = std::cos(273.6 * kPi / 180.0);
  const double a2 = 0.023 * 0.023, b2 = 0.020 * 0.020;
  const double rho = (a2 - b2) * s * c / std::sqrt((a2 * s * s + b2 * c * c) * (a2 * c * c + b2 * s * s));
  EXPECT_NEAR(cov(0, 1), rho * 0.020 * 0.023, 1e-15);
  EXPECT_DOUBLE_EQ(cov(0, 1), cov(1, 0));
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(cov).eigenvalues().minCoeff(), 0.0);
}

TEST(NmeaCovariance, InconsistentGstEllipseIsNotUsed) {
  auto lines = one_cycle("213121", "230394");
  lines.push_back(with_checksum("GPGST,213121.000,16.1,22.2,10.2,2.0,0.4,0.6,1.4"));  // skytraq capture
  const Mat3 cov = nmea_covariance_enu(epochs_of(lines)[0]);
  EXPECT_DOUBLE_EQ(cov(0, 0), 0.36);
  EXPECT_DOUBLE_EQ(cov(1, 1), 0.16);
  EXPECT_DOUBLE_EQ(cov(0, 1), 0.0);
}

TEST(NmeaCovariance, FromDopsAndUereWithoutGst) {
  NmeaOptions o;
  const auto epochs = epochs_of(one_cycle("123519", "230394"));
  const Mat3 cov = nmea_covariance_enu(epochs[0], o);
  // HDOP 0.9 from GGA, VDOP 2.1 from GSA, autonomous UERE.
  EXPECT_DOUBLE_EQ(cov(0, 0), 0.9 * 0.9 * o.uere_autonomous_m * o.uere_autonomous_m / 2.0);
  EXPECT_DOUBLE_EQ(cov(1, 1), cov(0, 0));
  EXPECT_DOUBLE_EQ(cov(2, 2), 2.1 * 2.1 * o.uere_autonomous_m * o.uere_autonomous_m);
  EXPECT_DOUBLE_EQ(cov(0, 1), 0.0);

  // RMC only: no DOP, no altitude.
  const auto rmc_only = epochs_of({with_checksum("GPRMC,123519,A,4807.038,N,01131.000,E,0.0,0.0,230394,,,D")});
  ASSERT_EQ(rmc_only[0].mode, GpsFixMode::k2D);
  const auto fix = to_gps_fix(rmc_only[0], o);
  ASSERT_TRUE(fix);
  EXPECT_EQ(fix->quality, 2);
  EXPECT_EQ(fix->satellites, -1);
  EXPECT_TRUE(std::isnan(fix->hdop));
  EXPECT_TRUE(std::isnan(fix->altitude_m));
  EXPECT_DOUBLE_EQ(fix->covariance_enu(0, 0), o.unknown_horizontal_sd_m * o.unknown_horizontal_sd_m);
  EXPECT_DOUBLE_EQ(fix->covariance_enu(2, 2), o.unknown_vertical_sd_m * o.unknown_vertical_sd_m);
}

TEST(NmeaFixes, TimeGoingBackwardsIsSkippedWithAWarning) {
  // A spliced capture (bt451): the second part starts earlier than the first ended.
  const auto epochs = epochs_of(concat({one_cycle("152508", "091209"), one_cycle("143306", "091209")}));
  ASSERT_EQ(epochs.size(), 2u);
  DataReport report;
  const auto fixes = nmea_fixes(epochs, {}, "spliced.nmea", &report);
  EXPECT_EQ(fixes.size(), 1u);
  EXPECT_TRUE(report_mentions(report, "not after the previous fix"));
}

TEST(NmeaCapture, ReadsAFileWithCommentsIntoARecording) {
  ScratchDir dir("nmea-capture");
  std::string text = "# Name: test receiver\n# Date: 1994-03-23\n";
  for (const auto& l : concat({one_cycle("123519", "230394"), one_cycle("123520", "230394", "4807.040")})) {
    text += l + "\r\n";
  }
  text += with_checksum("GPGGA,123521,4807.038,N,01131.000,E,0,00,,,M,,M,,") + "\n";  // lost the fix
  write_text(dir / "c.nmea", text);
  const Recording rec = read_nmea_capture(dir / "c.nmea");
  EXPECT_EQ(rec.format, "nmea");
  EXPECT_EQ(rec.path, (dir / "c.nmea").string());
  ASSERT_EQ(rec.gps.size(), 2u);
  EXPECT_NEAR(rec.gps[1].latitude_deg, 48.0 + 7.040 / 60.0, 1e-12);
  EXPECT_TRUE(report_mentions(rec.report, "without a position fix"));
  EXPECT_TRUE(rec.imu.empty());
}

TEST(NmeaCapture, RealCaptureMatchesGpsdKnownAnswer) {
  NAVAID_REQUIRE_SHARED_DATA();
  // GPSD's first timed TPV for bu353s4.log: 2014-12-31T03:07:19.000Z, -37.784788333, 175.314896667.
  const Recording rec = read_nmea_capture(testing::shared_data_dir() / "gpsd-nmea" / "bu353s4.log");
  ASSERT_EQ(rec.gps.size(), 25u);
  EXPECT_EQ(rec.gps[0].t, 1419995239LL * kSecond);
  EXPECT_NEAR(rec.gps[0].latitude_deg, -37.784788333, 1e-9);
  EXPECT_NEAR(rec.gps[0].longitude_deg, 175.314896667, 1e-9);
  EXPECT_DOUBLE_EQ(rec.gps[0].altitude_m, 59.9);
  EXPECT_EQ(rec.gps[0].mode, GpsFixMode::k3D);
  EXPECT_EQ(rec.gps[0].satellites, 8);
  EXPECT_EQ(rec.report.total(), 0u);
}

}  // namespace
}  // namespace navaid::io
