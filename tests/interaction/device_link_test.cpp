// The host DeviceLink and SerialPort over real pseudo-terminals. Most tests play the controller
// by hand on the pty master with a fake clock (every retransmission, timeout and reconnection is
// decided by the test, not by wall time); the rest run the C firmware behind the pty
// (SimulatedController) and through a socat null-modem pair.
#include "navaid/interaction/device_link.hpp"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "device_link_testing.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/belt_adapter.hpp"
#include "navaid_link_sim.hpp"
#include "test_support.hpp"

namespace navaid::interaction {
namespace {

using testing::Bytes;
using navaid::testing::ScratchDir;

/// A pseudo-terminal whose master the test holds: the test is the controller.
class PtyController {
 public:
  PtyController() {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
    EXPECT_GE(master_, 0);
    EXPECT_EQ(::grantpt(master_), 0);
    EXPECT_EQ(::unlockpt(master_), 0);
    char name[128] = {};
    EXPECT_EQ(::ptsname_r(master_, name, sizeof name), 0);
    path_ = name;
  }
  ~PtyController() { close(); }
  void close() {
    if (master_ >= 0) ::close(master_);
    master_ = -1;
  }
  const std::string& path() const { return path_; }

  /// Frames the host wrote since the last call (waits briefly for the first one).
  std::vector<testing::Delivered> frames(int wait_ms = 200) {
    std::uint8_t buf[1024];
    pollfd p{master_, POLLIN, 0};
    int wait = wait_ms;
    while (::poll(&p, 1, wait) > 0 && (p.revents & POLLIN) != 0) {
      const ssize_t n = ::read(master_, buf, sizeof buf);
      if (n <= 0) break;
      decoder_.feed(buf, static_cast<std::size_t>(n));
      wait = 10;  // the rest of a burst
    }
    std::vector<testing::Delivered> out;
    out.swap(decoder_.frames);
    return out;
  }
  void write(const Bytes& b) { ASSERT_EQ(::write(master_, b.data(), b.size()), static_cast<ssize_t>(b.size())); }
  void ack(std::uint16_t seq, AckStatus status = AckStatus::kApplied) {
    FrameBuffer f;
    write(testing::frame_bytes(f.data(), encode_ack(reply_seq_++, Ack{seq, status}, f.data())));
  }
  void nak(std::uint16_t seq, NakReason reason, std::uint8_t detail) {
    FrameBuffer f;
    write(testing::frame_bytes(
        f.data(), encode_nak(reply_seq_++, Nak{seq, static_cast<std::uint8_t>(reason), detail}, f.data())));
  }
  void heartbeat_reply(std::uint16_t seq) {
    FrameBuffer f;
    HeartbeatReply r;
    r.seq = seq;
    write(testing::frame_bytes(f.data(), encode_heartbeat_reply(reply_seq_++, r, f.data())));
  }

 private:
  int master_ = -1;
  std::string path_;
  testing::HostCollector decoder_{FrameDirection::kHostToDevice};
  std::uint16_t reply_seq_ = 0;
};

struct FakeClock {
  Timestamp now = 1'000'000'000;
  void advance_ms(double ms) { now += static_cast<Timestamp>(ms * 1e6); }
  DeviceLink::Clock fn() {
    return [this] { return now; };
  }
};

CueEvent haptic(CueOutcome outcome, std::optional<ActuatorPattern> pattern) {
  CueEvent e;
  e.channel = CueChannel::kHaptic;
  e.outcome = outcome;
  e.pattern = std::move(pattern);
  return e;
}

std::vector<SystemEventKind> kinds(const std::vector<SystemEvent>& events) {
  std::vector<SystemEventKind> k;
  for (const SystemEvent& e : events) k.push_back(e.kind);
  return k;
}

TEST(LinkConfig, DefaultsAndRangeChecks) {
  const LinkConfig d = read_link_config(Config());
  EXPECT_DOUBLE_EQ(d.heartbeat_s, 0.25);
  EXPECT_DOUBLE_EQ(d.timeout_s, 1.0);
  EXPECT_LT(d.heartbeat_s * 1000.0, NAVAID_LINK_DEFAULT_TIMEOUT_MS);  // below the firmware's timeout
  EXPECT_EQ(d.baud, 115200);
  const LinkConfig c = read_link_config(Config::parse(
      "interaction:\n  link:\n    heartbeat_s: 0.1\n    timeout_s: 2\n    max_retransmits: 0\n    baud: 57600\n"));
  EXPECT_DOUBLE_EQ(c.heartbeat_s, 0.1);
  EXPECT_DOUBLE_EQ(c.timeout_s, 2.0);
  EXPECT_EQ(c.max_retransmits, 0);
  EXPECT_EQ(c.baud, 57600);
  for (const char* bad : {"heartbeat_s: 0.9", "heartbeat_s: 0", "timeout_s: 0.01", "ack_timeout_s: 0",
                          "max_retransmits: 21", "reconnect_s: -1", "baud: 12345"}) {
    const std::string yaml = std::string("interaction:\n  link:\n    ") + bad + "\n";
    const std::string msg = navaid::testing::error_message<ConfigError>([&] { read_link_config(Config::parse(yaml)); }, bad);
    EXPECT_NE(msg.find("interaction.link."), std::string::npos) << msg;
  }
  const std::string msg = navaid::testing::error_message<ConfigError>([&] {
    read_link_config(Config::parse("interaction:\n  link:\n    heartbeat_s: 0.5\n    timeout_s: 0.4\n"));
  });
  EXPECT_NE(msg.find("must exceed heartbeat_s"), std::string::npos) << msg;
}

TEST(SerialPort, ClearErrorsForMissingPathsAndNonTerminals) {
  std::string msg = navaid::testing::error_message<IoError>([] { SerialPort p("/dev/navaid-no-such-port"); });
  EXPECT_NE(msg.find("/dev/navaid-no-such-port"), std::string::npos) << msg;
  EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;
  ScratchDir dir("serial_port");
  navaid::testing::write_text(dir / "plain.txt", "not a tty");
  msg = navaid::testing::error_message<IoError>([&] { SerialPort p((dir / "plain.txt").string()); });
  EXPECT_NE(msg.find("plain.txt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a serial port (tty)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Inappropriate ioctl"), std::string::npos) << msg;
  PtyController pty;
  msg = navaid::testing::error_message<IoError>([&] { SerialPort p(pty.path(), 12345); });
  EXPECT_NE(msg.find("unsupported baud rate 12345"), std::string::npos) << msg;
}

TEST(SerialPort, RawBytesBothWaysTimeoutAndHangUp) {
  PtyController pty;
  SerialPort port(pty.path(), 115200);
  std::uint8_t buf[64];
  EXPECT_EQ(port.read(buf, sizeof buf, 0), 0u);
  EXPECT_EQ(port.read(buf, sizeof buf, 5), 0u);  // nothing within the timeout
  // Every byte value passes unchanged (raw mode: no CR/LF mapping, no XON/XOFF, no echo).
  Bytes all(256);
  for (int i = 0; i < 256; ++i) all[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
  pty.write(all);
  Bytes got;
  while (got.size() < all.size()) {
    const std::size_t n = port.read(buf, sizeof buf, 200);
    ASSERT_GT(n, 0u);
    got.insert(got.end(), buf, buf + n);
  }
  EXPECT_EQ(got, all);
  const Bytes hb = testing::host_heartbeat(1);
  EXPECT_EQ(port.write(hb.data(), hb.size()), hb.size());
  const auto frames = pty.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, 0x03);
  pty.close();
  const std::string msg = navaid::testing::error_message<IoError>([&] { port.read(buf, sizeof buf, 100); });
  EXPECT_NE(msg.find(pty.path()), std::string::npos) << msg;
}

class DeviceLinkTest : public ::testing::Test {
 protected:
  LinkConfig config() const {
    LinkConfig c;
    c.ack_timeout_s = 0.1;
    c.max_retransmits = 2;
    return c;
  }
  FakeClock clock_;
  PtyController pty_;
};

TEST_F(DeviceLinkTest, OpensWithAResyncHeartbeatAndSendsPatternsUntilAcked) {
  DeviceLink link(pty_.path(), DeviceKind::kBelt, config(), clock_.fn());
  auto frames = pty_.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, static_cast<std::uint8_t>(FrameType::kHeartbeat));
  EXPECT_EQ(frames[0].payload, Bytes{protocol::kHeartbeatResync});
  const std::uint16_t hb_seq = frames[0].seq;

  ActuatorPattern p = testing::belt_pattern(1, 700, 1100, 250, 250);
  link.on_event(haptic(CueOutcome::kSent, p));
  EXPECT_TRUE(link.awaiting_ack());
  frames = pty_.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, static_cast<std::uint8_t>(FrameType::kPattern));
  EXPECT_EQ(frames[0].seq, static_cast<std::uint16_t>(hb_seq + 1));
  const DecodedFrame df{frames[0].type, frames[0].seq, SequenceStatus::kNew, true, frames[0].payload.data(),
                        frames[0].payload.size()};
  const auto back = parse_pattern(df);
  ASSERT_TRUE(back);
  ASSERT_EQ(back->commands.size(), 1u);
  EXPECT_EQ(back->commands[0].level, 700);
  EXPECT_EQ(back->commands[0].on_ms, 250);

  clock_.advance_ms(12);
  pty_.ack(frames[0].seq);
  EXPECT_TRUE(link.poll(0, 200).empty());
  EXPECT_FALSE(link.awaiting_ack());
  const LinkReport r = link.report();
  EXPECT_EQ(r.patterns_sent, 1u);
  EXPECT_EQ(r.acked, 1u);
  EXPECT_EQ(r.retransmits, 0u);
  ASSERT_EQ(r.latency_ms.size(), 1u);
  EXPECT_DOUBLE_EQ(r.latency_ms[0], 12.0);

  // Speech, dropped cues and other devices' patterns do not reach the wire; kSwitchedOff is ALL_OFF.
  CueEvent speech;
  speech.channel = CueChannel::kSpeech;
  speech.outcome = CueOutcome::kSpoken;
  link.on_event(speech);
  link.on_event(haptic(CueOutcome::kRateLimited, p));
  ActuatorPattern hand = p;
  hand.device = DeviceKind::kHand;
  link.on_event(haptic(CueOutcome::kSent, hand));
  EXPECT_THROW(link.send(hand), std::invalid_argument);
  EXPECT_TRUE(pty_.frames(20).empty());
  link.on_event(haptic(CueOutcome::kSwitchedOff, ActuatorPattern{}));
  frames = pty_.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, static_cast<std::uint8_t>(FrameType::kAllOff));
}

TEST_F(DeviceLinkTest, RetransmitsWithTheSameSequenceThenGivesUp) {
  DeviceLink link(pty_.path(), DeviceKind::kBelt, config(), clock_.fn());
  pty_.frames();
  link.send(testing::belt_pattern(0, 500, 1100));
  const auto first = pty_.frames();
  ASSERT_EQ(first.size(), 1u);
  clock_.advance_ms(99);
  link.poll(0);
  EXPECT_TRUE(pty_.frames(20).empty());  // not yet
  for (int attempt = 1; attempt <= 2; ++attempt) {
    clock_.advance_ms(1 + (attempt == 2 ? 99 : 0));
    link.poll(0);
    const auto again = pty_.frames();
    ASSERT_EQ(again.size(), 1u) << attempt;
    // The same frame under the same sequence: the controller's decoder sees a duplicate.
    EXPECT_EQ(again[0].seq, first[0].seq) << attempt;
    EXPECT_EQ(again[0].payload, first[0].payload) << attempt;
    EXPECT_EQ(again[0].seq_status, NAVAID_LINK_SEQ_DUPLICATE) << attempt;
  }
  clock_.advance_ms(100);
  link.poll(0);
  EXPECT_FALSE(link.awaiting_ack());
  EXPECT_TRUE(pty_.frames(20).empty());
  LinkReport r = link.report();
  EXPECT_EQ(r.retransmits, 2u);
  EXPECT_EQ(r.failed, 1u);
  EXPECT_EQ(r.frames_sent, 4u);  // heartbeat + 3 tries

  // A duplicate ACK (the first try was applied, its ACK lost) completes the frame as well.
  link.send(testing::belt_pattern(0, 600, 1100));
  const auto p = pty_.frames();
  clock_.advance_ms(100);
  link.poll(0);
  ASSERT_EQ(pty_.frames().size(), 1u);
  pty_.ack(p[0].seq, AckStatus::kDuplicate);
  link.poll(0, 200);
  r = link.report();
  EXPECT_EQ(r.acked, 1u);
  EXPECT_EQ(r.duplicate_acks, 1u);
  EXPECT_FALSE(link.awaiting_ack());
}

TEST_F(DeviceLinkTest, NaksAreNotRetransmittedAndNewerPatternsSupersede) {
  DeviceLink link(pty_.path(), DeviceKind::kBelt, config(), clock_.fn());
  pty_.frames();
  link.send(testing::belt_pattern(4, 1000, 1100));
  const auto f = pty_.frames();
  pty_.nak(f[0].seq, NakReason::kBadActuator, 4);
  link.poll(0, 200);
  EXPECT_FALSE(link.awaiting_ack());
  clock_.advance_ms(500);
  link.poll(0);
  for (const auto& fr : pty_.frames(20)) EXPECT_NE(fr.type, static_cast<std::uint8_t>(FrameType::kPattern));
  LinkReport r = link.report();
  EXPECT_EQ(r.naks, 1u);
  ASSERT_TRUE(r.last_nak);
  EXPECT_EQ(r.last_nak->reason, static_cast<std::uint8_t>(NakReason::kBadActuator));
  EXPECT_EQ(r.to_json()["last_nak"]["reason"], "bad_actuator");

  link.send(testing::belt_pattern(0, 100, 1100));
  link.send(testing::belt_pattern(1, 200, 1100));
  const auto two = pty_.frames();
  ASSERT_EQ(two.size(), 2u);
  pty_.ack(two[0].seq);  // late ACK of the replaced one: ignored
  link.poll(0, 200);
  EXPECT_TRUE(link.awaiting_ack());
  pty_.ack(two[1].seq);
  link.poll(0, 200);
  EXPECT_FALSE(link.awaiting_ack());
  r = link.report();
  EXPECT_EQ(r.superseded, 1u);
  EXPECT_EQ(r.acked, 1u);
}

TEST_F(DeviceLinkTest, StaleAckResynchronisesAndRenumbers) {
  DeviceLink link(pty_.path(), DeviceKind::kBelt, config(), clock_.fn());
  pty_.frames();
  link.send(testing::belt_pattern(2, 300, 1100));
  const auto f = pty_.frames();
  pty_.ack(f[0].seq, AckStatus::kStale);  // the controller's base is ahead of us
  link.poll(0, 200);
  const auto again = pty_.frames();
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[0].type, static_cast<std::uint8_t>(FrameType::kHeartbeat));
  EXPECT_EQ(again[0].payload, Bytes{protocol::kHeartbeatResync});
  EXPECT_EQ(again[1].type, static_cast<std::uint8_t>(FrameType::kPattern));
  EXPECT_EQ(again[1].payload, f[0].payload);
  EXPECT_GT(static_cast<std::uint16_t>(again[1].seq - again[0].seq), 0u);
  pty_.ack(again[1].seq);
  link.poll(0, 200);
  EXPECT_FALSE(link.awaiting_ack());
}

TEST_F(DeviceLinkTest, HeartbeatsLinkLostOnceAndRestored) {
  DeviceLink link(pty_.path(), DeviceKind::kBelt, config(), clock_.fn());
  auto frames = pty_.frames();
  clock_.advance_ms(249);
  link.poll(0);
  EXPECT_TRUE(pty_.frames(20).empty());
  clock_.advance_ms(1);
  link.poll(0);
  frames = pty_.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, static_cast<std::uint8_t>(FrameType::kHeartbeat));
  EXPECT_EQ(frames[0].payload, Bytes{protocol::kHeartbeatResync});  // until one is answered
  pty_.heartbeat_reply(frames[0].seq);
  EXPECT_TRUE(link.poll(0, 200).empty());
  clock_.advance_ms(250);
  link.poll(0);
  frames = pty_.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].payload, Bytes{0});  // answered: no resync flag any more
  // Silence: the last reply came at 250 ms; lost at 250 + 1000 ms, once.
  clock_.advance_ms(749);
  EXPECT_TRUE(link.poll(0).empty());
  EXPECT_TRUE(link.link_up());
  clock_.advance_ms(1);
  const auto lost = link.poll(seconds_to_ns(42.0));
  ASSERT_EQ(kinds(lost), std::vector<SystemEventKind>{SystemEventKind::kLinkLost});
  EXPECT_EQ(lost[0].t, seconds_to_ns(42.0));
  EXPECT_EQ(lost[0].value, pty_.path());
  for (int i = 0; i < 10; ++i) {
    clock_.advance_ms(250);
    EXPECT_TRUE(link.poll(0).empty());
  }
  pty_.frames(20);
  pty_.heartbeat_reply(1);
  EXPECT_EQ(kinds(link.poll(0, 200)), std::vector<SystemEventKind>{SystemEventKind::kLinkRestored});
  const LinkReport r = link.report();
  EXPECT_EQ(r.link_lost_events, 1u);
  EXPECT_EQ(r.link_restored_events, 1u);
  EXPECT_TRUE(r.link_up);
  EXPECT_EQ(r.heartbeat_replies, 2u);
}

TEST_F(DeviceLinkTest, ReopensThePortWhenItComesBack) {
  ScratchDir dir("device_link_reopen");
  const std::string link_path = (dir / "controller").string();
  std::filesystem::create_symlink(pty_.path(), link_path);
  DeviceLink link(link_path, DeviceKind::kBelt, config(), clock_.fn());
  pty_.frames();
  pty_.close();  // unplugged
  link.poll(0);
  EXPECT_FALSE(link.port_open());
  link.send(testing::belt_pattern(0, 500, 1000));
  EXPECT_EQ(link.report().dropped_offline, 1u);
  PtyController replugged;
  std::filesystem::remove(link_path);
  std::filesystem::create_symlink(replugged.path(), link_path);
  clock_.advance_ms(499);
  link.poll(0);
  EXPECT_FALSE(link.port_open());  // waits reconnect_s between tries
  clock_.advance_ms(1);
  link.poll(0);
  ASSERT_TRUE(link.port_open());
  const auto frames = replugged.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].payload, Bytes{protocol::kHeartbeatResync});
  replugged.heartbeat_reply(frames[0].seq);
  EXPECT_TRUE(link.poll(0, 200).empty());  // never declared lost: 1 s has not passed
  const LinkReport r = link.report();
  EXPECT_EQ(r.disconnects, 1u);
  EXPECT_EQ(r.reconnects, 1u);
  const nlohmann::ordered_json j = r.to_json();
  EXPECT_EQ(j["reconnects"], 1);
  EXPECT_EQ(j["device"], "belt");
  EXPECT_EQ(j["port"], link_path);
  EXPECT_TRUE(j["latency_ms"].contains("p99"));
  EXPECT_TRUE(j["decoder"].contains("crc_errors"));
}

TEST_F(DeviceLinkTest, CloseSwitchesTheDeviceOff) {
  {
    DeviceLink link(pty_.path(), DeviceKind::kBelt, config(), clock_.fn());
    pty_.frames();
    link.close();
    EXPECT_FALSE(link.port_open());
    link.send(testing::belt_pattern(0, 500, 1000));  // after close: nothing
  }
  const auto frames = pty_.frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, static_cast<std::uint8_t>(FrameType::kAllOff));
}

// ---- the C firmware on the other end ----

/// Polls until `done` or a generous real-time limit (the firmware thread runs on wall time).
template <class F>
bool poll_until(DeviceLink& link, std::vector<SystemEvent>& events, F done) {
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!done()) {
    if (std::chrono::steady_clock::now() > limit) return false;
    for (SystemEvent& e : link.poll(0, 5)) events.push_back(std::move(e));
  }
  return true;
}

TEST(DeviceLinkFirmware, PatternsArriveAreAckedAndSurviveNoise) {
  ScratchDir dir("device_link_firmware");
  firmware_sim::SimulatedController sim(NAVAID_LINK_DEVICE_BELT, 5, (dir / "belt").string());
  FakeClock clock;
  DeviceLink link(sim.host_path(), DeviceKind::kBelt, LinkConfig{}, clock.fn());
  std::vector<SystemEvent> events;
  // Patterns from the real scheduler and belt adapter, through the sink.
  BeltAdapter belt;
  CueScheduler scheduler(CuePolicyConfig{}, belt, nullptr);
  Cue veer;
  veer.kind = CueKind::kVeer;
  veer.priority = default_priority(CueKind::kVeer);
  veer.ttl_s = 3.0;
  veer.direction_rad = 0.35;
  for (const CueEvent& e : scheduler.push(veer)) link.on_event(e);
  ASSERT_TRUE(poll_until(link, events, [&] { return link.report().acked == 1; }));
  auto s = sim.snapshot();
  EXPECT_EQ(s.device.patterns_applied, 1u);
  EXPECT_EQ(s.outputs[BeltAdapter::kFrontLeft], belt.pattern(veer)->commands.at(0).level);

  // Noise both ways between patterns: the next patterns still get through.
  sim.inject_to_host({0xA5, 0x5A, 0x03, 0x81, 0x00, 0xA5, 0x13, 0x37, 0xFF});
  sim.inject_to_device({0xA5, 0x5A, 0x0B, 0x01, 0x00, 0x00, 0x42});
  for (std::uint8_t i = 0; i < 5; ++i) {
    link.send(testing::belt_pattern(i, static_cast<std::int16_t>(100 + i), 1100));
    ASSERT_TRUE(poll_until(link, events, [&] { return !link.awaiting_ack(); })) << i;
  }
  const LinkReport r = link.report();
  EXPECT_EQ(r.acked, 6u);
  EXPECT_EQ(r.naks, 0u);
  EXPECT_GT(r.decoder.dropped_bytes, 0u);
  s = sim.snapshot();
  EXPECT_EQ(s.outputs[4], 104);
  EXPECT_EQ(s.device.patterns_applied, 6u);
  EXPECT_TRUE(events.empty());
}

TEST(DeviceLinkFirmware, StoppingTheControllerLosesTheLinkAndRestartingRestoresIt) {
  ScratchDir dir("device_link_restart");
  firmware_sim::SimulatedController sim(NAVAID_LINK_DEVICE_HAND, 6, (dir / "hand").string());
  FakeClock clock;
  DeviceLink link(sim.host_path(), DeviceKind::kHand, LinkConfig{}, clock.fn());
  std::vector<SystemEvent> events;
  ASSERT_TRUE(poll_until(link, events, [&] { return link.report().heartbeat_replies == 1; }));
  sim.stop();
  ASSERT_TRUE(poll_until(link, events, [&] { return !link.port_open(); }));
  clock.advance_ms(999);
  link.poll(0);
  EXPECT_TRUE(events.empty());
  EXPECT_TRUE(link.link_up());
  clock.advance_ms(1);
  for (SystemEvent& e : link.poll(0)) events.push_back(e);
  ASSERT_EQ(kinds(events), std::vector<SystemEventKind>{SystemEventKind::kLinkLost});
  sim.start();  // a new pty behind the same symlink
  clock.advance_ms(500);
  ASSERT_TRUE(poll_until(link, events, [&] { return events.size() == 2; }));
  EXPECT_EQ(kinds(events), (std::vector<SystemEventKind>{SystemEventKind::kLinkLost, SystemEventKind::kLinkRestored}));
  EXPECT_EQ(link.report().reconnects, 1u);
  // The restarted controller accepts our numbering (resync heartbeat) and applies a pattern.
  ActuatorPattern p = testing::belt_pattern(5, 900, 1100);
  p.device = DeviceKind::kHand;
  link.send(p);
  ASSERT_TRUE(poll_until(link, events, [&] { return !link.awaiting_ack(); }));
  EXPECT_EQ(link.report().naks, 0u);
  EXPECT_EQ(sim.snapshot().outputs[5], 900);
}

TEST(DeviceLinkFirmware, AMutedControllerLosesTheLinkWithoutLosingThePort) {
  firmware_sim::SimulatedController sim(NAVAID_LINK_DEVICE_RUMBLE, 2);
  FakeClock clock;
  DeviceLink link(sim.host_path(), DeviceKind::kRumble, LinkConfig{}, clock.fn());
  std::vector<SystemEvent> events;
  ASSERT_TRUE(poll_until(link, events, [&] { return link.report().heartbeat_replies == 1; }));
  sim.set_mute(true);
  for (int i = 0; i < 4; ++i) {
    clock.advance_ms(250);
    for (SystemEvent& e : link.poll(0, 20)) events.push_back(e);
  }
  EXPECT_EQ(kinds(events), std::vector<SystemEventKind>{SystemEventKind::kLinkLost});
  EXPECT_TRUE(link.port_open());
  sim.set_mute(false);
  clock.advance_ms(250);  // the next heartbeat
  ASSERT_TRUE(poll_until(link, events, [&] { return events.size() == 2; }));
  EXPECT_EQ(events[1].kind, SystemEventKind::kLinkRestored);
}

/// A socat virtual null-modem cable: two ptys whose symlinks a() and b() are joined; killed when
/// it goes out of scope.
class SocatPair {
 public:
  explicit SocatPair(const std::filesystem::path& dir)
      : a_((dir / "a").string()), b_((dir / "b").string()), log_((dir / "socat.log").string()) {
    const std::string pid_file = (dir / "socat.pid").string();
    const std::string cmd = "socat -d -d pty,raw,echo=0,link=" + a_ + " pty,raw,echo=0,link=" + b_ + " 2>" + log_ +
                            " & echo $! > " + pid_file;
    if (std::system(cmd.c_str()) != 0) return;
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (!ready() && std::chrono::steady_clock::now() < limit) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const std::string pid = navaid::testing::read_text(pid_file);
    pid_ = pid.substr(0, pid.find('\n'));
  }
  ~SocatPair() {
    if (!pid_.empty()) std::system(("kill " + pid_ + " 2>/dev/null").c_str());
  }
  SocatPair(const SocatPair&) = delete;
  SocatPair& operator=(const SocatPair&) = delete;
  bool ready() const { return std::filesystem::exists(a_) && std::filesystem::exists(b_); }
  const std::string& a() const { return a_; }
  const std::string& b() const { return b_; }
  std::string log() const { return std::filesystem::exists(log_) ? navaid::testing::read_text(log_) : std::string(); }

 private:
  std::string a_, b_, log_, pid_;
};

TEST(DeviceLinkFirmware, OverASocatNullModemCable) {
  if (std::system("command -v socat >/dev/null 2>&1") != 0) GTEST_SKIP() << "socat is not installed";
  ScratchDir dir("device_link_socat");
  const SocatPair socat(dir.path());
  ASSERT_TRUE(socat.ready()) << socat.log();
  const std::string a = socat.a(), b = socat.b();
  auto sim = firmware_sim::SimulatedController::attach(NAVAID_LINK_DEVICE_WHEEL, 1, b);
  FakeClock clock;
  DeviceLink link(a, DeviceKind::kWheel, LinkConfig{}, clock.fn());
  std::vector<SystemEvent> events;
  ActuatorPattern left = testing::belt_pattern(0, -250, 1100);
  left.device = DeviceKind::kWheel;
  link.send(left);
  ASSERT_TRUE(poll_until(link, events, [&] { return link.report().acked == 1; }));
  ASSERT_TRUE(poll_until(link, events, [&] { return link.report().heartbeat_replies >= 1; }));
  EXPECT_EQ(sim.snapshot().outputs[0], -250);
  EXPECT_EQ(link.report().naks, 0u);
  EXPECT_TRUE(events.empty());
}

/// A noisy serial line: copies bytes both ways between two tty fds, flipping one random bit of a
/// byte with probability `flip` and dropping a byte with probability `drop` (fixed seeds).
class NoisyLine {
 public:
  NoisyLine(int a, int b, double flip, double drop) : a_(a), b_(b), flip_(flip), drop_(drop) {
    thread_ = std::thread([this] { run(); });
  }
  ~NoisyLine() {
    stop_ = true;
    thread_.join();
  }
  std::uint64_t flipped() const { return flipped_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  void run() {
    std::mt19937 rng_ab(11), rng_ba(12);
    std::uint8_t buf[512];
    while (!stop_) {
      pollfd p[2] = {{a_, POLLIN, 0}, {b_, POLLIN, 0}};
      if (::poll(p, 2, 5) <= 0) continue;
      for (int side = 0; side < 2; ++side) {
        if ((p[side].revents & POLLIN) == 0) continue;
        const ssize_t n = ::read(side == 0 ? a_ : b_, buf, sizeof buf);
        if (n <= 0) continue;
        std::mt19937& rng = side == 0 ? rng_ab : rng_ba;
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::vector<std::uint8_t> out;
        for (ssize_t i = 0; i < n; ++i) {
          if (u(rng) < drop_) {
            ++dropped_;
            continue;
          }
          std::uint8_t byte = buf[i];
          if (u(rng) < flip_) {
            byte ^= static_cast<std::uint8_t>(1u << (rng() % 8));
            ++flipped_;
          }
          out.push_back(byte);
        }
        if (!out.empty() && ::write(side == 0 ? b_ : a_, out.data(), out.size()) < 0) continue;
      }
    }
  }
  int a_, b_;
  double flip_, drop_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> flipped_{0}, dropped_{0};
  std::thread thread_;
};

// The host and the firmware over a socat line with bit errors and drops between them: host <->
// socat pty pair <-> noisy line <-> the simulated controller's pty. Every corrupted frame is
// caught by the CRC and retransmitted; none is applied wrongly.
TEST(DeviceLinkFirmware, OverASocatLineWithBitErrorsAndDrops) {
  if (std::system("command -v socat >/dev/null 2>&1") != 0) GTEST_SKIP() << "socat is not installed";
  ScratchDir dir("device_link_noisy");
  const SocatPair socat(dir.path());
  ASSERT_TRUE(socat.ready()) << socat.log();
  const std::string a = socat.a(), b = socat.b();
  firmware_sim::SimulatedController sim(NAVAID_LINK_DEVICE_BELT, 5);
  const int line_end = ::open(b.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  const int sim_end = ::open(sim.slave_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  ASSERT_GE(line_end, 0);
  ASSERT_GE(sim_end, 0);
  for (const int fd : {line_end, sim_end}) {
    termios t{};
    ASSERT_EQ(::tcgetattr(fd, &t), 0);
    ::cfmakeraw(&t);
    ASSERT_EQ(::tcsetattr(fd, TCSANOW, &t), 0);
  }
  constexpr int kPatterns = 100;
  std::uint64_t flipped = 0, dropped = 0;
  LinkReport r;
  firmware_sim::ControllerSnapshot s;
  std::int16_t last_acked_level = -1;
  {
    NoisyLine line(line_end, sim_end, 0.003, 0.003);
    DeviceLink link(a, DeviceKind::kBelt, LinkConfig{});
    std::vector<SystemEvent> events;
    for (int i = 0; i < kPatterns; ++i) {
      const auto level = static_cast<std::int16_t>(10 * (i + 1));
      const std::uint64_t acked_before = link.report().acked;
      link.send(testing::belt_pattern(static_cast<std::uint8_t>(i % 5), level, 1100));
      ASSERT_TRUE(poll_until(link, events, [&] { return !link.awaiting_ack(); })) << i;
      if (link.report().acked > acked_before) last_acked_level = level;
    }
    r = link.report();
    s = sim.snapshot();  // before close() switches everything off
    link.close();
    flipped = line.flipped();
    dropped = line.dropped();
  }
  ::close(line_end);
  ::close(sim_end);
  std::cout << "noisy line: " << flipped << " bits flipped, " << dropped << " bytes dropped; " << r.acked
            << " acked, " << r.retransmits << " retransmits, " << r.failed << " given up\n";
  EXPECT_GT(flipped + dropped, 10u) << "the line must really be noisy";
  EXPECT_EQ(r.acked + r.failed + r.naks, static_cast<std::uint64_t>(kPatterns));
  EXPECT_LE(r.failed, 4u);
  EXPECT_EQ(r.naks, 0u) << "a corrupted frame must never pass the CRC and be refused";
  EXPECT_GT(r.retransmits, 0u);
  EXPECT_GT(s.decoder.crc_errors + r.decoder.crc_errors + s.decoder.truncated + r.decoder.truncated, 0u);
  // What the controller applied last is a pattern the host sent (never a corrupted level).
  ASSERT_GT(last_acked_level, 0);
  bool seen = false;
  for (std::int16_t o : s.outputs) {
    EXPECT_TRUE(o == 0 || (o > 0 && o <= 10 * kPatterns && o % 10 == 0)) << o;
    seen = seen || o == last_acked_level;
  }
  EXPECT_TRUE(seen) << "the last acknowledged pattern is in force";
}

}  // namespace
}  // namespace navaid::interaction

namespace navaid::interaction {
namespace {

TEST(DeviceSimCommand, HostLinkTalksToTheCommandLineController) {
  ScratchDir dir("device_sim_cli");
  const std::string link_path = (dir / "belt").string();
  const std::string log = (dir / "sim.log").string();
  const std::string pid_file = (dir / "sim.pid").string();
  const std::string cmd = std::string(NAVAID_CLI_PATH) + " device-sim --device belt --link " + link_path +
                          " --duration 30 --status-s 0 >" + log + " 2>&1 & echo $! >" + pid_file;
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const std::string pid_text = navaid::testing::read_text(pid_file);
  const std::string pid = pid_text.substr(0, pid_text.find('\n'));
  struct Stop {
    std::string pid;
    ~Stop() {
      if (!pid.empty()) std::system(("kill " + pid + " 2>/dev/null").c_str());
    }
  } stop{pid};
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!std::filesystem::exists(link_path) && std::chrono::steady_clock::now() < limit) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(std::filesystem::exists(link_path)) << navaid::testing::read_text(log);
  FakeClock clock;
  DeviceLink link(link_path, DeviceKind::kBelt, Config(), clock.fn());
  link.send(testing::belt_pattern(2, 640, 1100));
  std::vector<SystemEvent> events;
  ASSERT_TRUE(poll_until(link, events, [&] { return link.report().acked == 1; }));
  EXPECT_EQ(link.report().naks, 0u);
  link.close();
  ASSERT_EQ(std::system(("kill " + pid).c_str()), 0);
  stop.pid.clear();
  std::string out;
  while (out.find("final:") == std::string::npos && std::chrono::steady_clock::now() < limit) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    out = navaid::testing::read_text(log);
  }
  EXPECT_NE(out.find("belt controller (5 actuators)"), std::string::npos) << out;
  EXPECT_NE(out.find("patterns 1"), std::string::npos) << out;
  EXPECT_NE(out.find("all_off 1"), std::string::npos) << out;  // close() switched it off
}

TEST(DeviceSimCommand, UsageErrors) {
  auto run = navaid::testing::navaid_cli("device-sim --device car --link /tmp/x");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("--device must be belt, hand, rumble or wheel"), std::string::npos) << run.output;
  run = navaid::testing::navaid_cli("device-sim --device belt");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("exactly one of --link"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace navaid::interaction
