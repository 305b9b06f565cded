#pragma once
// NMEA 0183 GNSS receiver output, in three layers:
//   1. NmeaParser: one line of text -> checksum-validated sentences -> typed GGA/RMC/GSA/GST/ZDA
//      records (any talker ID). Empty fields stay absent (std::optional), never 0.
//   2. NmeaEpochAssembler: typed records -> one NmeaEpoch per receiver cycle (UTC time of day),
//      with the date resolved (RMC/ZDA, carried over midnight, back-filled, GPS week rollover).
//   3. to_gps_fix / read_nmea_capture: epochs -> navaid::GpsFix (with an ENU covariance).
// NmeaReader chains 1 and 2 for a stream of lines. Problems in the input are never fatal: they are
// counted in a DataReport (naming the source and line) and in NmeaStats. docs/nmea.md explains
// every policy and the agreement with GPSD on 58 real receiver captures.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/time.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::io {

/// Nanoseconds since 00:00:00 UTC of the sentence's day ("hhmmss.sss"); 23:59:60 (a leap second)
/// gives 86400 s.
using TimeOfDay = Duration;

/// A UTC calendar date with the full year.
struct NmeaDate {
  int year = 1970;
  int month = 1;  ///< 1..12
  int day = 1;    ///< 1..31
  friend bool operator==(const NmeaDate& a, const NmeaDate& b) {
    return a.year == b.year && a.month == b.month && a.day == b.day;
  }
  friend bool operator!=(const NmeaDate& a, const NmeaDate& b) { return !(a == b); }
};

/// Days since 1970-01-01 (negative before) of a proleptic Gregorian date.
std::int64_t days_since_unix_epoch(const NmeaDate& date);
/// Inverse of days_since_unix_epoch.
NmeaDate date_from_days(std::int64_t days);
/// UTC date + time of day -> Timestamp (ns since the Unix epoch, leap seconds not counted).
Timestamp utc_timestamp(const NmeaDate& date, TimeOfDay time_of_day);

/// GGA: fix data. Latitude/longitude in degrees like GpsFix (north and east positive); other
/// angles in radians (DESIGN.md §4).
struct NmeaGga {
  std::string talker;                       ///< "GP", "GN", "GL", "GA", "GB", "BD", ...
  std::optional<TimeOfDay> time_of_day;
  std::optional<double> latitude_deg;
  std::optional<double> longitude_deg;
  /// 0 invalid, 1 GPS, 2 DGPS/SBAS, 3 PPS, 4 RTK fixed, 5 RTK float, 6 dead reckoning,
  /// 7 manual input, 8 simulator.
  std::optional<int> quality;
  std::optional<int> satellites;            ///< satellites used
  std::optional<double> hdop;
  std::optional<double> altitude_msl_m;     ///< antenna height above mean sea level
  std::optional<double> geoid_separation_m; ///< ellipsoid height minus MSL height
  std::optional<double> dgps_age_s;
  std::optional<int> dgps_station;
};

/// RMC: recommended minimum data; the usual source of the date.
struct NmeaRmc {
  std::string talker;
  std::optional<TimeOfDay> time_of_day;
  std::optional<char> status;               ///< 'A' valid, 'V' receiver warning, 'D' differential
  std::optional<double> latitude_deg;
  std::optional<double> longitude_deg;
  std::optional<double> speed_mps;          ///< converted from knots
  std::optional<double> course_rad;         ///< over ground, clockwise from true north
  std::optional<NmeaDate> date;             ///< ddmmyy, years 80..99 -> 19xx, 00..79 -> 20xx
  std::optional<double> magnetic_variation_rad;  ///< east positive
  std::optional<char> mode_indicator;       ///< NMEA 2.3 FAA mode: A D E F M N P R S
};

/// GSA: fix mode, satellites used, dilutions of precision. Carries no time: it belongs to the
/// cycle of the timed sentence before it (checked on the GPSD captures, see docs/nmea.md).
struct NmeaGsa {
  std::string talker;
  std::optional<char> selection;            ///< 'A' automatic, 'M' manual 2D/3D
  std::optional<int> fix_mode;              ///< 1 no fix, 2 2D, 3 3D
  std::vector<int> satellites_used;         ///< PRNs (empty fields skipped)
  std::optional<double> pdop;
  std::optional<double> hdop;
  std::optional<double> vdop;
  std::optional<int> system_id;             ///< NMEA 4.10 GNSS system id
};

/// GST: pseudorange error statistics of the fix with the same time of day.
struct NmeaGst {
  std::string talker;
  std::optional<TimeOfDay> time_of_day;
  std::optional<double> rms_range_m;
  std::optional<double> semi_major_sd_m;
  std::optional<double> semi_minor_sd_m;
  std::optional<double> semi_major_orientation_rad;  ///< clockwise from true north
  std::optional<double> latitude_sd_m;
  std::optional<double> longitude_sd_m;
  std::optional<double> altitude_sd_m;
};

/// ZDA: UTC time and date with a four-digit year.
struct NmeaZda {
  std::string talker;
  std::optional<TimeOfDay> time_of_day;
  std::optional<NmeaDate> date;
  std::optional<int> local_zone_hours;
  std::optional<int> local_zone_minutes;
};

using NmeaMessage = std::variant<NmeaGga, NmeaRmc, NmeaGsa, NmeaGst, NmeaZda>;

/// What a parser saw. Sentences of other types are counted in `ignored`, by type.
struct NmeaStats {
  std::size_t lines = 0;              ///< lines given to the parser, comments included
  std::size_t comment_lines = 0;      ///< blank or starting with '#'
  std::size_t garbage_lines = 0;      ///< non-blank lines holding no '$' or '!' sentence start
  std::size_t garbage_fragments = 0;  ///< text before or between sentences on a line
  std::size_t sentences = 0;          ///< framed sentences (a line may hold several)
  std::size_t missing_checksum = 0;   ///< accepted without a checksum
  std::size_t bad_checksum = 0;       ///< skipped: wrong or malformed "*hh"
  std::size_t malformed = 0;          ///< skipped: bad characters, address or field count
  std::size_t bad_fields = 0;         ///< malformed field values, dropped (left absent)
  std::map<std::string, std::size_t> decoded;  ///< by type: "GGA", "RMC", "GSA", "GST", "ZDA"
  std::map<std::string, std::size_t> ignored;  ///< by type: "GSV", "VTG", "PGRME", "VDM", ...

  std::size_t decoded_total() const;
  std::size_t ignored_total() const;
};

/// Sentence-level decoder. Not thread-safe; one per input stream.
class NmeaParser {
 public:
  /// `source` names the input in warnings (usually the file path); `report` (may be null)
  /// receives the counted warnings. At most `max_listed_per_kind` warnings of one kind name
  /// their line; further ones are merged into one counted entry so reports stay small.
  explicit NmeaParser(std::string source = "<nmea>", DataReport* report = nullptr,
                      std::size_t max_listed_per_kind = 10);
  ~NmeaParser();
  NmeaParser(const NmeaParser&) = delete;
  NmeaParser& operator=(const NmeaParser&) = delete;

  /// Decodes every sentence of the next line (its number is line_number() afterwards) and
  /// appends the GGA/RMC/GSA/GST/ZDA records to `out`; returns how many were appended.
  std::size_t parse_line(std::string_view line, std::vector<NmeaMessage>& out);
  /// Decodes one sentence ("$GPGGA,...*47"); nullopt when skipped or of another type.
  std::optional<NmeaMessage> parse_sentence(std::string_view sentence);

  std::size_t line_number() const;
  const NmeaStats& stats() const;
  const std::string& source() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Policies of the epoch assembler and of the GpsFix conversion (docs/nmea.md).
struct NmeaOptions {
  /// Receivers hit by the GPS week-number rollover report dates 1024 weeks (19.6 years) early.
  /// Dates before this one are moved forward by 1024 weeks until they are not. Unset (default):
  /// dates are kept as reported, except that a date 1023+ weeks before an earlier date of the
  /// same stream is always corrected. GPSD instead moves every date before 2017-01-01 when its
  /// leap-second count is above 17, which is how its checks come to show 2033/2034.
  std::optional<NmeaDate> earliest_valid_date;
  /// User equivalent range error [m] for HDOP/VDOP-based covariances, by fix quality.
  double uere_autonomous_m = 5.0;    ///< GGA quality 1 and 3, RMC 'A'
  double uere_differential_m = 1.0;  ///< quality 2 (DGPS, SBAS), RMC 'D'
  double uere_rtk_float_m = 0.3;     ///< quality 5
  double uere_rtk_fixed_m = 0.03;    ///< quality 4
  /// VDOP assumed as this multiple of HDOP when no GSA gives VDOP.
  double vdop_per_hdop = 1.7;
  /// Horizontal standard deviation [m] when a fix has neither GST nor HDOP (RMC-only receivers).
  double unknown_horizontal_sd_m = 30.0;
  /// Vertical standard deviation [m] when the altitude is unknown (2D fix).
  double unknown_vertical_sd_m = 1000.0;
  /// Epochs held while no date is known, to be back-filled when the first date arrives; older
  /// ones are released without a date (and give no GpsFix).
  std::size_t max_undated_epochs = 3600;
};

/// One receiver cycle: every sentence with the same UTC time of day, plus the untimed GSAs that
/// followed them. Fields below `mode` are the assembler's decisions.
struct NmeaEpoch {
  enum class DateSource : std::uint8_t {
    kNone,        ///< no date known (yet): t is absent
    kSentence,    ///< RMC (status A/D) or ZDA of this epoch
    kCarried,     ///< date of the previous epoch, advanced at midnight
    kBackfilled,  ///< epoch before the first date of the stream, dated from the next epoch
  };

  TimeOfDay time_of_day = 0;
  std::optional<NmeaDate> date;
  std::optional<Timestamp> t;  ///< UTC, ns since the Unix epoch; absent when no date is known
  DateSource date_source = DateSource::kNone;
  bool rollover_corrected = false;  ///< date moved forward by 1024 weeks
  std::size_t first_line = 0;       ///< line of its first sentence

  std::optional<NmeaGga> gga;  ///< the GN one when several talkers sent GGA, else the first
  std::optional<NmeaRmc> rmc;
  std::vector<NmeaGsa> gsa;    ///< one per constellation on multi-GNSS receivers
  std::optional<NmeaGst> gst;
  std::optional<NmeaZda> zda;

  GpsFixMode mode = GpsFixMode::kNoFix;
  std::optional<double> latitude_deg;   ///< present iff mode is 2D or 3D
  std::optional<double> longitude_deg;

  bool has_position() const { return mode != GpsFixMode::kNoFix; }
};

/// Groups typed records into epochs. Feed records in input order; completed epochs come out in
/// the same order (an epoch completes when a record with another time arrives, or at finish()).
class NmeaEpochAssembler {
 public:
  explicit NmeaEpochAssembler(NmeaOptions options = {}, std::string source = "<nmea>",
                              DataReport* report = nullptr, std::size_t max_listed_per_kind = 10);
  ~NmeaEpochAssembler();
  NmeaEpochAssembler(const NmeaEpochAssembler&) = delete;
  NmeaEpochAssembler& operator=(const NmeaEpochAssembler&) = delete;

  /// `line` is only used in warnings.
  void add(const NmeaMessage& message, std::size_t line = 0);
  /// End of input: completes the open epoch and releases undated ones.
  void finish();
  /// Moves out the epochs completed so far.
  std::vector<NmeaEpoch> take_epochs();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Parser + assembler over a stream of lines (for live serial input or any line source).
class NmeaReader {
 public:
  explicit NmeaReader(std::string source = "<nmea>", NmeaOptions options = {});
  ~NmeaReader();
  NmeaReader(const NmeaReader&) = delete;
  NmeaReader& operator=(const NmeaReader&) = delete;

  void add_line(std::string_view line);
  void finish();
  std::vector<NmeaEpoch> take_epochs();

  const NmeaStats& stats() const;
  const DataReport& report() const;
  const NmeaOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The GpsFix of an epoch with a position and a time (nullopt otherwise). Unknown values are NaN
/// (altitude of a 2D fix, geoid separation, HDOP) or -1 (satellites). Covariance: GST when the
/// epoch has one, else HDOP/VDOP x UERE (docs/nmea.md).
std::optional<GpsFix> to_gps_fix(const NmeaEpoch& epoch, const NmeaOptions& options = {});

/// ENU position covariance [m^2] of an epoch (used by to_gps_fix).
Mat3 nmea_covariance_enu(const NmeaEpoch& epoch, const NmeaOptions& options = {});

/// GpsFix records of the epochs that have a position and a time, strictly increasing in time:
/// epochs without a fix, without a date, or not after the previous fix are counted in `report`.
std::vector<GpsFix> nmea_fixes(const std::vector<NmeaEpoch>& epochs, const NmeaOptions& options,
                               const std::string& source, DataReport* report);

/// Reads an NMEA 0183 capture (one sentence per line; '#' lines are comments; binary garbage is
/// skipped and counted). Format "nmea", fixes in `gps`, problems in `report`. Throws IoError
/// when the file is missing or unreadable, or holds no NMEA sentence at all.
Recording read_nmea_capture(const std::filesystem::path& path, const NmeaOptions& options = {});

}  // namespace navaid::io
