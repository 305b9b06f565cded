// The controller's C state machine (interaction/firmware/navaid_link.c), driven with frames from
// the host encoder and answered through the host decoder: patterns applied and pulsed, holds
// expiring, the link timeout switching everything off, ALL_OFF, every NAK reason, heartbeat
// replies, retransmissions and the millisecond counter wrapping.
#include <gtest/gtest.h>

#include "device_link_testing.hpp"

namespace navaid::interaction {
namespace {

using testing::Bytes;

class Firmware {
 public:
  explicit Firmware(std::uint8_t kind = NAVAID_LINK_DEVICE_BELT, std::uint8_t actuators = 5,
                    std::uint32_t now_ms = 0) {
    navaid_link_device_init(&dev, kind, actuators, 0, now_ms);
  }
  void rx(const Bytes& b, std::uint32_t now_ms) { navaid_link_device_rx(&dev, b.data(), b.size(), now_ms); }
  void tick(std::uint32_t now_ms) { navaid_link_device_tick(&dev, now_ms); }
  int out(std::uint8_t i) const { return navaid_link_device_output(&dev, i); }
  /// The replies queued so far, decoded on the host.
  std::vector<DecodedFrame> replies() {
    std::uint8_t buf[NAVAID_LINK_TX_BUFFER];
    const std::size_t n = navaid_link_device_tx(&dev, buf, sizeof buf);
    host.frames.clear();
    host.feed(buf, n);
    std::vector<DecodedFrame> out;
    for (const auto& f : host.frames) {
      out.push_back({f.type, f.seq, SequenceStatus::kNew, true, f.payload.data(), f.payload.size()});
    }
    return out;
  }
  std::optional<Ack> single_ack() {
    const auto r = replies();
    if (r.size() != 1) return std::nullopt;
    return parse_ack(r[0]);
  }
  std::optional<Nak> single_nak() {
    const auto r = replies();
    if (r.size() != 1) return std::nullopt;
    return parse_nak(r[0]);
  }

  navaid_link_device dev;
  testing::HostCollector host{FrameDirection::kDeviceToHost};
};

TEST(DeviceFirmware, PatternIsAppliedAndAcked) {
  Firmware fw;
  ActuatorPattern p = testing::belt_pattern(2, 600, 1100);
  p.commands.push_back({4, 1000, 0, 0, 1100});
  fw.rx(testing::host_pattern(p, 41), 10);
  EXPECT_EQ(fw.out(0), 0);
  EXPECT_EQ(fw.out(2), 600);
  EXPECT_EQ(fw.out(4), 1000);
  EXPECT_EQ(navaid_link_device_active_mask(&fw.dev), 0x14);
  const auto ack = fw.single_ack();
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->seq, 41);
  EXPECT_EQ(ack->status, AckStatus::kApplied);
  EXPECT_EQ(fw.dev.counters.patterns_applied, 1u);
  // A new pattern replaces the old one entirely: actuators not listed go off.
  fw.rx(testing::host_pattern(testing::belt_pattern(0, 300, 1100), 42), 20);
  EXPECT_EQ(fw.out(0), 300);
  EXPECT_EQ(fw.out(2), 0);
  EXPECT_EQ(fw.out(4), 0);
  // An empty pattern is "all off".
  fw.rx(testing::host_pattern(ActuatorPattern{}, 43), 30);
  EXPECT_EQ(fw.out(0), 0);
  EXPECT_EQ(navaid_link_device_active_mask(&fw.dev), 0);
}

TEST(DeviceFirmware, PulsesAndHoldsExpire) {
  Firmware fw;
  fw.rx(testing::host_pattern(testing::belt_pattern(1, 700, 1000, 200, 100), 1), 0);
  fw.tick(199);
  EXPECT_EQ(fw.out(1), 700);
  fw.tick(250);
  EXPECT_EQ(fw.out(1), 0);  // off phase, still held
  EXPECT_EQ(navaid_link_device_active_mask(&fw.dev), 0x02);
  fw.tick(300);
  EXPECT_EQ(fw.out(1), 700);  // next period
  fw.rx(testing::host_heartbeat(2), 500);  // keep the link alive; does not touch the pattern
  fw.tick(999);
  EXPECT_EQ(fw.out(1), 700);
  fw.tick(1000);
  EXPECT_EQ(fw.out(1), 0);
  EXPECT_EQ(navaid_link_device_active_mask(&fw.dev), 0);
  EXPECT_EQ(fw.dev.counters.hold_expiries, 1u);
  EXPECT_EQ(fw.dev.counters.link_timeouts, 0u);
}

TEST(DeviceFirmware, LinkTimeoutSwitchesAllOffAndForgetsTheSequence) {
  Firmware fw;
  fw.rx(testing::host_pattern(testing::belt_pattern(3, 900, 60000), 500), 0);
  fw.replies();
  fw.rx(testing::host_heartbeat(501), 900);  // any valid frame keeps it alive
  fw.rx({0x00, 0x11, 0x22}, 1500);               // garbage is not a sign of life
  fw.tick(1899);
  EXPECT_EQ(fw.out(3), 900);
  EXPECT_EQ(fw.dev.counters.link_timeouts, 0u);
  fw.tick(1900);
  EXPECT_EQ(fw.out(3), 0);
  EXPECT_EQ(fw.dev.counters.link_timeouts, 1u);
  EXPECT_EQ(fw.dev.link_alive, 0);
  fw.tick(5000);
  EXPECT_EQ(fw.dev.counters.link_timeouts, 1u);  // once per loss
  // A restarted host numbers from 0 again: accepted as new after the timeout.
  fw.replies();
  fw.rx(testing::host_pattern(testing::belt_pattern(3, 100, 1000), 0), 5000);
  const auto ack = fw.single_ack();
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kApplied);
  EXPECT_EQ(fw.out(3), 100);
}

TEST(DeviceFirmware, AllOff) {
  Firmware fw;
  fw.rx(testing::host_pattern(testing::belt_pattern(0, 500, 5000), 1), 0);
  fw.replies();
  fw.rx(testing::host_all_off(2), 10);
  EXPECT_EQ(fw.out(0), 0);
  const auto ack = fw.single_ack();
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->seq, 2);
  EXPECT_EQ(fw.dev.counters.all_off_commands, 1u);
}

TEST(DeviceFirmware, NakReasons) {
  Firmware fw;
  ActuatorPattern hand = testing::belt_pattern(0, 500, 1000);
  hand.device = DeviceKind::kHand;
  struct Case {
    Bytes frame;
    NakReason reason;
    std::uint8_t detail;
  };
  ActuatorPattern repeated = testing::belt_pattern(1, 500, 1000);
  repeated.commands.push_back({1, 400, 0, 0, 1000});
  std::vector<Case> cases = {
      {testing::host_pattern(hand, 1), NakReason::kWrongDevice, 2},
      {testing::host_pattern(testing::belt_pattern(5, 500, 1000), 2), NakReason::kBadActuator, 5},
      {testing::host_pattern(repeated, 3), NakReason::kBadActuator, 1},
      {testing::host_pattern(testing::belt_pattern(4, 1001, 1000), 4), NakReason::kBadLevel, 4},
      {testing::host_pattern(testing::belt_pattern(2, -1, 1000), 5), NakReason::kBadLevel, 2},
      {testing::raw_frame(0x7E, 6, {1, 2}), NakReason::kUnknownType, 0x7E},
      {testing::raw_frame(0x01, 7, {1, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0}), NakReason::kBadLength, 11},
  };
  std::uint16_t seq = 1;
  for (const Case& c : cases) {
    fw.rx(c.frame, seq * 10u);
    const auto nak = fw.single_nak();
    ASSERT_TRUE(nak) << "case " << seq;
    EXPECT_EQ(nak->seq, seq);
    EXPECT_EQ(nak->reason, static_cast<std::uint8_t>(c.reason)) << "case " << seq;
    EXPECT_EQ(nak->detail, c.detail) << "case " << seq;
    ++seq;
  }
  EXPECT_EQ(fw.dev.counters.naks_sent, cases.size());
  EXPECT_EQ(fw.dev.counters.patterns_applied, 0u);
  for (std::uint8_t i = 0; i < 5; ++i) EXPECT_EQ(fw.out(i), 0);
  // The wheel takes signed angles.
  Firmware wheel(NAVAID_LINK_DEVICE_WHEEL, 1);
  ActuatorPattern left = testing::belt_pattern(0, -300, 1000);
  left.device = DeviceKind::kWheel;
  wheel.rx(testing::host_pattern(left, 1), 0);
  EXPECT_EQ(wheel.out(0), -300);
  EXPECT_TRUE(wheel.single_ack());
}

TEST(DeviceFirmware, RetransmissionsAreAckedNotReapplied) {
  Firmware fw;
  const Bytes p = testing::host_pattern(testing::belt_pattern(0, 500, 1000), 20);
  fw.rx(p, 0);
  fw.replies();
  fw.rx(p, 100);  // the host did not see the ACK and sent the same frame again
  auto ack = fw.single_ack();
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kDuplicate);
  fw.rx(testing::host_all_off(19), 200);  // an older frame arriving late
  ack = fw.single_ack();
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kStale);
  EXPECT_EQ(fw.dev.counters.all_off_commands, 0u);
  fw.tick(999);
  EXPECT_EQ(fw.out(0), 500);  // the hold still counts from the first receipt
  fw.tick(1000);
  EXPECT_EQ(fw.out(0), 0);
  EXPECT_EQ(fw.dev.counters.patterns_applied, 1u);
}

TEST(DeviceFirmware, HeartbeatReply) {
  Firmware fw(NAVAID_LINK_DEVICE_HAND, 6);
  ActuatorPattern p = testing::belt_pattern(5, 500, 3000);
  p.device = DeviceKind::kHand;
  fw.rx(testing::host_pattern(p, 7), 0);
  fw.rx({0xA5, 0x5A, 0x00, 0x02, 0x08, 0x00, 0xDE, 0xAD}, 1);  // ALL_OFF with a bad CRC
  fw.replies();
  fw.rx(testing::host_heartbeat(8), 2);
  const auto r = fw.replies();
  ASSERT_EQ(r.size(), 1u);
  const auto reply = parse_heartbeat_reply(r[0]);
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->seq, 8);
  EXPECT_EQ(reply->device, DeviceKind::kHand);
  EXPECT_EQ(reply->active_mask, 0x20);
  EXPECT_EQ(reply->frames_ok, 2);  // the pattern and the heartbeat itself
  EXPECT_EQ(reply->crc_errors, 1);
}

TEST(DeviceFirmware, MillisecondCounterWrapsAround) {
  const std::uint32_t t0 = 0xFFFFFF00u;
  Firmware fw(NAVAID_LINK_DEVICE_BELT, 5, t0 - 100);
  fw.rx(testing::host_pattern(testing::belt_pattern(0, 800, 1000, 100, 100), 1), t0);
  fw.tick(t0 + 150);  // 0xFFFFFF96, before the wrap: off phase
  EXPECT_EQ(fw.out(0), 0);
  fw.tick(0x00000010u);  // 272 ms after t0, across the wrap: on phase
  EXPECT_EQ(fw.out(0), 800);
  fw.rx(testing::host_heartbeat(2), 0x00000200u);  // 768 ms
  fw.tick(t0 + 999);
  EXPECT_EQ(navaid_link_device_active_mask(&fw.dev), 1);
  fw.tick(t0 + 1000);  // = 0x000002E8
  EXPECT_EQ(navaid_link_device_active_mask(&fw.dev), 0);
  EXPECT_EQ(fw.dev.counters.hold_expiries, 1u);
  // The link timeout counts across the wrap as well: 1000 ms after the heartbeat.
  fw.tick(0x00000200u + 999);
  EXPECT_EQ(fw.dev.counters.link_timeouts, 0u);
  fw.tick(0x00000200u + 1000);
  EXPECT_EQ(fw.dev.counters.link_timeouts, 1u);
}

TEST(DeviceFirmware, InterbyteTimeoutAbandonsAPartialFrame) {
  Firmware fw;
  const Bytes p = testing::host_pattern(testing::belt_pattern(0, 500, 1000), 1);
  fw.rx(Bytes(p.begin(), p.begin() + 7), 0);
  fw.tick(50);
  EXPECT_EQ(fw.dev.dec.counters.truncated, 0u);
  fw.tick(51);
  EXPECT_EQ(fw.dev.dec.counters.truncated, 1u);
  // The rest of the old frame arrives late and is dropped; the next whole frame works.
  fw.rx(Bytes(p.begin() + 7, p.end()), 60);
  fw.rx(testing::host_pattern(testing::belt_pattern(1, 500, 1000), 2), 61);
  EXPECT_EQ(fw.out(1), 500);
  EXPECT_EQ(fw.dev.counters.patterns_applied, 1u);
}

TEST(DeviceFirmware, FullTransmitBufferDropsWholeReplies) {
  Firmware fw;
  for (std::uint16_t s = 0; s < 20; ++s) fw.rx(testing::host_heartbeat(s), s);
  EXPECT_GT(fw.dev.counters.tx_overflows, 0u);
  const auto r = fw.replies();
  // Only whole frames were queued: the 8 that fit in 128 bytes (16 bytes each) all decode.
  EXPECT_EQ(r.size(), NAVAID_LINK_TX_BUFFER / 16);
  EXPECT_EQ(fw.host.decoder().counters().crc_errors, 0u);
  EXPECT_EQ(fw.dev.counters.tx_overflows, 20u - r.size());
  // ACKs that did not fit are not counted as sent (11 bytes each: 11 fit in 128).
  Firmware acks;
  for (std::uint16_t s = 0; s < 20; ++s) acks.rx(testing::host_all_off(s), s);
  EXPECT_EQ(acks.dev.counters.acks_sent, NAVAID_LINK_TX_BUFFER / 11);
  EXPECT_EQ(acks.dev.counters.acks_sent + acks.dev.counters.tx_overflows, 20u);
  EXPECT_EQ(acks.replies().size(), NAVAID_LINK_TX_BUFFER / 11);
}

TEST(DeviceFirmware, ItsOwnRepliesEchoedBackAreIgnoredNotNaked) {
  // A host tty left with echo on sends every reply straight back; NAKing those would loop.
  Firmware fw;
  fw.rx(testing::host_heartbeat(1), 0);
  std::uint8_t buf[NAVAID_LINK_TX_BUFFER];
  const std::size_t n = navaid_link_device_tx(&fw.dev, buf, sizeof buf);
  ASSERT_GT(n, 0u);
  fw.rx(Bytes(buf, buf + n), 1);
  EXPECT_TRUE(fw.replies().empty());
  EXPECT_EQ(fw.dev.counters.naks_sent, 0u);
  EXPECT_EQ(fw.dev.dec.counters.unknown_type, 1u);
  // An unknown host type is still refused.
  fw.rx(testing::raw_frame(0x10, 2, {}), 2);
  const auto nak = fw.single_nak();
  ASSERT_TRUE(nak);
  EXPECT_EQ(nak->reason, static_cast<std::uint8_t>(NakReason::kUnknownType));
}

}  // namespace
}  // namespace navaid::interaction
