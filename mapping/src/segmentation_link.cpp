#include "navaid/mapping/segmentation_link.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"

namespace navaid::mapping {

namespace {

constexpr const char* kOutagesKey = "mapping.network.outages";
constexpr const char* kPeriodKey = "mapping.network.check_period_s";
constexpr const char* kTimeoutKey = "mapping.network.timeout_s";
constexpr Range kOutageRange{0.0, 1e6};  // seconds after the start: up to 11 days of recording

/// The checks the reader and the constructor share; `origin` names where a key came from.
void validate(const SegmentationLinkConfig& c, const std::function<std::string(const char*)>& origin) {
  if (!(c.check_period_s >= 0.01 && c.check_period_s <= 3600))
    throw ConfigError(origin(kPeriodKey), kPeriodKey, "must be in [0.01, 3600] s");
  if (!(c.timeout_s >= 0.001 && c.timeout_s < c.check_period_s))
    throw ConfigError(origin(kTimeoutKey), kTimeoutKey,
                      "must be at least 0.001 s and shorter than mapping.network.check_period_s (" +
                          fmt::format("{}", c.check_period_s) + " s): a probe's reply is due before the next probe");
  for (std::size_t i = 0; i < c.outages.size(); ++i) {
    const auto& o = c.outages[i];
    const std::string key = std::string(kOutagesKey) + "[" + std::to_string(i) + "]";
    if (!(o.start_s >= kOutageRange.min && o.end_s <= kOutageRange.max))
      throw ConfigError(origin(kOutagesKey), key, "outage times must be in [0, 1e6] s after the recording start");
    if (!(o.end_s > o.start_s))
      throw ConfigError(origin(kOutagesKey), key,
                        fmt::format("outage [{}, {}] ends before it starts (expected start_s < end_s)", o.start_s, o.end_s));
    if (i > 0 && o.start_s < c.outages[i - 1].end_s)
      throw ConfigError(origin(kOutagesKey), key,
                        fmt::format("outage starting at {} s overlaps or precedes the one ending at {} s", o.start_s,
                                    c.outages[i - 1].end_s) +
                            " (outages must be in time order, not overlapping)");
  }
}

}  // namespace

namespace {
const ConfigKey<double> kPeriod{kPeriodKey, SegmentationLinkConfig{}.check_period_s, {0.01, 3600},
                                "how often the edge probes the segmentation server [s]"};
const ConfigKey<double> kTimeout{kTimeoutKey, SegmentationLinkConfig{}.timeout_s, {0.001, 3600},
                                 "how long a probe waits for its reply [s] (< check_period_s)"};
// Read by hand below (pairs, a friendlier message): declared here for the schema.
const ConfigKey<std::vector<double>> kOutages{kOutagesKey, std::nullopt, 0, kOutageRange,
                                              "network outages as a flat list of start_s, end_s pairs after the "
                                              "recording start, e.g. [1.0, 2.0, 5.0, 6.5]; absent: no link"};
}  // namespace

ConfigSchema segmentation_link_config_schema() { return ConfigSchema().add(kPeriod).add(kTimeout).add(kOutages); }

std::optional<SegmentationLinkConfig> read_segmentation_link_config(const Config& config) {
  SegmentationLinkConfig c;
  c.check_period_s = get(config, kPeriod);
  c.timeout_s = get(config, kTimeout);
  if (!config.has(kOutagesKey)) return std::nullopt;
  std::vector<double> flat;
  try {
    flat = get(config, kOutages);
  } catch (const ConfigError&) {
    throw ConfigError(config.origin(kOutagesKey), kOutagesKey,
                      "expected a flat list of start_s, end_s pairs in [0, 1e6] s after the recording start, e.g. "
                      "[1.0, 2.0, 5.0, 6.5] for two outages");
  }
  if (flat.size() % 2 != 0)
    throw ConfigError(config.origin(kOutagesKey), kOutagesKey,
                      "expected start_s, end_s pairs, found an odd number of values (" + std::to_string(flat.size()) + ")");
  for (std::size_t i = 0; i < flat.size(); i += 2) c.outages.push_back({flat[i], flat[i + 1]});
  validate(c, [&config](const char* key) { return config.origin(key); });
  return c;
}

const char* network_change_name(NetworkChangeKind kind) {
  return kind == NetworkChangeKind::kLost ? "lost" : "restored";
}

SegmentationLink::SegmentationLink(const SegmentationLinkConfig& config, Timestamp start) {
  validate(config, [](const char*) { return std::string("<SegmentationLinkConfig>"); });
  // Integer nanoseconds from here on: the probe times, and so the changes, are exact.
  const Timestamp period = seconds_to_ns(config.check_period_s);
  const Timestamp timeout = seconds_to_ns(config.timeout_s);
  std::vector<Interval> rel;  // relative to start
  for (const auto& o : config.outages) rel.push_back({seconds_to_ns(o.start_s), seconds_to_ns(o.end_s)});
  for (const auto& o : rel) outages_.push_back({start + o.start, start + o.end});

  const auto first_probe_at_or_after = [period](Timestamp t) { return (t + period - 1) / period * period; };
  const auto inside = [&rel](Timestamp t) -> const Interval* {
    for (const auto& o : rel)
      if (t >= o.start && t < o.end) return &o;
    return nullptr;
  };
  // The link is up whenever an outage begins (a restore happens at a probe outside every outage,
  // and outages the probes skipped over are consumed on the way).
  std::size_t i = 0;
  while (i < rel.size()) {
    const Timestamp probe = first_probe_at_or_after(rel[i].start);
    if (probe >= rel[i].end) {  // no probe fell inside: labels lost, nothing detected
      ++i;
      continue;
    }
    schedule_.push_back({start + probe + timeout, NetworkChangeKind::kLost});
    Timestamp restore = first_probe_at_or_after(rel[i].end);
    while (const Interval* o = inside(restore)) restore = first_probe_at_or_after(o->end);
    schedule_.push_back({start + restore, NetworkChangeKind::kRestored});
    while (i < rel.size() && rel[i].end <= restore) ++i;
  }
}

bool SegmentationLink::network_up(Timestamp t) const {
  return std::none_of(outages_.begin(), outages_.end(), [t](const Interval& o) { return t >= o.start && t < o.end; });
}

bool SegmentationLink::link_up(Timestamp t) const {
  const auto after = std::upper_bound(schedule_.begin(), schedule_.end(), t,
                                      [](Timestamp v, const NetworkChange& c) { return v < c.t; });
  return after == schedule_.begin() || std::prev(after)->kind == NetworkChangeKind::kRestored;
}

bool SegmentationLink::labels_available(Timestamp t) {
  const auto after = std::upper_bound(schedule_.begin(), schedule_.end(), t,
                                      [](Timestamp v, const NetworkChange& c) { return v < c.t; });
  observed_ = std::max(observed_, static_cast<std::size_t>(after - schedule_.begin()));
  return network_up(t) && link_up(t);
}

std::vector<NetworkChange> SegmentationLink::changes() const {
  return {schedule_.begin(), schedule_.begin() + static_cast<std::ptrdiff_t>(observed_)};
}

std::vector<NetworkChange> SegmentationLink::take_changes() {
  std::vector<NetworkChange> out(schedule_.begin() + static_cast<std::ptrdiff_t>(taken_),
                                 schedule_.begin() + static_cast<std::ptrdiff_t>(observed_));
  taken_ = observed_;
  return out;
}

std::size_t SegmentationLink::outages_detected() const {
  return static_cast<std::size_t>(std::count_if(schedule_.begin(), schedule_.begin() + static_cast<std::ptrdiff_t>(observed_),
                                                [](const NetworkChange& c) { return c.kind == NetworkChangeKind::kLost; }));
}

}  // namespace navaid::mapping
