// The device link's framing, host (C++) against controller (C): CRC known answer, byte-identical
// encoders, round trips of every type, corrupt input of every kind, sequence rules and a fixed-seed
// fuzz in which both decoders must deliver the same frames with the same counters.
#include "navaid/interaction/device_protocol.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <stdexcept>

#include "device_link_testing.hpp"

namespace navaid::interaction {
namespace {

using testing::Bytes;
using testing::FirmwareCollector;
using testing::HostCollector;

const std::uint8_t kCheck[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

TEST(DeviceProtocol, CrcKnownAnswerOnBothSides) {
  EXPECT_EQ(crc16_ccitt_false(kCheck, sizeof kCheck), 0x29B1);
  EXPECT_EQ(navaid_link_crc16(kCheck, sizeof kCheck), 0x29B1);
  // Incremental update equals the one-shot CRC.
  EXPECT_EQ(crc16_ccitt_false(kCheck + 4, 5, crc16_ccitt_false(kCheck, 4)), 0x29B1);
  EXPECT_EQ(crc16_ccitt_false(nullptr, 0), 0xFFFF);
}

TEST(DeviceProtocol, HostAndFirmwareEncodersAreByteIdentical) {
  std::mt19937 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const auto len = static_cast<std::uint8_t>(rng() % (protocol::kMaxPayload + 1));
    Bytes payload(len);
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    const auto type = static_cast<std::uint8_t>(rng());
    const auto seq = static_cast<std::uint16_t>(rng());
    FrameBuffer host{};
    FrameBuffer fw{};
    const std::size_t n = encode_frame(type, seq, payload.data(), len, host.data());
    ASSERT_EQ(navaid_link_encode(type, seq, payload.data(), len, fw.data(), fw.size()), n);
    ASSERT_EQ(0, std::memcmp(host.data(), fw.data(), n)) << "frame " << i;
  }
  // Too long: the host throws, the firmware returns 0.
  std::uint8_t big[protocol::kMaxPayload + 1] = {};
  FrameBuffer out{};
  EXPECT_THROW(encode_frame(1, 0, big, sizeof big, out.data()), std::invalid_argument);
  EXPECT_EQ(navaid_link_encode(1, 0, big, sizeof big, out.data(), out.size()), 0u);
  ActuatorPattern nine;
  nine.commands.resize(9);
  EXPECT_THROW(encode_pattern(nine, 0, out.data()), std::invalid_argument);
}

TEST(DeviceProtocol, PatternRoundTripThroughBothDecoders) {
  ActuatorPattern p;
  p.device = DeviceKind::kWheel;
  p.commands = {{0, -1234, 0, 0, 1100}};
  ActuatorPattern hand;
  hand.device = DeviceKind::kHand;
  for (std::uint8_t i = 0; i < 8; ++i) {
    hand.commands.push_back({i, static_cast<std::int16_t>(100 * i), static_cast<std::uint16_t>(10 + i),
                             static_cast<std::uint16_t>(20 + i), static_cast<std::uint16_t>(65535 - i)});
  }
  for (const ActuatorPattern& in : {p, hand, ActuatorPattern{}}) {
    const Bytes frame = testing::host_pattern(in, 0xBEEF);
    HostCollector host(FrameDirection::kHostToDevice);
    FirmwareCollector fw;
    host.feed(frame);
    fw.feed(frame);
    ASSERT_EQ(host.frames.size(), 1u);
    ASSERT_EQ(fw.frames.size(), 1u);
    EXPECT_EQ(host.frames[0], fw.frames[0]);
    DecodedFrame f{host.frames[0].type, host.frames[0].seq, SequenceStatus::kNew, true,
                   host.frames[0].payload.data(), host.frames[0].payload.size()};
    const std::optional<ActuatorPattern> out = parse_pattern(f);
    ASSERT_TRUE(out);
    EXPECT_EQ(out->device, in.device);
    ASSERT_EQ(out->commands.size(), in.commands.size());
    for (std::size_t k = 0; k < in.commands.size(); ++k) {
      EXPECT_EQ(out->commands[k].actuator, in.commands[k].actuator);
      EXPECT_EQ(out->commands[k].level, in.commands[k].level);
      EXPECT_EQ(out->commands[k].on_ms, in.commands[k].on_ms);
      EXPECT_EQ(out->commands[k].off_ms, in.commands[k].off_ms);
      EXPECT_EQ(out->commands[k].hold_ms, in.commands[k].hold_ms);
    }
    EXPECT_FALSE(parse_ack(f));
  }
}

TEST(DeviceProtocol, EveryTypeRoundTripsThroughTheHostDecoder) {
  FrameBuffer b{};
  HostCollector host(FrameDirection::kBoth);
  std::size_t n = encode_all_off(1, b.data());
  host.feed(b.data(), n);
  n = encode_heartbeat(2, true, b.data());
  host.feed(b.data(), n);
  n = encode_ack(3, Ack{0x1234, AckStatus::kStale}, b.data());
  host.feed(b.data(), n);
  n = encode_nak(4, Nak{0x4321, 5, 7}, b.data());
  host.feed(b.data(), n);
  HeartbeatReply r;
  r.seq = 99;
  r.device = DeviceKind::kRumble;
  r.active_mask = 0x03;
  r.frames_ok = 65535;
  r.crc_errors = 12;
  n = encode_heartbeat_reply(5, r, b.data());
  host.feed(b.data(), n);
  ASSERT_EQ(host.frames.size(), 5u);
  const auto frame = [&](std::size_t i) { return host.decoded(i); };
  EXPECT_EQ(host.frames[0].type, 0x02);
  EXPECT_TRUE(host.frames[0].payload.empty());
  EXPECT_EQ(host.frames[1].payload, Bytes{protocol::kHeartbeatResync});
  const auto ack = parse_ack(frame(2));
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->seq, 0x1234);
  EXPECT_EQ(ack->status, AckStatus::kStale);
  const auto nak = parse_nak(frame(3));
  ASSERT_TRUE(nak);
  EXPECT_EQ(nak->seq, 0x4321);
  EXPECT_EQ(nak->reason, 5);
  EXPECT_EQ(nak->detail, 7);
  EXPECT_EQ(to_string(static_cast<NakReason>(nak->reason)), "bad_level");
  EXPECT_EQ(to_string(static_cast<NakReason>(99)), "unknown");
  const auto reply = parse_heartbeat_reply(frame(4));
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->seq, 99);
  EXPECT_EQ(reply->device, DeviceKind::kRumble);
  EXPECT_EQ(reply->active_mask, 0x03);
  EXPECT_EQ(reply->frames_ok, 65535);
  EXPECT_EQ(reply->crc_errors, 12);
  EXPECT_FALSE(parse_nak(frame(2)));
  EXPECT_FALSE(parse_pattern(frame(2)));
  EXPECT_EQ(host.decoder().counters().frames_ok, 5u);
}

TEST(DeviceProtocol, ParsersRejectMalformedPayloads) {
  Bytes ack = {1, 0, 3};  // status 3 does not exist
  EXPECT_FALSE(parse_ack(DecodedFrame{0x81, 0, SequenceStatus::kNew, true, ack.data(), ack.size()}));
  Bytes reply = {0, 0, 9, 0, 0, 0, 0, 0};  // device kind 9
  EXPECT_FALSE(parse_heartbeat_reply(DecodedFrame{0x83, 0, SequenceStatus::kNew, true, reply.data(), reply.size()}));
  Bytes pattern = {1, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // says 2 commands, carries 1
  EXPECT_FALSE(parse_pattern(DecodedFrame{0x01, 0, SequenceStatus::kNew, false, pattern.data(), pattern.size()}));
  pattern = {0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // device kind 0
  EXPECT_FALSE(parse_pattern(DecodedFrame{0x01, 0, SequenceStatus::kNew, true, pattern.data(), pattern.size()}));
}

TEST(DeviceProtocol, FirmwareRepliesDecodeOnTheHost) {
  navaid_link_device dev;
  navaid_link_device_init(&dev, NAVAID_LINK_DEVICE_BELT, 5, 0, 0);
  const Bytes in = testing::cat({testing::host_heartbeat(10, true),
                                 testing::host_pattern(testing::belt_pattern(1, 500, 1000), 11),
                                 testing::host_pattern(testing::belt_pattern(7, 500, 1000), 12)});
  navaid_link_device_rx(&dev, in.data(), in.size(), 5);
  std::uint8_t out[256];
  const std::size_t n = navaid_link_device_tx(&dev, out, sizeof out);
  HostCollector host(FrameDirection::kDeviceToHost);
  host.feed(out, n);
  ASSERT_EQ(host.frames.size(), 3u);
  const auto frame = [&](std::size_t i) { return host.decoded(i); };
  const auto reply = parse_heartbeat_reply(frame(0));
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->seq, 10);
  EXPECT_EQ(reply->device, DeviceKind::kBelt);
  const auto ack = parse_ack(frame(1));
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->seq, 11);
  EXPECT_EQ(ack->status, AckStatus::kApplied);
  const auto nak = parse_nak(frame(2));
  ASSERT_TRUE(nak);
  EXPECT_EQ(nak->seq, 12);
  EXPECT_EQ(nak->reason, static_cast<std::uint8_t>(NakReason::kBadActuator));
  EXPECT_EQ(nak->detail, 7);
  // The controller numbers its replies 0, 1, 2 from boot.
  EXPECT_EQ(host.frames[0].seq, 0);
  EXPECT_EQ(host.frames[2].seq, 2);
  EXPECT_EQ(host.decoder().counters().crc_errors, 0u);
}

/// Feeds `bad` then a good frame to both decoders, flushes, and expects only the good frame;
/// returns the host decoder's counters.
DecoderCounters expect_only_good_frame_survives(const Bytes& bad, const std::string& what) {
  const Bytes good = testing::host_all_off(777);
  const Bytes stream = testing::cat({bad, good});
  HostCollector host(FrameDirection::kHostToDevice);
  FirmwareCollector fw;
  host.feed(stream);
  fw.feed(stream);
  host.flush();
  fw.flush();
  EXPECT_EQ(host.frames.size(), 1u) << what;
  EXPECT_EQ(fw.frames.size(), 1u) << what;
  if (host.frames.size() == 1 && fw.frames.size() == 1) {
    EXPECT_EQ(host.frames[0].seq, 777) << what;
    EXPECT_EQ(host.frames[0], fw.frames[0]) << what;
  }
  EXPECT_EQ(host.decoder().counters().dropped_bytes, bad.size()) << what;
  EXPECT_EQ(fw.counters().dropped_bytes, bad.size()) << what;
  return host.decoder().counters();
}

TEST(DeviceProtocol, EverySingleBitFlipIsRejectedAndTheNextFrameSurvives) {
  ActuatorPattern p = testing::belt_pattern(2, 800, 1100, 200, 100);
  p.commands.push_back({4, 300, 0, 0, 1100});
  const Bytes frame = testing::host_pattern(p, 0x0102);
  int rejected = 0;
  for (std::size_t byte = 0; byte < frame.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      Bytes bad = frame;
      bad[byte] = static_cast<std::uint8_t>(bad[byte] ^ (1u << bit));
      const DecoderCounters c =
          expect_only_good_frame_survives(bad, "byte " + std::to_string(byte) + " bit " + std::to_string(bit));
      // Past the sync, length and type bytes (whose flips fail earlier checks or the CRC), every
      // flip is caught by the CRC itself.
      if (byte >= 4) {
        EXPECT_GE(c.crc_errors, 1u) << "byte " << byte << " bit " << bit;
      }
      ++rejected;
    }
  }
  EXPECT_EQ(rejected, static_cast<int>(frame.size() * 8));
}

TEST(DeviceProtocol, TruncatedFramesAreAbandonedWithoutLosingTheNext) {
  const Bytes frame = testing::host_pattern(testing::belt_pattern(0, 1000, 500), 5);
  for (std::size_t cut = 1; cut < frame.size(); ++cut) {
    expect_only_good_frame_survives(Bytes(frame.begin(), frame.begin() + static_cast<long>(cut)),
                                    "cut at " + std::to_string(cut));
  }
  // A partial frame at the end of the stream is counted as truncated by flush().
  HostCollector host(FrameDirection::kHostToDevice);
  FirmwareCollector fw;
  const Bytes partial(frame.begin(), frame.begin() + 10);
  host.feed(partial);
  fw.feed(partial);
  EXPECT_TRUE(host.decoder().has_partial());
  host.flush();
  fw.flush();
  EXPECT_FALSE(host.decoder().has_partial());
  EXPECT_EQ(host.decoder().counters().truncated, 1u);
  EXPECT_EQ(fw.counters().truncated, 1u);
  EXPECT_TRUE(host.frames.empty());
}

TEST(DeviceProtocol, BadLengthsAndUnknownTypes) {
  // Length byte beyond the largest payload, rejected before any CRC.
  Bytes too_long = {protocol::kSync0, protocol::kSync1, 75, 0x01, 0, 0};
  expect_only_good_frame_survives(too_long, "length 75");
  // ALL_OFF with a payload and HEARTBEAT without one: wrong length for the type.
  expect_only_good_frame_survives(testing::raw_frame(0x02, 1, {0}), "all_off len 1");
  expect_only_good_frame_survives(testing::raw_frame(0x03, 1, {}), "heartbeat len 0");
  expect_only_good_frame_survives(testing::raw_frame(0x01, 1, {1}), "pattern len 1");
  {
    HostCollector host(FrameDirection::kHostToDevice);
    FirmwareCollector fw;
    const Bytes b = testing::raw_frame(0x03, 1, {});
    host.feed(b);
    fw.feed(b);
    EXPECT_EQ(host.decoder().counters().length_errors, 1u);
    EXPECT_EQ(fw.counters().length_errors, 1u);
  }
  // A valid CRC over an unknown type, and a PATTERN whose count disagrees with its length, are
  // delivered (the controller NAKs them) but not well formed.
  const Bytes unknown = testing::raw_frame(0x44, 9, {1, 2, 3});
  const Bytes miscount = testing::raw_frame(0x01, 10, {1, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  HostCollector host(FrameDirection::kHostToDevice);
  FirmwareCollector fw;
  host.feed(testing::cat({unknown, miscount}));
  fw.feed(testing::cat({unknown, miscount}));
  ASSERT_EQ(host.frames.size(), 2u);
  EXPECT_EQ(host.frames, fw.frames);
  EXPECT_FALSE(host.well_formed[0]);
  EXPECT_FALSE(host.well_formed[1]);
  EXPECT_EQ(host.decoder().counters().unknown_type, 1u);
  EXPECT_EQ(host.decoder().counters().length_errors, 1u);
  EXPECT_EQ(host.decoder().counters().frames_ok, 0u);
  EXPECT_EQ(fw.counters().unknown_type, 1u);
  EXPECT_EQ(fw.counters().length_errors, 1u);
  // The host decoder does not know host-to-device types.
  HostCollector device_side(FrameDirection::kDeviceToHost);
  device_side.feed(testing::host_all_off(3));
  EXPECT_EQ(device_side.decoder().counters().unknown_type, 1u);
}

TEST(DeviceProtocol, GarbageBetweenFramesIsSkipped) {
  const Bytes a = testing::host_all_off(1);
  const Bytes b = testing::host_pattern(testing::belt_pattern(3, 200, 900), 2);
  const Bytes c = testing::host_heartbeat(3);
  // Garbage holding sync bytes, a sync pair with a plausible length and a lone sync0 right before
  // a frame.
  const Bytes g1 = {0x00, 0xA5, 0xFF, 0xA5, 0x5A, 0x09, 0x01, 0x13};
  const Bytes g2 = {0x5A, 0x5A, 0xA5};
  const Bytes g3 = {0xA5, 0x5A, 0x02, 0x03, 0x00};
  const Bytes stream = testing::cat({g1, a, g2, b, g3, c});
  HostCollector host(FrameDirection::kHostToDevice);
  FirmwareCollector fw;
  host.feed(stream);
  fw.feed(stream);
  host.flush();
  fw.flush();
  ASSERT_EQ(host.frames.size(), 3u);
  EXPECT_EQ(host.frames, fw.frames);
  EXPECT_EQ(host.frames[0].seq, 1);
  EXPECT_EQ(host.frames[1].seq, 2);
  EXPECT_EQ(host.frames[2].seq, 3);
  EXPECT_EQ(host.decoder().counters().dropped_bytes, g1.size() + g2.size() + g3.size());
  EXPECT_EQ(fw.counters().dropped_bytes, g1.size() + g2.size() + g3.size());
  EXPECT_EQ(host.decoder().counters().seq_gaps, 0u);
}

TEST(DeviceProtocol, SequenceDuplicatesStaleGapsWrapAndResync) {
  const std::vector<std::uint16_t> seqs = {10, 10, 9, 11, 14, 65534, 65535, 0, 1, 1};
  Bytes stream;
  for (std::uint16_t s : seqs) stream = testing::cat({stream, testing::host_all_off(s)});
  // 14 -> 65534 is 65520 ahead, i.e. 16 behind: stale. So feed the wrap part after a resync.
  stream = testing::cat({stream, testing::host_heartbeat(65533, true), testing::host_all_off(65534),
                         testing::host_all_off(65535), testing::host_all_off(0), testing::host_all_off(1)});
  HostCollector host(FrameDirection::kHostToDevice);
  FirmwareCollector fw;
  host.feed(stream);
  fw.feed(stream);
  ASSERT_EQ(host.frames.size(), seqs.size() + 5);
  EXPECT_EQ(host.frames, fw.frames);
  const std::vector<int> expected = {0, 1, 2, 0, 0, 2, 2, 2, 2, 2, /*resync*/ 0, 0, 0, 0, 0};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(host.frames[i].seq_status, expected[i]) << "frame " << i << " seq " << host.frames[i].seq;
  }
  EXPECT_EQ(host.decoder().counters().seq_gaps, 2u);  // 11 -> 14
  EXPECT_EQ(fw.counters().seq_gaps, 2u);
  EXPECT_EQ(host.decoder().counters().replayed, 7u);
  EXPECT_EQ(fw.counters().replayed, 7u);
  // forget_sequence: the next frame is new whatever its number.
  host.decoder().forget_sequence();
  host.feed(testing::host_all_off(0));
  EXPECT_EQ(host.frames.back().seq_status, 0);
}

void expect_same_counters(const DecoderCounters& h, const navaid_link_counters& c, const std::string& what) {
  EXPECT_EQ(h.frames_ok, c.frames_ok) << what;
  EXPECT_EQ(h.crc_errors, c.crc_errors) << what;
  EXPECT_EQ(h.length_errors, c.length_errors) << what;
  EXPECT_EQ(h.unknown_type, c.unknown_type) << what;
  EXPECT_EQ(h.replayed, c.replayed) << what;
  EXPECT_EQ(h.seq_gaps, c.seq_gaps) << what;
  EXPECT_EQ(h.truncated, c.truncated) << what;
  EXPECT_EQ(h.resyncs, c.resyncs) << what;
  EXPECT_EQ(h.dropped_bytes, c.dropped_bytes) << what;
}

// 200k streams: random bytes, valid frames of random types and lengths, and mutated frames (bit
// flips, dropped, inserted and duplicated bytes, cut ends). Both decoders must deliver the same
// frames and keep the same counters, whatever chunks the host is fed in; every byte ends up
// either in a delivered frame or counted as dropped.
TEST(DeviceProtocol, FuzzBothDecodersAgree) {
  std::mt19937 rng(20261203);
  HostCollector host(FrameDirection::kHostToDevice);
  FirmwareCollector fw;
  std::size_t fed = 0;
  std::size_t last_checked = 0;
  for (int stream = 0; stream < 200000; ++stream) {
    Bytes s;
    const unsigned kind = rng() % 4;
    if (kind == 0) {
      s.resize(rng() % 40);
      for (auto& b : s) b = static_cast<std::uint8_t>(rng() % 3 == 0 ? (rng() % 2 ? 0xA5 : 0x5A) : rng());
    } else {
      const int frames = 1 + static_cast<int>(rng() % 3);
      for (int f = 0; f < frames; ++f) {
        const unsigned t = rng() % 5;
        const auto seq = static_cast<std::uint16_t>(rng() % 8 == 0 ? rng() : (stream * 3 + f) & 0xFFFF);
        Bytes frame;
        if (t == 0) {
          ActuatorPattern p;
          p.device = static_cast<DeviceKind>(1 + rng() % 4);
          const unsigned n = rng() % 9;
          for (unsigned k = 0; k < n; ++k) {
            p.commands.push_back({static_cast<std::uint8_t>(rng() % 10), static_cast<std::int16_t>(rng()),
                                  static_cast<std::uint16_t>(rng()), static_cast<std::uint16_t>(rng()),
                                  static_cast<std::uint16_t>(rng())});
          }
          frame = testing::host_pattern(p, seq);
        } else if (t == 1) {
          frame = testing::host_all_off(seq);
        } else if (t == 2) {
          frame = testing::host_heartbeat(seq, rng() % 4 == 0);
        } else {
          Bytes payload(rng() % (protocol::kMaxPayload + 1));
          for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
          frame = testing::raw_frame(static_cast<std::uint8_t>(t == 3 ? rng() : 1), seq, payload);
        }
        if (kind == 2) {
          const unsigned m = rng() % 5;
          const std::size_t at = rng() % frame.size();
          if (m == 0) frame[at] = static_cast<std::uint8_t>(frame[at] ^ (1u << (rng() % 8)));
          if (m == 1) frame.erase(frame.begin() + static_cast<long>(at));
          if (m == 2) frame.insert(frame.begin() + static_cast<long>(at), static_cast<std::uint8_t>(rng()));
          if (m == 3) frame.resize(at);
          if (m == 4) frame.insert(frame.end(), frame.begin(), frame.begin() + static_cast<long>(at));
        }
        s = testing::cat({s, frame});
      }
    }
    fw.feed(s);
    // The host gets the same bytes in random chunks.
    std::size_t pos = 0;
    while (pos < s.size()) {
      const std::size_t n = std::min<std::size_t>(s.size() - pos, 1 + rng() % (rng() % 4 == 0 ? 200 : 16));
      host.feed(s.data() + pos, n);
      pos += n;
    }
    fed += s.size();
    if (rng() % 64 == 0) {
      host.flush();
      fw.flush();
    }
    if (stream % 20000 == 19999) {
      ASSERT_EQ(host.frames.size(), fw.frames.size()) << "stream " << stream;
      for (std::size_t i = last_checked; i < host.frames.size(); ++i) {
        ASSERT_EQ(host.frames[i], fw.frames[i]) << "frame " << i;
      }
      last_checked = host.frames.size();
      expect_same_counters(host.decoder().counters(), fw.counters(), "stream " + std::to_string(stream));
    }
  }
  host.flush();
  fw.flush();
  ASSERT_EQ(host.frames.size(), fw.frames.size());
  EXPECT_TRUE(std::equal(host.frames.begin(), host.frames.end(), fw.frames.begin()));
  const DecoderCounters& c = host.decoder().counters();
  expect_same_counters(c, fw.counters(), "end");
  std::size_t delivered_bytes = 0;
  std::size_t well_formed = 0;
  for (std::size_t i = 0; i < host.frames.size(); ++i) {
    delivered_bytes += protocol::kOverhead + host.frames[i].payload.size();
    well_formed += host.well_formed[i] ? 1 : 0;
  }
  EXPECT_EQ(delivered_bytes + c.dropped_bytes, fed);
  EXPECT_EQ(well_formed, c.frames_ok);
  EXPECT_LE(c.replayed, c.frames_ok);
  // The fuzz reaches every kind of rejection.
  EXPECT_GT(c.frames_ok, 100000u);
  EXPECT_GT(c.crc_errors, 1000u);
  EXPECT_GT(c.length_errors, 1000u);
  EXPECT_GT(c.unknown_type, 1000u);
  EXPECT_GT(c.truncated, 100u);
  EXPECT_GT(c.replayed, 100u);
}

}  // namespace
}  // namespace navaid::interaction
