// Stop-and-wait on the device link: one PATTERN / ALL_OFF in flight at a time, a newer pattern
// replaces one still waiting (the controller only needs the latest state), retransmissions keep
// their sequence so the controller acknowledges a repeat without applying it twice.
#include "navaid/interaction/device_link.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"

namespace navaid::interaction {

namespace {

constexpr const char* kBaudKey = "interaction.link.baud";

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  // Nearest rank: the smallest sample with at least q of the samples at or below it.
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

nlohmann::ordered_json decoder_json(const DecoderCounters& c) {
  nlohmann::ordered_json j;
  j["frames_ok"] = c.frames_ok;
  j["crc_errors"] = c.crc_errors;
  j["length_errors"] = c.length_errors;
  j["unknown_type"] = c.unknown_type;
  j["replayed"] = c.replayed;
  j["seq_gaps"] = c.seq_gaps;
  j["truncated"] = c.truncated;
  j["resyncs"] = c.resyncs;
  j["dropped_bytes"] = c.dropped_bytes;
  return j;
}

}  // namespace

namespace {
const LinkConfig kDeviceLinkDefaults;
const ConfigKey<double> kHeartbeat{"interaction.link.heartbeat_s", kDeviceLinkDefaults.heartbeat_s, {0.02, 0.5},
                                   "a heartbeat goes out when nothing was sent for this long [s]"};
const ConfigKey<double> kTimeout{"interaction.link.timeout_s", kDeviceLinkDefaults.timeout_s, {0.1, 30.0},
                                 "no reply for this long: the link is lost [s] (> heartbeat_s)"};
const ConfigKey<double> kAckTimeout{"interaction.link.ack_timeout_s", kDeviceLinkDefaults.ack_timeout_s, {0.001, 5.0},
                                    "a pattern frame without ACK for this long is sent again [s]"};
const ConfigKey<int> kMaxRetransmits{"interaction.link.max_retransmits", kDeviceLinkDefaults.max_retransmits, 0, 20,
                                     "retransmissions of one frame before it is given up"};
const ConfigKey<double> kReconnect{"interaction.link.reconnect_s", kDeviceLinkDefaults.reconnect_s, {0.01, 60.0},
                                   "while the port is gone, try reopening it this often [s]"};
const ConfigKey<int> kBaud{kBaudKey, kDeviceLinkDefaults.baud, 1, 4000000, "serial baud rate (a standard rate)"};
}  // namespace

ConfigSchema link_config_schema() {
  return ConfigSchema().add(kHeartbeat).add(kTimeout).add(kAckTimeout).add(kMaxRetransmits).add(kReconnect).add(kBaud);
}

LinkConfig read_link_config(const Config& config) {
  LinkConfig c;
  c.heartbeat_s = get(config, kHeartbeat);
  c.timeout_s = get(config, kTimeout);
  if (c.timeout_s <= c.heartbeat_s) {
    const char* key = config.has("interaction.link.timeout_s") ? "interaction.link.timeout_s"
                                                                : "interaction.link.heartbeat_s";
    throw ConfigError(config.origin(key), key,
                      "timeout_s " + std::to_string(c.timeout_s) + " must exceed heartbeat_s " +
                          std::to_string(c.heartbeat_s) + " (the link would be lost between two heartbeats)");
  }
  c.ack_timeout_s = get(config, kAckTimeout);
  c.max_retransmits = get(config, kMaxRetransmits);
  c.reconnect_s = get(config, kReconnect);
  c.baud = get(config, kBaud);
  const auto& rates = supported_baud_rates();
  if (std::find(rates.begin(), rates.end(), c.baud) == rates.end()) {
    std::string list;
    for (int r : rates) list += (list.empty() ? "" : ", ") + std::to_string(r);
    throw ConfigError(config.origin(kBaudKey), kBaudKey,
                      "baud rate " + std::to_string(c.baud) + " is not supported (one of " + list + ")");
  }
  return c;
}

nlohmann::ordered_json LinkReport::to_json() const {
  nlohmann::ordered_json j;
  j["port"] = port;
  j["device"] = std::string(to_string(device));
  j["link_up"] = link_up;
  j["patterns_sent"] = patterns_sent;
  j["all_off_sent"] = all_off_sent;
  j["heartbeats_sent"] = heartbeats_sent;
  j["frames_sent"] = frames_sent;
  j["acked"] = acked;
  j["duplicate_acks"] = duplicate_acks;
  j["retransmits"] = retransmits;
  j["naks"] = naks;
  j["failed"] = failed;
  j["superseded"] = superseded;
  j["dropped_offline"] = dropped_offline;
  j["short_writes"] = short_writes;
  j["heartbeat_replies"] = heartbeat_replies;
  j["link_lost_events"] = link_lost_events;
  j["link_restored_events"] = link_restored_events;
  j["disconnects"] = disconnects;
  j["reconnects"] = reconnects;
  if (last_nak) {
    j["last_nak"] = {{"seq", last_nak->seq},
                     {"reason", std::string(to_string(static_cast<NakReason>(last_nak->reason)))},
                     {"detail", last_nak->detail}};
  } else {
    j["last_nak"] = nullptr;
  }
  j["decoder"] = decoder_json(decoder);
  j["latency_ms"] = {{"count", latency_ms.size()},
                     {"p50", percentile(latency_ms, 0.50)},
                     {"p99", percentile(latency_ms, 0.99)},
                     {"max", latency_ms.empty() ? 0.0 : *std::max_element(latency_ms.begin(), latency_ms.end())}};
  return j;
}

Timestamp DeviceLink::steady_now() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

DeviceLink::DeviceLink(std::string port, DeviceKind device, const Config& config, Clock clock)
    : DeviceLink(std::move(port), device, read_link_config(config), std::move(clock)) {}

DeviceLink::DeviceLink(std::string port, DeviceKind device, LinkConfig config, Clock clock)
    : path_(std::move(port)), device_(device), config_(config), clock_(std::move(clock)) {
  port_.emplace(path_, config_.baud);
  const Timestamp now = clock_();
  // The controller gets timeout_s from now to answer before we call the link lost.
  last_rx_ = now;
  last_tx_ = now;
  report_.port = path_;
  report_.device = device_;
  send_heartbeat(true);
}

DeviceLink::~DeviceLink() {
  try {
    close();
  } catch (...) {
    // Closing is best effort; a destructor must not throw.
  }
}

void DeviceLink::on_event(const CueEvent& event) {
  if (event.channel != CueChannel::kHaptic || closed_) return;
  switch (event.outcome) {
    case CueOutcome::kSent:
    case CueOutcome::kRefreshed:
      if (event.pattern && event.pattern->device == device_) send(*event.pattern);
      return;
    case CueOutcome::kSwitchedOff: send_all_off(); return;
    default: return;
  }
}

void DeviceLink::send(const ActuatorPattern& pattern) {
  if (pattern.device != device_) {
    throw std::invalid_argument("a " + std::string(to_string(pattern.device)) + " pattern cannot go to the " +
                                std::string(to_string(device_)) + " on " + path_);
  }
  if (pattern.commands.empty()) {
    send_all_off();
    return;
  }
  FrameBuffer buf;
  const std::size_t n = encode_pattern(pattern, 0, buf.data());  // validates the command count
  if (!port_ || closed_) {
    ++report_.dropped_offline;
    return;
  }
  ++report_.patterns_sent;
  send_command(static_cast<std::uint8_t>(FrameType::kPattern),
               std::vector<std::uint8_t>(buf.begin() + protocol::kHeaderSize, buf.begin() + static_cast<long>(n - 2)));
}

void DeviceLink::send_all_off() {
  if (!port_ || closed_) {
    ++report_.dropped_offline;
    return;
  }
  ++report_.all_off_sent;
  send_command(static_cast<std::uint8_t>(FrameType::kAllOff), {});
}

void DeviceLink::send_command(std::uint8_t type, std::vector<std::uint8_t> payload) {
  if (pending_) ++report_.superseded;
  const Timestamp now = clock_();
  pending_ = Pending{type, std::move(payload), next_seq_++, now, now, 1};
  transmit_pending();
}

void DeviceLink::transmit_pending() {
  FrameBuffer buf;
  const std::size_t n = encode_frame(pending_->type, pending_->seq, pending_->payload.data(), pending_->payload.size(),
                                     buf.data());
  write_frame(buf.data(), n);
}

void DeviceLink::send_heartbeat(bool resync) {
  FrameBuffer buf;
  const std::size_t n = encode_heartbeat(next_seq_++, resync, buf.data());
  ++report_.heartbeats_sent;
  write_frame(buf.data(), n);
}

void DeviceLink::write_frame(const std::uint8_t* data, std::size_t n) {
  if (!port_) return;
  const Timestamp now = clock_();
  try {
    const std::size_t written = port_->write(data, n, 20);
    if (written < n) ++report_.short_writes;
    ++report_.frames_sent;
    last_tx_ = now;
  } catch (const IoError&) {
    lose_port(now);
  }
}

void DeviceLink::lose_port(Timestamp now) {
  port_.reset();
  ++report_.disconnects;
  // Whatever waited for an ACK will not get one; the scheduler's next refresh sends it again.
  if (pending_) ++report_.failed;
  pending_.reset();
  next_reopen_ = now + seconds_to_ns(config_.reconnect_s);
}

void DeviceLink::try_reopen(Timestamp now) {
  if (now < next_reopen_) return;
  try {
    port_.emplace(path_, config_.baud);
  } catch (const IoError&) {
    next_reopen_ = now + seconds_to_ns(config_.reconnect_s);
    return;
  }
  ++report_.reconnects;
  decoder_.reset();
  synced_ = false;
  send_heartbeat(true);
}

void DeviceLink::link_event(bool up, Timestamp stamp) {
  up_ = up;
  if (up) {
    ++report_.link_restored_events;
  } else {
    ++report_.link_lost_events;
  }
  queued_.push_back({stamp, up ? SystemEventKind::kLinkRestored : SystemEventKind::kLinkLost, path_});
}

void DeviceLink::on_frame(const DecodedFrame& frame, Timestamp now) {
  if (!frame.well_formed) return;
  last_rx_ = now;
  if (!up_) link_event(true, 0);
  if (const auto ack = parse_ack(frame)) {
    if (!pending_ || ack->seq != pending_->seq) return;  // a late ACK of a superseded frame
    if (ack->status == AckStatus::kStale) {
      // The controller's numbering is ahead of ours (it outlived a restart of the host and our
      // resync heartbeat was lost): resynchronise and send the frame again under a new number.
      synced_ = false;
      send_heartbeat(true);
      if (!pending_) return;  // the write failed and the port is gone
      if (pending_->tries > config_.max_retransmits) {
        ++report_.failed;
        pending_.reset();
        return;
      }
      ++pending_->tries;
      ++report_.retransmits;
      pending_->seq = next_seq_++;
      pending_->sent_at = now;
      transmit_pending();
      return;
    }
    ++report_.acked;
    if (ack->status == AckStatus::kDuplicate) ++report_.duplicate_acks;
    report_.latency_ms.push_back(static_cast<double>(now - pending_->handed_at) * 1e-6);
    pending_.reset();
  } else if (const auto nak = parse_nak(frame)) {
    ++report_.naks;
    report_.last_nak = *nak;
    // A refused frame would be refused again: no retransmission.
    if (pending_ && nak->seq == pending_->seq) pending_.reset();
  } else if (parse_heartbeat_reply(frame)) {
    ++report_.heartbeat_replies;
    // Every heartbeat carries the resync flag until one is answered.
    synced_ = true;
  }
}

std::vector<SystemEvent> DeviceLink::poll(Timestamp now, int wait_ms) {
  if (closed_) return {};
  if (!port_) try_reopen(clock_());
  if (port_) {
    try {
      std::uint8_t buf[512];
      int wait = wait_ms;
      for (int i = 0; i < 64 && port_; ++i) {
        const std::size_t n = port_->read(buf, sizeof buf, wait);
        wait = 0;
        if (n == 0) break;
        const Timestamp t = clock_();
        last_byte_at_ = t;
        decoder_.feed(buf, n, [&](const DecodedFrame& f) { on_frame(f, t); });
      }
    } catch (const IoError&) {
      lose_port(clock_());
    }
  }
  const Timestamp t = clock_();
  // A partial reply whose rest never came: abandon it so the next reply is not held up.
  if (decoder_.has_partial() && t - last_byte_at_ > protocol::kInterbyteTimeoutMs * 1'000'000LL) {
    decoder_.flush([&](const DecodedFrame& f) { on_frame(f, t); });
  }
  if (pending_ && port_ && t - pending_->sent_at >= seconds_to_ns(config_.ack_timeout_s)) {
    if (pending_->tries > config_.max_retransmits) {
      ++report_.failed;
      pending_.reset();
    } else {
      ++pending_->tries;
      ++report_.retransmits;
      pending_->sent_at = t;
      transmit_pending();
    }
  }
  if (port_ && t - last_tx_ >= seconds_to_ns(config_.heartbeat_s)) send_heartbeat(!synced_);
  if (up_ && t - last_rx_ >= seconds_to_ns(config_.timeout_s)) link_event(false, 0);
  std::vector<SystemEvent> events = std::move(queued_);
  queued_.clear();
  for (SystemEvent& e : events) e.t = now;
  return events;
}

void DeviceLink::close() {
  if (closed_) return;
  closed_ = true;
  if (port_) {
    // Leave the motors off rather than waiting for their holds to run out.
    FrameBuffer buf;
    const std::size_t n = encode_all_off(next_seq_++, buf.data());
    try {
      port_->write(buf.data(), n, 20);
      ++report_.all_off_sent;
      ++report_.frames_sent;
    } catch (const IoError&) {
      // The port is going away anyway.
    }
    port_.reset();
  }
  pending_.reset();
}

LinkReport DeviceLink::report() const {
  LinkReport r = report_;
  r.link_up = up_;
  r.decoder = decoder_.counters();
  return r;
}

}  // namespace navaid::interaction
