// Reference check of the NMEA reader against GPSD's own regression output on 58 real receiver
// captures (../shared/data/gpsd-nmea, see SOURCE.md there and docs/nmea.md for the results).
//
// Matching, per capture:
//  * Reference epochs: GPSD TPV reports that carry a "time". GPSD re-reports an epoch after many
//    sentences of its cycle; the last TPV with a given time is its final view of that epoch.
//  * Our epochs: every NmeaEpoch with a time (no-fix epochs included, as GPSD reports those too).
//  * A reference epoch is matched by our epoch with the same UTC time to the millisecond (GPSD
//    prints milliseconds). GPSD moves dates before 2017 forward by 1024 weeks when it trusts its
//    build-time leap-second count (docs/nmea.md): a match at exactly that shift counts, separately.
//  * It agrees when the fix mode is equal and, for 2D/3D, latitude and longitude agree within
//    1e-6 degree (GPSD prints 9 decimals).
// Set NAVAID_NMEA_GPSD_VERBOSE=1 for the per-capture table, =2 for every disagreement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

// GCC 12's -Wnull-dereference misfires inside nlohmann::json's inlined iterators.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <nlohmann/json.hpp>
#pragma GCC diagnostic pop

#include "navaid/io/nmea.hpp"
#include "navaid/io/text_file.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;

constexpr Duration kMillisecond = 1'000'000;
// 1024 weeks, GPSD's "WKRO" correction.
constexpr Duration kWeekRollover = 1024LL * 7 * 86400 * kNanosecondsPerSecond;
constexpr double kLatLonTolDeg = 1e-6;

struct GpsdTpv {
  Timestamp t = 0;
  int mode = 0;
  std::optional<double> lat, lon;
};

// "2014-12-31T03:07:19.000Z"
std::optional<Timestamp> parse_iso_time(const std::string& s) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double sec = 0;
  if (std::sscanf(s.c_str(), "%d-%d-%dT%d:%d:%lfZ", &y, &mo, &d, &h, &mi, &sec) != 6) return std::nullopt;
  const auto ms = static_cast<long long>(std::llround(sec * 1000.0));
  const TimeOfDay tod = (static_cast<long long>(h) * 3600 + mi * 60) * kNanosecondsPerSecond + ms * kMillisecond;
  return utc_timestamp(NmeaDate{y, mo, d}, tod);
}

// hhmmss[.ss] of a sentence's time field, in milliseconds; nullopt when empty or malformed.
std::optional<long long> sentence_time_ms(const std::string& sentence) {
  // Time field index by sentence type (talker stripped).
  static const std::map<std::string, std::size_t> kTimeField = {
      {"GGA", 1}, {"RMC", 1}, {"GLL", 5}, {"GNS", 1}, {"ZDA", 1}, {"GST", 1}, {"GBS", 1}, {"BWC", 1}};
  const std::string body = sentence.substr(0, sentence.find('*'));
  const auto fields = split_fields(body, ',');  // views into body
  if (fields.empty() || fields[0].size() < 4) return std::nullopt;
  const auto it = kTimeField.find(std::string(fields[0].substr(fields[0].size() - 3)));
  if (it == kTimeField.end() || it->second >= fields.size()) return std::nullopt;
  const std::string text(fields[it->second]);
  int h = 0, m = 0;
  double s = 0;
  if (text.size() < 6 || std::sscanf(text.c_str(), "%2d%2d%lf", &h, &m, &s) != 3) return std::nullopt;
  return (h * 3600LL + m * 60LL) * 1000 + std::llround(s * 1000.0);
}

bool is_timed_sentence(const std::string& sentence) {
  const auto comma = sentence.find(',');
  if (comma == std::string::npos || comma < 4) return false;
  const std::string type = sentence.substr(comma - 3, 3);
  return type == "GGA" || type == "RMC" || type == "GLL" || type == "GNS" || type == "ZDA" || type == "GST" ||
         type == "GBS" || type == "BWC";
}

// GPSD's view of each epoch: the last TPV with that time among those GPSD emitted while the latest
// timed sentence it had read carried that time of day. GPSD keeps its last time when a sentence
// brings none it can use (RMC status 'V', empty time fields), so TPVs after such sentences show a
// later cycle's data under a stale time: they are not GPSD's answer for that epoch.
std::vector<GpsdTpv> read_gpsd_reference(const fs::path& chk) {
  std::ifstream in(chk, std::ios::binary);
  std::map<Timestamp, std::size_t> index;
  std::vector<GpsdTpv> tpvs;
  std::string line;
  std::optional<long long> cycle_ms;  // time of day of the latest timed sentence
  bool seen_timed = false;
  const long long day_ms = 86400LL * 1000;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && (line.front() == '$' || line.front() == '!')) {
      // A garbled line may hold several sentences: the last one counts.
      const std::string last = line.substr(line.find_last_of("$!"));
      if (is_timed_sentence(last)) {
        seen_timed = true;
        cycle_ms = sentence_time_ms(last);
      }
    }
    if (line.empty() || line.front() != '{') continue;
    const auto j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object() || j.value("class", "") != "TPV" || !j.contains("time")) continue;
    const auto t = parse_iso_time(j["time"].get<std::string>());
    if (!t) continue;
    if (seen_timed && (!cycle_ms || *cycle_ms % day_ms != (*t / kMillisecond) % day_ms)) continue;
    GpsdTpv tpv;
    tpv.t = *t;
    tpv.mode = j.value("mode", 0);
    if (j.contains("lat") && j.contains("lon")) {
      tpv.lat = j["lat"].get<double>();
      tpv.lon = j["lon"].get<double>();
    }
    const auto [it, inserted] = index.emplace(tpv.t, tpvs.size());
    if (inserted) tpvs.push_back(tpv);
    else tpvs[it->second] = tpv;
  }
  return tpvs;
}

struct CaptureResult {
  std::string name;
  std::size_t reference = 0;      // GPSD epochs with a time
  std::size_t agree = 0;          // same time, mode and position
  std::size_t agree_wkro = 0;     // ... of which matched only through GPSD's 1024-week shift
  std::size_t missing = 0;        // no epoch of ours at that time
  std::size_t mode_differs = 0;
  // Classes of mode disagreement (docs/nmea.md): the receiver's GSA says 2D where GPSD says 3D;
  // a cycle with RMC only (no GGA, no GSA) that GPSD keeps at 3D; a GGA with fewer than 3
  // satellites that GPSD declares no fix; anything else.
  std::size_t mode_gsa_2d = 0, mode_rmc_only = 0, mode_gga_few_sats = 0, mode_other = 0;
  std::size_t position_differs = 0;
  std::size_t ours_only = 0;      // our epochs with a time GPSD never reported
  std::size_t both_positions = 0;        // matched epochs where both have a position (any mode)
  std::size_t both_positions_agree = 0;  // ... that agree within the tolerance
  std::size_t our_epochs = 0;
  std::size_t fixes = 0;          // GpsFix records from read_nmea_capture
  std::size_t warnings = 0;
  std::vector<std::string> details;
};

int mode_number(GpsFixMode m) { return static_cast<int>(m); }

CaptureResult compare_capture(const fs::path& log) {
  CaptureResult r;
  r.name = log.filename().string();

  NmeaReader reader(log.string());
  TextFile file(log);
  std::string line;
  std::vector<NmeaEpoch> epochs;
  while (file.next(line)) reader.add_line(line);
  reader.finish();
  epochs = reader.take_epochs();

  std::map<Timestamp, const NmeaEpoch*> ours;  // by millisecond
  for (const auto& e : epochs) {
    if (!e.t) continue;
    ++r.our_epochs;
    ours.emplace((*e.t + kMillisecond / 2) / kMillisecond, &e);
  }

  const auto reference = read_gpsd_reference(fs::path(log.string() + ".chk"));
  std::map<Timestamp, bool> matched;
  for (const auto& tpv : reference) {
    ++r.reference;
    const Timestamp key = tpv.t / kMillisecond;
    bool wkro = false;
    auto it = ours.find(key);
    for (const Duration shift : {-kWeekRollover, kWeekRollover}) {
      if (it != ours.end()) break;
      it = ours.find((tpv.t + shift) / kMillisecond);
      wkro = it != ours.end();
    }
    char text[256];
    if (it == ours.end()) {
      ++r.missing;
      std::snprintf(text, sizeof text, "missing  %s  gpsd mode %d", format_seconds(tpv.t).c_str(), tpv.mode);
      r.details.push_back(text);
      continue;
    }
    matched[it->first] = true;
    const NmeaEpoch& e = *it->second;
    const int our_mode = mode_number(e.mode);
    const bool same_position = tpv.lat && tpv.lon && e.latitude_deg && e.longitude_deg &&
                               std::abs(*tpv.lat - *e.latitude_deg) <= kLatLonTolDeg &&
                               std::abs(*tpv.lon - *e.longitude_deg) <= kLatLonTolDeg;
    if (tpv.mode >= 2 && tpv.lat && e.latitude_deg) {
      ++r.both_positions;
      if (same_position) ++r.both_positions_agree;
    }
    // GPSD's mode 0 ("not seen") and 1 ("no fix") both mean: no position in this epoch.
    const int gpsd_mode = std::max(tpv.mode, 1);
    if (our_mode != gpsd_mode) {
      ++r.mode_differs;
      bool gsa_2d = false;
      for (const auto& g : e.gsa) gsa_2d = gsa_2d || g.fix_mode == 2;
      const char* kind = "other";
      if (gsa_2d && our_mode == 2 && gpsd_mode == 3) {
        ++r.mode_gsa_2d;
        kind = "GSA 2D";
      } else if (!e.gga && e.gsa.empty() && our_mode == 2 && gpsd_mode == 3) {
        ++r.mode_rmc_only;
        kind = "RMC only";
      } else if (e.gga && e.gga->satellites && *e.gga->satellites < 3 && gpsd_mode == 1) {
        ++r.mode_gga_few_sats;
        kind = "GGA <3 sats";
      } else {
        ++r.mode_other;
      }
      std::snprintf(text, sizeof text, "mode     %s  line %zu  ours %d gpsd %d  (%s)", format_seconds(tpv.t).c_str(),
                    e.first_line, our_mode, tpv.mode, kind);
      r.details.push_back(text);
      continue;
    }
    if (our_mode >= 2) {
      if (!same_position) {
        ++r.position_differs;
        std::snprintf(text, sizeof text, "position %s  line %zu  ours %.9f,%.9f gpsd %.9f,%.9f",
                      format_seconds(tpv.t).c_str(), e.first_line, e.latitude_deg.value_or(NAN),
                      e.longitude_deg.value_or(NAN), tpv.lat.value_or(NAN), tpv.lon.value_or(NAN));
        r.details.push_back(text);
        continue;
      }
    }
    ++r.agree;
    if (wkro) ++r.agree_wkro;
  }
  for (const auto& [key, e] : ours) {
    if (matched.count(key) != 0) continue;
    ++r.ours_only;
    char text[160];
    std::snprintf(text, sizeof text, "ours     %s  line %zu  ours %d", format_seconds(*e->t).c_str(), e->first_line,
                  mode_number(e->mode));
    r.details.push_back(text);
  }

  const Recording recording = read_nmea_capture(log);
  r.fixes = recording.gps.size();
  r.warnings = recording.report.total();
  return r;
}

int verbosity() {
  const char* v = std::getenv("NAVAID_NMEA_GPSD_VERBOSE");
  return v ? std::atoi(v) : 0;
}

TEST(NmeaGpsdReference, EveryCaptureAgreesWithGpsd) {
  NAVAID_REQUIRE_SHARED_DATA();
  const fs::path dir = testing::shared_data_dir() / "gpsd-nmea";
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  std::vector<fs::path> logs;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".log" && fs::exists(entry.path().string() + ".chk")) logs.push_back(entry.path());
  }
  std::sort(logs.begin(), logs.end());
  ASSERT_GE(logs.size(), 46u);

  CaptureResult total;
  std::size_t crashes = 0;
  std::vector<CaptureResult> results;
  for (const auto& log : logs) {
    try {
      results.push_back(compare_capture(log));
    } catch (const std::exception& e) {
      ++crashes;
      ADD_FAILURE() << log << ": " << e.what();
      continue;
    }
    const auto& r = results.back();
    total.reference += r.reference;
    total.agree += r.agree;
    total.agree_wkro += r.agree_wkro;
    total.missing += r.missing;
    total.mode_differs += r.mode_differs;
    total.mode_gsa_2d += r.mode_gsa_2d;
    total.mode_rmc_only += r.mode_rmc_only;
    total.mode_gga_few_sats += r.mode_gga_few_sats;
    total.mode_other += r.mode_other;
    total.position_differs += r.position_differs;
    total.ours_only += r.ours_only;
    total.both_positions += r.both_positions;
    total.both_positions_agree += r.both_positions_agree;
    total.our_epochs += r.our_epochs;
    total.fixes += r.fixes;
  }
  const double rate = total.reference ? static_cast<double>(total.agree) / static_cast<double>(total.reference) : 0;
  const double strict =
      total.reference ? static_cast<double>(total.agree - total.agree_wkro) / static_cast<double>(total.reference) : 0;

  if (verbosity() > 0) {
    std::printf("| capture | GPSD epochs | agree | via WKRO | missing | position | mode: GSA 2D | RMC only | "
                "GGA <3 sats | other | ours only | fixes |\n");
    for (const auto& r : results) {
      std::printf("| %s | %zu | %zu (%.1f%%) | %zu | %zu | %zu | %zu | %zu | %zu | %zu | %zu | %zu |\n", r.name.c_str(),
                  r.reference, r.agree,
                  r.reference ? 100.0 * static_cast<double>(r.agree) / static_cast<double>(r.reference) : 100.0,
                  r.agree_wkro, r.missing, r.position_differs, r.mode_gsa_2d, r.mode_rmc_only, r.mode_gga_few_sats,
                  r.mode_other, r.ours_only, r.fixes);
      if (verbosity() > 1) {
        for (const auto& d : r.details) std::printf("    %s\n", d.c_str());
      }
    }
  }
  std::printf("[nmea vs gpsd] %zu captures, %zu GPSD epochs: %zu agree (%.2f%%; %.2f%% without the WKRO shift), "
              "%zu missing, %zu mode (%zu GSA 2D, %zu RMC only, %zu GGA <3 sats, %zu other), %zu position; "
              "%zu ours only; %zu fixes; positions agree in %zu of %zu epochs where both have one\n",
              results.size(), total.reference, total.agree, 100.0 * rate, 100.0 * strict, total.missing,
              total.mode_differs, total.mode_gsa_2d, total.mode_rmc_only, total.mode_gga_few_sats, total.mode_other,
              total.position_differs, total.ours_only, total.fixes, total.both_positions_agree,
              total.both_positions);

  EXPECT_EQ(crashes, 0u);
  EXPECT_EQ(results.size(), logs.size());
  // Set just below what we achieve (94.2%, docs/nmea.md) so that regressions are caught. Every
  // GPSD epoch has an epoch of ours at the same time, and every position agrees to 1e-6 degree;
  // all disagreements are fix-mode policy differences explained in docs/nmea.md.
  EXPECT_GE(rate, 0.94);
  EXPECT_EQ(total.missing, 0u);
  EXPECT_EQ(total.position_differs, 0u);
  EXPECT_EQ(total.both_positions_agree, total.both_positions);
}

}  // namespace
}  // namespace navaid::io
