// Groups decoded NMEA records into receiver cycles (epochs) and resolves their UTC date.
#include <algorithm>
#include <deque>

#include "navaid/io/nmea.hpp"
#include "nmea_detail.hpp"

namespace navaid::io {

namespace {

constexpr Duration kDay = 86400 * kNanosecondsPerSecond;
constexpr Duration kHalfDay = kDay / 2;
constexpr Duration kMidnightWindow = 3600 * kNanosecondsPerSecond;
constexpr std::int64_t kRolloverDays = 1024 * 7;  // the 10-bit GPS week counter wraps every 1024 weeks

NmeaDate add_days(const NmeaDate& date, std::int64_t days) {
  return date_from_days(days_since_unix_epoch(date) + days);
}

std::string format_date(const NmeaDate& d) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02d", d.year, d.month, d.day);
  return buffer;
}

bool valid_quality(const std::optional<int>& q) { return q && *q >= 1 && *q <= 5; }

bool rmc_valid(const NmeaRmc& rmc) {
  if (rmc.status != 'A' && rmc.status != 'D') return false;
  // FAA mode: E estimated (dead reckoning), M manual, S simulator, N not valid, and Quectel's
  // C/U/V are not GNSS measurements.
  if (rmc.mode_indicator) {
    const char m = *rmc.mode_indicator;
    if (m != 'A' && m != 'D' && m != 'F' && m != 'P' && m != 'R') return false;
  }
  return true;
}

bool has_position(const std::optional<double>& lat, const std::optional<double>& lon) {
  return lat.has_value() && lon.has_value();
}

}  // namespace

// Proleptic Gregorian calendar <-> day count, by shifting the year to start in March so that the
// leap day is the last day of the shifted year.
std::int64_t days_since_unix_epoch(const NmeaDate& date) {
  const std::int64_t y = date.year - (date.month <= 2 ? 1 : 0);
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const std::int64_t year_of_era = y - era * 400;
  const std::int64_t shifted_month = (date.month + 9) % 12;  // March = 0
  const std::int64_t day_of_year = (153 * shifted_month + 2) / 5 + date.day - 1;
  const std::int64_t day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;  // 719468 days from 0000-03-01 to 1970-01-01
}

NmeaDate date_from_days(std::int64_t days) {
  const std::int64_t z = days + 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const std::int64_t day_of_era = z - era * 146097;
  const std::int64_t year_of_era =
      (day_of_era - day_of_era / 1460 + day_of_era / 36524 - day_of_era / 146096) / 365;
  const std::int64_t day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
  const std::int64_t shifted_month = (5 * day_of_year + 2) / 153;
  NmeaDate date;
  date.day = static_cast<int>(day_of_year - (153 * shifted_month + 2) / 5 + 1);
  date.month = static_cast<int>(shifted_month < 10 ? shifted_month + 3 : shifted_month - 9);
  date.year = static_cast<int>(year_of_era + era * 400 + (date.month <= 2 ? 1 : 0));
  return date;
}

Timestamp utc_timestamp(const NmeaDate& date, TimeOfDay time_of_day) {
  return days_since_unix_epoch(date) * kDay + time_of_day;
}

struct NmeaEpochAssembler::Impl {
  Impl(NmeaOptions opts, std::string source, DataReport* report, std::size_t max_listed)
      : options(opts), warnings(std::move(source), report, max_listed) {}

  NmeaOptions options;
  nmea_detail::Warnings warnings;

  std::optional<NmeaEpoch> current;
  bool current_repeats_time = false;
  std::deque<TimeOfDay> recent_times;  // of the last few closed epochs
  std::deque<NmeaEpoch> undated;
  std::vector<NmeaEpoch> done;

  std::optional<NmeaDate> last_date;  // date of the latest dated epoch ...
  TimeOfDay last_time = 0;            // ... and its time of day

  NmeaEpoch& epoch_at(TimeOfDay time, std::size_t line) {
    if (current && current->time_of_day == time) return *current;
    close_current();
    current.emplace();
    current->time_of_day = time;
    current->first_line = line;
    current_repeats_time = std::find(recent_times.begin(), recent_times.end(), time) != recent_times.end();
    return *current;
  }

  void no_time(std::string_view type, std::size_t line) {
    warnings.warn("no time", line, std::string(type) + " without a time cannot be placed in an epoch; skipped");
  }

  // Several talkers may report the same cycle (GPGGA + GLGGA, GPRMC + GARMC): keep the one with a
  // position, preferring the combined-GNSS "GN" talker.
  template <typename M>
  static int preference(const M& m) {
    return (has_position(m.latitude_deg, m.longitude_deg) ? 2 : 0) + (m.talker == "GN" ? 1 : 0);
  }

  void add(const NmeaMessage& message, std::size_t line) {
    if (const auto* gga = std::get_if<NmeaGga>(&message)) {
      if (!gga->time_of_day) return no_time("GGA", line);
      auto& e = epoch_at(*gga->time_of_day, line);
      if (!e.gga || preference(*gga) > preference(*e.gga)) e.gga = *gga;
    } else if (const auto* rmc = std::get_if<NmeaRmc>(&message)) {
      if (!rmc->time_of_day) return no_time("RMC", line);
      auto& e = epoch_at(*rmc->time_of_day, line);
      if (!e.rmc || preference(*rmc) > preference(*e.rmc)) e.rmc = *rmc;
    } else if (const auto* gst = std::get_if<NmeaGst>(&message)) {
      if (!gst->time_of_day) return no_time("GST", line);
      epoch_at(*gst->time_of_day, line).gst = *gst;
    } else if (const auto* zda = std::get_if<NmeaZda>(&message)) {
      if (!zda->time_of_day) return no_time("ZDA", line);
      epoch_at(*zda->time_of_day, line).zda = *zda;
    } else if (const auto* gsa = std::get_if<NmeaGsa>(&message)) {
      // Receivers send GSA after the timed sentences of their cycle: wherever it can be told on the
      // GPSD captures (463 GSAs), its HDOP equals that of the GGA before it, never the one after.
      if (!current) {
        warnings.warn("GSA before time", line, "GSA before any timed sentence (no epoch to attach to); skipped");
        return;
      }
      current->gsa.push_back(*gsa);
    }
  }

  void decide_fix(NmeaEpoch& e) const {
    std::optional<int> gsa_mode;
    for (const auto& g : e.gsa) {
      if (g.fix_mode && (!gsa_mode || *g.fix_mode > *gsa_mode)) gsa_mode = g.fix_mode;
    }
    std::optional<double> lat, lon;
    bool from_gga = false;
    if (e.gga && valid_quality(e.gga->quality) && has_position(e.gga->latitude_deg, e.gga->longitude_deg)) {
      lat = e.gga->latitude_deg;
      lon = e.gga->longitude_deg;
      from_gga = true;
    } else if (e.gga && e.gga->quality) {
      // GGA states no fix (0), dead reckoning (6), manual (7) or simulation (8): not a GNSS fix,
      // whatever RMC says.
    } else if (e.rmc && rmc_valid(*e.rmc) && has_position(e.rmc->latitude_deg, e.rmc->longitude_deg)) {
      lat = e.rmc->latitude_deg;
      lon = e.rmc->longitude_deg;
    }
    e.mode = GpsFixMode::kNoFix;
    if (lat && lon) {
      if (gsa_mode) {
        e.mode = static_cast<GpsFixMode>(*gsa_mode);
      } else {
        e.mode = from_gga && e.gga->altitude_msl_m ? GpsFixMode::k3D : GpsFixMode::k2D;
      }
    }
    if (e.mode == GpsFixMode::kNoFix) {
      e.latitude_deg.reset();
      e.longitude_deg.reset();
    } else {
      e.latitude_deg = lat;
      e.longitude_deg = lon;
    }
  }

  // The epoch's own date: ZDA (four-digit year) first, else RMC when its status is valid. GPSD
  // also ignores RMC dates under status 'V': some chips (MTK3301) send bogus ones then.
  std::optional<NmeaDate> own_date(const NmeaEpoch& e) const {
    if (e.zda && e.zda->date) return e.zda->date;
    if (e.rmc && e.rmc->date && (e.rmc->status == 'A' || e.rmc->status == 'D')) return e.rmc->date;
    return std::nullopt;
  }

  void resolve_date(NmeaEpoch& e) {
    const auto own = own_date(e);
    if (own) {
      NmeaDate date = *own;
      bool corrected = false;
      if (options.earliest_valid_date) {
        const auto earliest = days_since_unix_epoch(*options.earliest_valid_date);
        while (days_since_unix_epoch(date) < earliest) {
          date = add_days(date, kRolloverDays);
          corrected = true;
        }
      }
      // A date 1024 (or 2048, 3072) weeks, give or take a week, behind the stream's previous one:
      // the receiver lost the week count (e.g. after a cold start).
      if (last_date) {
        const std::int64_t behind = days_since_unix_epoch(*last_date) - days_since_unix_epoch(date);
        for (std::int64_t k = 1; k <= 3; ++k) {
          if (behind >= k * kRolloverDays - 7 && behind <= k * kRolloverDays + 7) {
            date = add_days(date, k * kRolloverDays);
            corrected = true;
            break;
          }
        }
      }
      if (corrected) {
        warnings.warn("week rollover", e.first_line,
                      "date " + format_date(*own) + " moved by 1024 weeks to " + format_date(date) +
                          " (GPS week-number rollover)");
      }
      if (last_date && date == *last_date && e.time_of_day + kHalfDay < last_time &&
          e.time_of_day + kDay - last_time <= kMidnightWindow) {
        // Some receivers update the date a cycle late at midnight: the time of day wrapped, the
        // date did not. (A bigger jump back is a spliced capture, not a midnight.)
        const NmeaDate next = add_days(date, 1);
        warnings.warn("date behind", e.first_line,
                      "time wrapped past midnight at " + nmea_detail::format_time_of_day(e.time_of_day) +
                          " but the date is still " + format_date(date) + "; using " + format_date(next));
        date = next;
        e.date_source = NmeaEpoch::DateSource::kCarried;
      } else {
        e.date_source = NmeaEpoch::DateSource::kSentence;
      }
      e.date = date;
      e.rollover_corrected = corrected;
    } else if (last_date) {
      e.date = carried_date(e.time_of_day);
      e.date_source = NmeaEpoch::DateSource::kCarried;
    }
    if (e.date) {
      e.t = utc_timestamp(*e.date, e.time_of_day);
      last_date = e.date;
      last_time = e.time_of_day;
    }
  }

  // The date of the previous dated epoch, moved across midnight when the time of day jumps by more
  // than half a day (forward past 24:00, or back before 00:00).
  NmeaDate carried_date(TimeOfDay time) const {
    if (time + kHalfDay < last_time) return add_days(*last_date, 1);
    if (time > last_time + kHalfDay) return add_days(*last_date, -1);
    return *last_date;
  }

  // Dates the epochs held before the stream's first date, walking back from `next`.
  void backfill(const NmeaEpoch& next) {
    NmeaDate date = *next.date;
    TimeOfDay time = next.time_of_day;
    for (auto it = undated.rbegin(); it != undated.rend(); ++it) {
      if (it->time_of_day > time + kHalfDay) date = add_days(date, -1);
      else if (it->time_of_day + kHalfDay < time) date = add_days(date, 1);
      it->date = date;
      it->t = utc_timestamp(date, it->time_of_day);
      it->date_source = NmeaEpoch::DateSource::kBackfilled;
      time = it->time_of_day;
    }
    for (auto& e : undated) done.push_back(std::move(e));
    undated.clear();
  }

  void close_current() {
    if (!current) return;
    NmeaEpoch e = std::move(*current);
    current.reset();
    if (current_repeats_time) {
      // A time of day seen a cycle or a few ago: a receiver repeating a stale cycle (GPSD treats
      // a non-advancing GGA time as "no fix" too).
      warnings.warn("time not advancing", e.first_line,
                    "time " + nmea_detail::format_time_of_day(e.time_of_day) +
                        " repeats the previous cycle's; epoch dropped");
      return;
    }
    recent_times.push_back(e.time_of_day);
    if (recent_times.size() > 4) recent_times.pop_front();
    decide_fix(e);
    resolve_date(e);
    if (e.date && !undated.empty()) backfill(e);
    if (e.date) {
      done.push_back(std::move(e));
      return;
    }
    undated.push_back(std::move(e));
    if (undated.size() > options.max_undated_epochs) {
      warnings.warn("no date", undated.front().first_line, "no date (RMC/ZDA) known yet; epoch released undated");
      done.push_back(std::move(undated.front()));
      undated.pop_front();
    }
  }

  void finish() {
    close_current();
    if (!undated.empty()) {
      warnings.warn("no date", undated.front().first_line,
                    std::to_string(undated.size()) + " epoch(s) before the end of input without any date (RMC/ZDA)");
    }
    for (auto& e : undated) done.push_back(std::move(e));
    undated.clear();
  }
};

NmeaEpochAssembler::NmeaEpochAssembler(NmeaOptions options, std::string source, DataReport* report,
                                       std::size_t max_listed_per_kind)
    : impl_(std::make_unique<Impl>(options, std::move(source), report, max_listed_per_kind)) {}
NmeaEpochAssembler::~NmeaEpochAssembler() = default;

void NmeaEpochAssembler::add(const NmeaMessage& message, std::size_t line) { impl_->add(message, line); }
void NmeaEpochAssembler::finish() { impl_->finish(); }

std::vector<NmeaEpoch> NmeaEpochAssembler::take_epochs() {
  std::vector<NmeaEpoch> out;
  out.swap(impl_->done);
  return out;
}

}  // namespace navaid::io
