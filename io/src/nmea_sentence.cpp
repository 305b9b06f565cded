// NMEA 0183 sentence framing, checksum validation and GGA/RMC/GSA/GST/ZDA field decoding.
#include <charconv>
#include <cmath>
#include <cstdio>

#include "navaid/io/nmea.hpp"
#include "navaid/io/text_file.hpp"
#include "nmea_detail.hpp"

namespace navaid::io {

namespace nmea_detail {
std::string format_time_of_day(long long ns) {
  const long long ms = ns / 1'000'000;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%02lld:%02lld:%02lld.%03lld", ms / 3'600'000, ms / 60'000 % 60,
                ms / 1000 % 60, ms % 1000);
  return buffer;
}
}  // namespace nmea_detail

std::size_t NmeaStats::decoded_total() const {
  std::size_t n = 0;
  for (const auto& [type, count] : decoded) n += count;
  return n;
}

std::size_t NmeaStats::ignored_total() const {
  std::size_t n = 0;
  for (const auto& [type, count] : ignored) n += count;
  return n;
}

namespace {

constexpr double kKnotsToMps = 1852.0 / 3600.0;
constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_upper_alnum(char c) { return (c >= 'A' && c <= 'Z') || is_digit(c); }

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// Strict decimal "[+-]digits[.digits]": receivers never send exponents, and "nan"/"inf" text
// must not turn into numbers.
std::optional<double> parse_decimal(std::string_view text) {
  if (text.empty()) return std::nullopt;
  bool negative = false;
  if (text.front() == '+' || text.front() == '-') {
    negative = text.front() == '-';
    text.remove_prefix(1);
  }
  std::size_t digits = 0;
  bool dot = false;
  for (const char c : text) {
    if (is_digit(c)) {
      ++digits;
    } else if (c == '.' && !dot) {
      dot = true;
    } else {
      return std::nullopt;
    }
  }
  if (digits == 0) return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return negative ? -value : value;
}

std::optional<long long> parse_integer_text(std::string_view text) {
  if (text.empty() || text.size() > 12) return std::nullopt;
  bool negative = false;
  if (text.front() == '+' || text.front() == '-') {
    negative = text.front() == '-';
    text.remove_prefix(1);
  }
  if (text.empty()) return std::nullopt;
  long long value = 0;
  for (const char c : text) {
    if (!is_digit(c)) return std::nullopt;
    value = value * 10 + (c - '0');
  }
  return negative ? -value : value;
}

int days_in_month(int year, int month) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return month == 2 && leap ? 29 : kDays[month - 1];
}

// Quoted for messages, cut to keep reports readable when a line is noise.
std::string quoted(std::string_view text) {
  constexpr std::size_t kMax = 32;
  if (text.size() <= kMax) return "'" + std::string(text) + "'";
  return "'" + std::string(text.substr(0, kMax)) + "...' (" + std::to_string(text.size()) + " characters)";
}

std::string range_text(double min, double max) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "is outside [%g, %g]", min, max);
  return buffer;
}

}  // namespace

struct NmeaParser::Impl {
  Impl(std::string source, DataReport* report, std::size_t max_listed)
      : warnings(std::move(source), report, max_listed) {}

  nmea_detail::Warnings warnings;
  NmeaStats stats;
  std::size_t line = 0;
  std::vector<std::string_view> fields;  // reused: no allocation per sentence
  std::string_view type;                 // of the sentence being decoded, for messages

  // ---- field decoding: a malformed value is dropped (absent) and counted, never fatal ----

  std::string_view field(std::size_t i) const { return i < fields.size() ? fields[i] : std::string_view(); }

  void bad_field(std::string_view name, std::string_view text, const std::string& why) {
    ++stats.bad_fields;
    warnings.warn("malformed field", line,
                  std::string(type) + " " + std::string(name) + " " + quoted(text) + " " + why + "; field ignored");
  }

  std::optional<double> number(std::size_t i, std::string_view name, double min, double max) {
    const auto text = field(i);
    if (text.empty()) return std::nullopt;
    const auto value = parse_decimal(text);
    if (!value) {
      bad_field(name, text, "is not a number");
      return std::nullopt;
    }
    if (*value < min || *value > max) {
      bad_field(name, text, range_text(min, max));
      return std::nullopt;
    }
    return value;
  }

  std::optional<int> integer(std::size_t i, std::string_view name, long long min, long long max) {
    const auto text = field(i);
    if (text.empty()) return std::nullopt;
    const auto value = parse_integer_text(text);
    if (!value) {
      bad_field(name, text, "is not an integer");
      return std::nullopt;
    }
    if (*value < min || *value > max) {
      bad_field(name, text, range_text(static_cast<double>(min), static_cast<double>(max)));
      return std::nullopt;
    }
    return static_cast<int>(*value);
  }

  std::optional<char> flag(std::size_t i, std::string_view name, std::string_view allowed) {
    const auto text = field(i);
    if (text.empty()) return std::nullopt;
    if (text.size() != 1 || allowed.find(text.front()) == std::string_view::npos) {
      bad_field(name, text, "is not one of " + std::string(allowed));
      return std::nullopt;
    }
    return text.front();
  }

  // hhmmss[.sss]: exactly six digits, then an optional fraction (digits beyond the ninth dropped).
  std::optional<TimeOfDay> time_of_day(std::size_t i) {
    const auto text = field(i);
    if (text.empty()) return std::nullopt;
    bool ok = text.size() >= 6 && (text.size() == 6 || text[6] == '.');
    for (std::size_t k = 0; ok && k < text.size(); ++k) ok = k == 6 || is_digit(text[k]);
    if (!ok) {
      bad_field("time", text, "is not hhmmss.ss");
      return std::nullopt;
    }
    const int hh = (text[0] - '0') * 10 + (text[1] - '0');
    const int mm = (text[2] - '0') * 10 + (text[3] - '0');
    const int ss = (text[4] - '0') * 10 + (text[5] - '0');
    if (hh > 23 || mm > 59 || ss > 60) {
      bad_field("time", text, "is not a valid time of day");
      return std::nullopt;
    }
    Duration fraction = 0;
    Duration scale = kNanosecondsPerSecond;
    for (std::size_t k = 7; k < text.size() && scale > 1; ++k) {
      scale /= 10;
      fraction += (text[k] - '0') * scale;
    }
    return (static_cast<Duration>(hh) * 3600 + mm * 60 + ss) * kNanosecondsPerSecond + fraction;
  }

  // [d]ddmm.mmmm -> degrees; the integer and fractional minutes are decoded separately so that
  // survey-grade positions (8+ decimals) keep their precision.
  std::optional<double> angle(std::string_view text, std::string_view name, double max_deg) {
    const std::size_t dot = text.find('.');
    const std::string_view whole = text.substr(0, dot);
    const std::string_view frac = dot == std::string_view::npos ? std::string_view() : text.substr(dot + 1);
    bool ok = whole.size() >= 3 && whole.size() <= 5;
    for (const char c : whole) ok = ok && is_digit(c);
    for (const char c : frac) ok = ok && is_digit(c);
    if (!ok) {
      bad_field(name, text, "is not [d]ddmm.mmmm");
      return std::nullopt;
    }
    long long integer_part = 0;
    for (const char c : whole) integer_part = integer_part * 10 + (c - '0');
    double fraction = 0.0;
    long long frac_digits = 0;
    double frac_scale = 1.0;
    for (std::size_t k = 0; k < frac.size() && k < 15; ++k) {
      frac_digits = frac_digits * 10 + (frac[k] - '0');
      frac_scale *= 10.0;
    }
    fraction = static_cast<double>(frac_digits) / frac_scale;
    const long long degrees = integer_part / 100;
    const double minutes = static_cast<double>(integer_part % 100) + fraction;
    if (minutes >= 60.0) {
      bad_field(name, text, "has 60 or more minutes");
      return std::nullopt;
    }
    const double value = static_cast<double>(degrees) + minutes / 60.0;
    if (value > max_deg) {
      bad_field(name, text, "is beyond " + std::to_string(static_cast<int>(max_deg)) + " degrees");
      return std::nullopt;
    }
    return value;
  }

  // Four fields: latitude, N/S, longitude, E/W. All empty -> absent without a warning; any
  // inconsistency -> the whole position is dropped (half a position is no position).
  bool position(std::size_t i, std::optional<double>& latitude, std::optional<double>& longitude) {
    const auto lat_text = field(i), ns = field(i + 1), lon_text = field(i + 2), ew = field(i + 3);
    if (lat_text.empty() && ns.empty() && lon_text.empty() && ew.empty()) return true;
    if (lat_text.empty() || lon_text.empty()) {
      bad_field("position", std::string(lat_text) + "," + std::string(ns) + "," + std::string(lon_text) + "," +
                                std::string(ew), "is incomplete");
      return false;
    }
    const bool ns_ok = ns == "N" || ns == "S";
    const bool ew_ok = ew == "E" || ew == "W";
    if (!ns_ok || !ew_ok) {
      bad_field("hemisphere", ns_ok ? ew : ns, "is not N/S or E/W");
      return false;
    }
    const auto lat = angle(lat_text, "latitude", 90.0);
    const auto lon = angle(lon_text, "longitude", 180.0);
    if (!lat || !lon) return false;
    latitude = ns == "S" ? -*lat : *lat;
    longitude = ew == "W" ? -*lon : *lon;
    return true;
  }

  // RMC ddmmyy. Two-digit years pivot on the GPS epoch: 80..99 -> 19xx, 00..79 -> 20xx.
  std::optional<NmeaDate> ddmmyy(std::size_t i) {
    const auto text = field(i);
    if (text.empty()) return std::nullopt;
    bool ok = text.size() == 6;
    for (std::size_t k = 0; ok && k < 6; ++k) ok = is_digit(text[k]);
    if (!ok) {
      bad_field("date", text, "is not ddmmyy");
      return std::nullopt;
    }
    NmeaDate date;
    date.day = (text[0] - '0') * 10 + (text[1] - '0');
    date.month = (text[2] - '0') * 10 + (text[3] - '0');
    const int yy = (text[4] - '0') * 10 + (text[5] - '0');
    date.year = yy >= 80 ? 1900 + yy : 2000 + yy;
    if (date.month < 1 || date.month > 12 || date.day < 1 || date.day > days_in_month(date.year, date.month)) {
      bad_field("date", text, "is not a calendar date");
      return std::nullopt;
    }
    return date;
  }

  // ---- sentences ----

  NmeaGga decode_gga(std::string_view talker) {
    NmeaGga m;
    m.talker = std::string(talker);
    m.time_of_day = time_of_day(1);
    position(2, m.latitude_deg, m.longitude_deg);
    m.quality = integer(6, "quality", 0, 9);
    m.satellites = integer(7, "satellites", 0, 255);
    m.hdop = number(8, "HDOP", 0.0, 1000.0);
    m.altitude_msl_m = number(9, "altitude", -1.0e4, 1.0e6);
    m.geoid_separation_m = number(11, "geoid separation", -1000.0, 1000.0);
    m.dgps_age_s = number(13, "DGPS age", 0.0, 1.0e6);
    m.dgps_station = integer(14, "DGPS station", 0, 9999);
    return m;
  }

  NmeaRmc decode_rmc(std::string_view talker) {
    NmeaRmc m;
    m.talker = std::string(talker);
    m.time_of_day = time_of_day(1);
    m.status = flag(2, "status", "AVD");
    position(3, m.latitude_deg, m.longitude_deg);
    if (const auto knots = number(7, "speed", 0.0, 1.0e5)) m.speed_mps = *knots * kKnotsToMps;
    if (const auto course = number(8, "course", -360.0, 360.0)) m.course_rad = *course * kRadPerDeg;
    m.date = ddmmyy(9);
    const auto variation = number(10, "magnetic variation", 0.0, 180.0);
    const auto variation_sign = flag(11, "magnetic variation direction", "EW");
    if (variation && variation_sign) {
      m.magnetic_variation_rad = (*variation_sign == 'W' ? -*variation : *variation) * kRadPerDeg;
    }
    m.mode_indicator = flag(12, "mode indicator", "ABCDEFMNPRSUV");
    return m;
  }

  NmeaGsa decode_gsa(std::string_view talker) {
    NmeaGsa m;
    m.talker = std::string(talker);
    m.selection = flag(1, "selection mode", "AM");
    // Antaris receivers put 'E' (dead reckoning) here: not a 1/2/3 fix mode, so absent.
    if (field(2) != "E") m.fix_mode = integer(2, "fix mode", 1, 3);
    // Standard: 12 satellite fields then PDOP, HDOP, VDOP, and (NMEA 4.10) a system id. Some
    // receivers (Navior CH-4701) send more satellite fields: the DOPs are then the last three.
    const std::size_t n = fields.size() - 1;
    const bool has_system_id = n == 18;
    const std::size_t dop = has_system_id ? 15 : n - 2;
    for (std::size_t i = 3; i < dop; ++i) {
      if (const auto prn = integer(i, "satellite", 1, 999)) m.satellites_used.push_back(*prn);
    }
    m.pdop = number(dop, "PDOP", 0.0, 1000.0);
    m.hdop = number(dop + 1, "HDOP", 0.0, 1000.0);
    m.vdop = number(dop + 2, "VDOP", 0.0, 1000.0);
    if (has_system_id) m.system_id = integer(18, "system id", 0, 15);
    return m;
  }

  NmeaGst decode_gst(std::string_view talker) {
    NmeaGst m;
    m.talker = std::string(talker);
    m.time_of_day = time_of_day(1);
    m.rms_range_m = number(2, "RMS", 0.0, 1.0e9);
    m.semi_major_sd_m = number(3, "semi-major sd", 0.0, 1.0e9);
    m.semi_minor_sd_m = number(4, "semi-minor sd", 0.0, 1.0e9);
    if (const auto theta = number(5, "orientation", -360.0, 360.0)) m.semi_major_orientation_rad = *theta * kRadPerDeg;
    m.latitude_sd_m = number(6, "latitude sd", 0.0, 1.0e9);
    m.longitude_sd_m = number(7, "longitude sd", 0.0, 1.0e9);
    m.altitude_sd_m = number(8, "altitude sd", 0.0, 1.0e9);
    return m;
  }

  NmeaZda decode_zda(std::string_view talker) {
    NmeaZda m;
    m.talker = std::string(talker);
    m.time_of_day = time_of_day(1);
    const auto day = integer(2, "day", 1, 31);
    const auto month = integer(3, "month", 1, 12);
    // GPS time starts in 1980: an earlier year is a receiver clock that was never set. 2261 is
    // the last whole year of the int64 nanosecond clock (fuzz_nmea_capture found the overflow).
    const auto year = integer(4, "year", 1980, 2261);
    if (day && month && year) {
      if (*day <= days_in_month(*year, *month)) {
        m.date = NmeaDate{*year, *month, *day};
      } else {
        bad_field("date", std::string(field(2)) + "," + std::string(field(3)) + "," + std::string(field(4)),
                  "is not a calendar date");
      }
    }
    m.local_zone_hours = integer(5, "local zone hours", -13, 13);
    m.local_zone_minutes = integer(6, "local zone minutes", 0, 59);
    return m;
  }

  // ---- framing ----

  void malformed(const std::string& why) {
    ++stats.malformed;
    warnings.warn("malformed sentence", line, why + "; sentence skipped");
  }

  std::optional<NmeaMessage> sentence(std::string_view text) {
    ++stats.sentences;
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r' || text.back() == '\n'))
      text.remove_suffix(1);
    for (const char c : text) {
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) {
        malformed("sentence holds non-printable bytes (binary garbage or line noise)");
        return std::nullopt;
      }
    }
    std::string_view body = text.substr(1);
    const std::size_t star = body.find('*');
    if (star != std::string_view::npos) {
      const std::string_view given = body.substr(star + 1);
      body = body.substr(0, star);
      if (given.size() != 2 || hex_value(given[0]) < 0 || hex_value(given[1]) < 0) {
        ++stats.bad_checksum;
        warnings.warn("bad checksum", line, "malformed checksum " + quoted(given) + "; sentence skipped");
        return std::nullopt;
      }
      unsigned sum = 0;
      for (const char c : body) sum ^= static_cast<unsigned char>(c);
      const unsigned expected = static_cast<unsigned>(hex_value(given[0]) * 16 + hex_value(given[1]));
      if (sum != expected) {
        ++stats.bad_checksum;
        char computed[3];
        std::snprintf(computed, sizeof computed, "%02X", sum);
        warnings.warn("bad checksum", line,
                      "bad checksum (computed " + std::string(computed) + ", sentence says " + std::string(given) +
                          "); sentence skipped");
        return std::nullopt;
      }
    } else {
      ++stats.missing_checksum;
      warnings.warn("no checksum", line, "sentence without checksum accepted");
    }

    fields.clear();
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = body.find(',', start);
      fields.push_back(body.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    const std::string_view address = fields[0];
    bool address_ok = !address.empty();
    for (const char c : address) address_ok = address_ok && is_upper_alnum(c);
    if (!address_ok) {
      malformed("address " + quoted(address) + " is not a talker and sentence type");
      return std::nullopt;
    }
    const auto decoded_type = [](std::string_view t) {
      return t == "GGA" || t == "RMC" || t == "GSA" || t == "GST" || t == "ZDA";
    };
    // 'P' starts a proprietary sentence, except Quectel's "PQ" talker for QZSS (PQGSA).
    const bool standard = address.size() == 5 && (address.front() != 'P' || decoded_type(address.substr(2)));
    if (!standard) {
      if (address.front() == 'P') {
        ++stats.ignored[std::string(address)];
      } else {
        malformed("address " + quoted(address) + " is not a talker and sentence type");
      }
      return std::nullopt;
    }
    const std::string_view talker = address.substr(0, 2);
    type = address.substr(2);
    if (!decoded_type(type)) {
      ++stats.ignored[std::string(type)];
      return std::nullopt;
    }

    // A checksummed sentence may omit trailing fields; one without a checksum must be complete
    // (it may have been cut short in transmission and nothing else vouches for it).
    const bool checksummed = star != std::string_view::npos;
    std::size_t required = 0;
    if (type == "GGA") required = checksummed ? 10 : 15;
    if (type == "RMC") required = checksummed ? 10 : 12;
    if (type == "GSA") required = 18;
    if (type == "GST") required = 9;
    if (type == "ZDA") required = checksummed ? 5 : 7;
    if (fields.size() < required) {
      malformed(std::string(type) + " has " + std::to_string(fields.size() - 1) + " fields, at least " +
                std::to_string(required - 1) + " expected (truncated?)");
      return std::nullopt;
    }

    std::optional<NmeaMessage> message;
    if (type == "GGA") message = decode_gga(talker);
    if (type == "RMC") message = decode_rmc(talker);
    if (type == "GSA") message = decode_gsa(talker);
    if (type == "GST") message = decode_gst(talker);
    if (type == "ZDA") message = decode_zda(talker);
    ++stats.decoded[std::string(type)];
    return message;
  }

  std::size_t parse_line(std::string_view text, std::vector<NmeaMessage>& out) {
    ++line;
    ++stats.lines;
    if (is_blank_or_comment(text)) {
      ++stats.comment_lines;
      return 0;
    }
    std::size_t begin = text.find_first_of("$!");
    if (begin == std::string_view::npos) {
      ++stats.garbage_lines;
      warnings.warn("garbage line", line, "no NMEA sentence on this line (garbage); skipped");
      return 0;
    }
    if (!trim(text.substr(0, begin)).empty()) {
      ++stats.garbage_fragments;
      warnings.warn("garbage fragment", line, "garbage before a sentence; skipped");
    }
    std::size_t appended = 0;
    // A '$' or '!' is never data inside a sentence: it starts the next one (lost line ends).
    while (begin != std::string_view::npos) {
      const std::size_t end = text.find_first_of("$!", begin + 1);
      const auto piece = text.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin);
      if (auto message = sentence(piece)) {
        out.push_back(std::move(*message));
        ++appended;
      }
      begin = end;
    }
    return appended;
  }
};

NmeaParser::NmeaParser(std::string source, DataReport* report, std::size_t max_listed_per_kind)
    : impl_(std::make_unique<Impl>(std::move(source), report, max_listed_per_kind)) {}
NmeaParser::~NmeaParser() = default;

std::size_t NmeaParser::parse_line(std::string_view line, std::vector<NmeaMessage>& out) {
  return impl_->parse_line(line, out);
}

std::optional<NmeaMessage> NmeaParser::parse_sentence(std::string_view sentence) {
  sentence = trim(sentence);
  if (sentence.empty() || (sentence.front() != '$' && sentence.front() != '!')) {
    ++impl_->stats.garbage_fragments;
    impl_->warnings.warn("garbage fragment", impl_->line, "text does not start with '$' or '!'; skipped");
    return std::nullopt;
  }
  return impl_->sentence(sentence);
}

std::size_t NmeaParser::line_number() const { return impl_->line; }
const NmeaStats& NmeaParser::stats() const { return impl_->stats; }
const std::string& NmeaParser::source() const { return impl_->warnings.source(); }

}  // namespace navaid::io
