#pragma once
// The host's device link to the vibration controller (docs/device-protocol.md): the patterns a
// CueSession's scheduler sends go out as PATTERN / ALL_OFF frames over a SerialPort, each waits
// for its ACK and is retransmitted (same sequence) a bounded number of times; heartbeats keep the
// controller's link timeout from firing while nothing else is sent; no reply for timeout_s makes
// a kLinkLost system event (the cue generator says "link lost"), the first reply after that a
// kLinkRestored; a port that disappears is reopened every reconnect_s.
//
// Single-threaded and caller-driven: on_event() writes, poll() reads replies and runs the timers.
// Time comes from an injectable clock so that tests are deterministic.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "navaid/core/config.hpp"
#include "navaid/core/time.hpp"
#include "navaid/interaction/actuator_pattern.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/interaction/device_protocol.hpp"
#include "navaid/interaction/serial_port.hpp"
#include "navaid/interaction/system_event.hpp"

namespace navaid::interaction {

struct LinkConfig {
  /// A HEARTBEAT goes out when nothing was sent for this long. Four per second: the controller's
  /// link timeout (1000 ms) then survives three lost heartbeats in a row.
  double heartbeat_s = 0.25;
  /// No reply at all for this long: the link is lost. Equal to the controller's own timeout, so
  /// that when the host gives up the controller has switched its motors off too.
  double timeout_s = 1.0;
  /// A PATTERN / ALL_OFF without ACK for this long is sent again. A frame takes < 8 ms at
  /// 115200 baud; 100 ms leaves room for Bluetooth serial (BLE on the Bluno Nano: 20-50 ms).
  double ack_timeout_s = 0.1;
  /// Retransmissions of one frame before it is given up (1 + 3 tries = 0.4 s < timeout_s).
  int max_retransmits = 3;
  /// While the port is gone, how often to try reopening it.
  double reconnect_s = 0.5;
  int baud = 115200;
};

/// Keys interaction.link.heartbeat_s [0.02, 0.5], timeout_s [0.1, 30] (> heartbeat_s),
/// ack_timeout_s [0.001, 5], max_retransmits [0, 20], reconnect_s [0.01, 60], baud (one of
/// supported_baud_rates()). ConfigError when out of range.
LinkConfig read_link_config(const Config& config);

/// What the link did, for the run summary.
struct LinkReport {
  std::string port;
  DeviceKind device = DeviceKind::kBelt;
  bool link_up = true;
  std::uint64_t patterns_sent = 0;     ///< PATTERN frames handed to the link (first tries)
  std::uint64_t all_off_sent = 0;      ///< ALL_OFF frames (first tries)
  std::uint64_t heartbeats_sent = 0;
  std::uint64_t frames_sent = 0;       ///< every frame written: the above plus retransmissions
  std::uint64_t acked = 0;             ///< PATTERN / ALL_OFF acknowledged (applied or duplicate)
  std::uint64_t duplicate_acks = 0;    ///< of those, the controller had already applied it
  std::uint64_t retransmits = 0;
  std::uint64_t naks = 0;
  std::uint64_t failed = 0;            ///< given up after max_retransmits
  std::uint64_t superseded = 0;        ///< a newer pattern replaced one still waiting for its ACK
  std::uint64_t dropped_offline = 0;   ///< patterns that came while the port was closed
  std::uint64_t short_writes = 0;      ///< frames the port took only in part (output full)
  std::uint64_t heartbeat_replies = 0;
  std::uint64_t link_lost_events = 0;
  std::uint64_t link_restored_events = 0;
  std::uint64_t disconnects = 0;       ///< the port went away
  std::uint64_t reconnects = 0;        ///< ... and was opened again
  std::optional<Nak> last_nak;
  DecoderCounters decoder;             ///< the host decoder's counters (controller -> host)
  std::vector<double> latency_ms;      ///< handed to the link -> ACK received, per acked frame

  /// Everything above; latency as count, p50, p99 and max (the samples are not listed).
  nlohmann::ordered_json to_json() const;
};

class DeviceLink {
 public:
  using Clock = std::function<Timestamp()>;
  /// Nanoseconds of std::chrono::steady_clock.
  static Timestamp steady_now();

  /// Opens `port` (IoError when it cannot be opened) for a controller of `device`; keys from
  /// read_link_config(config). A HEARTBEAT with the resync flag goes out at once, so that the
  /// controller accepts our numbering whatever it saw before.
  DeviceLink(std::string port, DeviceKind device, const Config& config, Clock clock = &DeviceLink::steady_now);
  DeviceLink(std::string port, DeviceKind device, LinkConfig config, Clock clock = &DeviceLink::steady_now);
  ~DeviceLink();
  DeviceLink(const DeviceLink&) = delete;
  DeviceLink& operator=(const DeviceLink&) = delete;

  /// The CueSession sink: haptic kSent / kRefreshed send the event's pattern, kSwitchedOff sends
  /// ALL_OFF; everything else (speech, dropped cues, other devices' patterns) is ignored.
  void on_event(const CueEvent& event);
  /// Sends a pattern now (an empty command list is sent as ALL_OFF). A pattern for another device
  /// kind throws std::invalid_argument.
  void send(const ActuatorPattern& pattern);
  void send_all_off();

  /// Reads replies (waiting up to `wait_ms` for the first byte), handles ACK timeouts,
  /// retransmissions, heartbeats, the link timeout and reconnection. Returns the link events
  /// that happened, stamped `now` (the caller's clock, e.g. the guidance timeline's).
  std::vector<SystemEvent> poll(Timestamp now, int wait_ms = 0);
  /// The same, stamped with the link's clock.
  std::vector<SystemEvent> poll() { return poll(clock_(), 0); }

  /// Sends ALL_OFF (best effort) and closes the port; further calls do nothing.
  void close();

  bool link_up() const { return up_; }
  bool port_open() const { return port_.has_value(); }
  /// True while a PATTERN / ALL_OFF waits for its ACK.
  bool awaiting_ack() const { return pending_.has_value(); }
  const LinkConfig& config() const { return config_; }
  LinkReport report() const;

 private:
  struct Pending {
    std::uint8_t type = 0;
    std::vector<std::uint8_t> payload;
    std::uint16_t seq = 0;
    Timestamp handed_at = 0;  ///< first try
    Timestamp sent_at = 0;    ///< last try
    int tries = 0;
  };
  void send_command(std::uint8_t type, std::vector<std::uint8_t> payload);
  void transmit_pending();
  void send_heartbeat(bool resync);
  void write_frame(const std::uint8_t* data, std::size_t n);
  void lose_port(Timestamp now);
  void try_reopen(Timestamp now);
  void on_frame(const DecodedFrame& frame, Timestamp now);
  void link_event(bool up, Timestamp stamp);

  std::string path_;
  DeviceKind device_;
  LinkConfig config_;
  Clock clock_;
  std::optional<SerialPort> port_;
  FrameDecoder decoder_{FrameDirection::kDeviceToHost};
  std::uint16_t next_seq_ = 0;
  std::optional<Pending> pending_;
  bool up_ = true;       ///< as the cue generator assumes at start
  bool synced_ = false;  ///< a heartbeat was answered since the port was opened
  bool closed_ = false;
  Timestamp last_rx_ = 0;
  Timestamp last_tx_ = 0;
  Timestamp last_byte_at_ = 0;
  Timestamp next_reopen_ = 0;
  std::vector<SystemEvent> queued_;  ///< link events found while reading, handed out by poll()
  LinkReport report_;
};

}  // namespace navaid::interaction
