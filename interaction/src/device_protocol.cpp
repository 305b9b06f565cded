// The host's end of the device link's framing (docs/device-protocol.md). Deliberately shares no
// code with interaction/firmware/navaid_link.c: the tests run each against the other.
#include "navaid/interaction/device_protocol.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

#include "navaid/core/enum_names.hpp"

namespace navaid::interaction {

namespace {

constexpr NameTable<FrameType, 6> kFrameTypeNames{{
    {FrameType::kPattern, "pattern"},
    {FrameType::kAllOff, "all_off"},
    {FrameType::kHeartbeat, "heartbeat"},
    {FrameType::kAck, "ack"},
    {FrameType::kNak, "nak"},
    {FrameType::kHeartbeatReply, "heartbeat_reply"},
}};
constexpr NameTable<AckStatus, 3> kAckNames{{
    {AckStatus::kApplied, "applied"},
    {AckStatus::kDuplicate, "duplicate"},
    {AckStatus::kStale, "stale"},
}};
constexpr NameTable<NakReason, 5> kNakNames{{
    {NakReason::kBadLength, "bad_length"},
    {NakReason::kUnknownType, "unknown_type"},
    {NakReason::kWrongDevice, "wrong_device"},
    {NakReason::kBadActuator, "bad_actuator"},
    {NakReason::kBadLevel, "bad_level"},
}};

// The host has the memory for tables (the C side computes bit by bit): a different way to the
// same CRC is part of the cross-check. t1 is the classic byte table; t2 advances a byte through
// two steps, so that two bytes cost two independent lookups (the CRC is linear:
// T[a ^ b] = T[a] ^ T[b]), which halves the dependency chain per byte.
struct CrcTables {
  std::array<std::uint16_t, 256> t1{};
  std::array<std::uint16_t, 256> t2{};
  constexpr CrcTables() {
    for (unsigned i = 0; i < 256; ++i) {
      unsigned c = i << 8;
      for (int b = 0; b < 8; ++b) c = (c & 0x8000u) != 0 ? ((c << 1) ^ 0x1021u) : (c << 1);
      t1[i] = static_cast<std::uint16_t>(c & 0xFFFFu);
    }
    for (unsigned i = 0; i < 256; ++i) {
      t2[i] = static_cast<std::uint16_t>(((t1[i] & 0xFFu) << 8) ^ t1[t1[i] >> 8]);
    }
  }
};
constexpr CrcTables kCrc;

std::uint16_t le16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
void put_le16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v & 0xFF);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}

bool is_known_host_type(std::uint8_t t) {
  return t == static_cast<std::uint8_t>(FrameType::kPattern) || t == static_cast<std::uint8_t>(FrameType::kAllOff) ||
         t == static_cast<std::uint8_t>(FrameType::kHeartbeat);
}
bool is_known_device_type(std::uint8_t t) {
  return t == static_cast<std::uint8_t>(FrameType::kAck) || t == static_cast<std::uint8_t>(FrameType::kNak) ||
         t == static_cast<std::uint8_t>(FrameType::kHeartbeatReply);
}

/// A PATTERN whose count byte agrees with its length.
bool pattern_count_fits(const std::uint8_t* payload, std::size_t len) {
  return len >= 2 && 2 + static_cast<std::size_t>(payload[1]) * protocol::kActuatorSize == len;
}

}  // namespace

std::string_view to_string(FrameType type) { return enum_name(kFrameTypeNames, type); }
std::string_view to_string(AckStatus status) { return enum_name(kAckNames, status); }
std::string_view to_string(NakReason reason) { return enum_name(kNakNames, reason); }

std::uint16_t crc16_ccitt_false(const std::uint8_t* data, std::size_t n, std::uint16_t crc) {
  std::size_t i = 0;
  for (; i + 2 <= n; i += 2) {
    crc = static_cast<std::uint16_t>(kCrc.t2[((crc >> 8) ^ data[i]) & 0xFFu] ^ kCrc.t1[(crc ^ data[i + 1]) & 0xFFu]);
  }
  if (i < n) crc = static_cast<std::uint16_t>((crc << 8) ^ kCrc.t1[((crc >> 8) ^ data[i]) & 0xFFu]);
  return crc;
}

std::size_t encode_frame(std::uint8_t type, std::uint16_t seq, const std::uint8_t* payload, std::size_t len,
                         std::uint8_t* out) {
  if (len > protocol::kMaxPayload) {
    throw std::invalid_argument("device frame payload of " + std::to_string(len) + " bytes exceeds " +
                                std::to_string(protocol::kMaxPayload));
  }
  out[0] = protocol::kSync0;
  out[1] = protocol::kSync1;
  out[2] = static_cast<std::uint8_t>(len);
  out[3] = type;
  put_le16(out + 4, seq);
  if (len > 0) std::memcpy(out + protocol::kHeaderSize, payload, len);
  // The CRC covers length, type, sequence and payload: everything after the sync bytes.
  put_le16(out + protocol::kHeaderSize + len, crc16_ccitt_false(out + 2, 4 + len));
  return protocol::kOverhead + len;
}

std::size_t encode_pattern(const ActuatorPattern& pattern, std::uint16_t seq, std::uint8_t* out) {
  if (pattern.commands.size() > protocol::kMaxActuators) {
    throw std::invalid_argument("a device pattern holds at most " + std::to_string(protocol::kMaxActuators) +
                                " commands, got " + std::to_string(pattern.commands.size()));
  }
  std::array<std::uint8_t, protocol::kMaxPayload> p{};
  p[0] = static_cast<std::uint8_t>(pattern.device);
  p[1] = static_cast<std::uint8_t>(pattern.commands.size());
  std::uint8_t* c = p.data() + 2;
  for (const ActuatorCommand& cmd : pattern.commands) {
    c[0] = cmd.actuator;
    put_le16(c + 1, static_cast<std::uint16_t>(cmd.level));
    put_le16(c + 3, cmd.on_ms);
    put_le16(c + 5, cmd.off_ms);
    put_le16(c + 7, cmd.hold_ms);
    c += protocol::kActuatorSize;
  }
  return encode_frame(static_cast<std::uint8_t>(FrameType::kPattern), seq, p.data(),
                      2 + pattern.commands.size() * protocol::kActuatorSize, out);
}

std::size_t encode_all_off(std::uint16_t seq, std::uint8_t* out) {
  return encode_frame(static_cast<std::uint8_t>(FrameType::kAllOff), seq, nullptr, 0, out);
}

std::size_t encode_heartbeat(std::uint16_t seq, bool resync, std::uint8_t* out) {
  const std::uint8_t flags = resync ? protocol::kHeartbeatResync : 0;
  return encode_frame(static_cast<std::uint8_t>(FrameType::kHeartbeat), seq, &flags, 1, out);
}

std::size_t encode_ack(std::uint16_t seq, const Ack& ack, std::uint8_t* out) {
  std::uint8_t p[protocol::kAckSize];
  put_le16(p, ack.seq);
  p[2] = static_cast<std::uint8_t>(ack.status);
  return encode_frame(static_cast<std::uint8_t>(FrameType::kAck), seq, p, sizeof p, out);
}

std::size_t encode_nak(std::uint16_t seq, const Nak& nak, std::uint8_t* out) {
  std::uint8_t p[protocol::kNakSize];
  put_le16(p, nak.seq);
  p[2] = nak.reason;
  p[3] = nak.detail;
  return encode_frame(static_cast<std::uint8_t>(FrameType::kNak), seq, p, sizeof p, out);
}

std::size_t encode_heartbeat_reply(std::uint16_t seq, const HeartbeatReply& reply, std::uint8_t* out) {
  std::uint8_t p[protocol::kHeartbeatReplySize];
  put_le16(p, reply.seq);
  p[2] = static_cast<std::uint8_t>(reply.device);
  p[3] = reply.active_mask;
  put_le16(p + 4, reply.frames_ok);
  put_le16(p + 6, reply.crc_errors);
  return encode_frame(static_cast<std::uint8_t>(FrameType::kHeartbeatReply), seq, p, sizeof p, out);
}

std::optional<Ack> parse_ack(const DecodedFrame& f) {
  if (f.type != static_cast<std::uint8_t>(FrameType::kAck) || f.len != protocol::kAckSize) return std::nullopt;
  if (f.payload[2] > static_cast<std::uint8_t>(AckStatus::kStale)) return std::nullopt;
  return Ack{le16(f.payload), static_cast<AckStatus>(f.payload[2])};
}

std::optional<Nak> parse_nak(const DecodedFrame& f) {
  if (f.type != static_cast<std::uint8_t>(FrameType::kNak) || f.len != protocol::kNakSize) return std::nullopt;
  return Nak{le16(f.payload), f.payload[2], f.payload[3]};
}

std::optional<HeartbeatReply> parse_heartbeat_reply(const DecodedFrame& f) {
  if (f.type != static_cast<std::uint8_t>(FrameType::kHeartbeatReply) || f.len != protocol::kHeartbeatReplySize) {
    return std::nullopt;
  }
  const std::uint8_t kind = f.payload[2];
  if (kind < static_cast<std::uint8_t>(DeviceKind::kBelt) || kind > static_cast<std::uint8_t>(DeviceKind::kWheel)) {
    return std::nullopt;
  }
  HeartbeatReply r;
  r.seq = le16(f.payload);
  r.device = static_cast<DeviceKind>(kind);
  r.active_mask = f.payload[3];
  r.frames_ok = le16(f.payload + 4);
  r.crc_errors = le16(f.payload + 6);
  return r;
}

std::optional<ActuatorPattern> parse_pattern(const DecodedFrame& f) {
  if (f.type != static_cast<std::uint8_t>(FrameType::kPattern) || !pattern_count_fits(f.payload, f.len)) {
    return std::nullopt;
  }
  const std::uint8_t kind = f.payload[0];
  if (kind < static_cast<std::uint8_t>(DeviceKind::kBelt) || kind > static_cast<std::uint8_t>(DeviceKind::kWheel)) {
    return std::nullopt;
  }
  ActuatorPattern p;
  p.device = static_cast<DeviceKind>(kind);
  const std::uint8_t* c = f.payload + 2;
  for (std::size_t k = 0; k < f.payload[1]; ++k, c += protocol::kActuatorSize) {
    ActuatorCommand cmd;
    cmd.actuator = c[0];
    cmd.level = static_cast<std::int16_t>(le16(c + 1));
    cmd.on_ms = le16(c + 3);
    cmd.off_ms = le16(c + 5);
    cmd.hold_ms = le16(c + 7);
    p.commands.push_back(cmd);
  }
  return p;
}

// ---- decoder ----

FrameDecoder::FrameDecoder(FrameDirection direction) : direction_(direction) {}

int FrameDecoder::check_length(std::uint8_t type, std::size_t len) const {
  const bool host = direction_ != FrameDirection::kDeviceToHost && is_known_host_type(type);
  const bool device = direction_ != FrameDirection::kHostToDevice && is_known_device_type(type);
  if (!host && !device) return -1;
  switch (static_cast<FrameType>(type)) {
    case FrameType::kPattern: return len >= 2 && (len - 2) % protocol::kActuatorSize == 0 ? 1 : 0;
    case FrameType::kAllOff: return len == 0 ? 1 : 0;
    case FrameType::kHeartbeat: return len == protocol::kHeartbeatSize ? 1 : 0;
    case FrameType::kAck: return len == protocol::kAckSize ? 1 : 0;
    case FrameType::kNak: return len == protocol::kNakSize ? 1 : 0;
    case FrameType::kHeartbeatReply: return len == protocol::kHeartbeatReplySize ? 1 : 0;
  }
  return -1;
}

std::size_t FrameDecoder::skip_to_next_sync(const std::uint8_t* p, std::size_t n) {
  // Drop the candidate's first byte, then whatever cannot start a frame.
  std::size_t k = 1;
  while (k < n && p[k] != protocol::kSync0) ++k;
  counters_.dropped_bytes += k;
  return k;
}

SequenceStatus FrameDecoder::classify(std::uint8_t type, std::uint16_t seq, const std::uint8_t* payload) {
  const bool anchor =
      (type == static_cast<std::uint8_t>(FrameType::kHeartbeat) && (payload[0] & protocol::kHeartbeatResync) != 0) ||
      type == static_cast<std::uint8_t>(FrameType::kHeartbeatReply);
  if (anchor || !has_seq_) {
    has_seq_ = true;
    last_seq_ = seq;
    return SequenceStatus::kNew;
  }
  // Serial arithmetic on 16 bits: ahead by 1..32767 is new, behind by 1..32768 is stale.
  const auto ahead = static_cast<std::uint16_t>(seq - last_seq_);
  if (ahead == 0) return SequenceStatus::kDuplicate;
  if (ahead > 0x7FFF) return SequenceStatus::kStale;
  counters_.seq_gaps += ahead - 1u;
  last_seq_ = seq;
  return SequenceStatus::kNew;
}

std::size_t FrameDecoder::scan(const std::uint8_t* p, std::size_t n, const Callback& on_frame) {
  // Every decision needs only the bytes of the candidate at `at`, so scanning a whole chunk in
  // place decides exactly as feeding it byte by byte would; what is left is one partial candidate.
  std::size_t at = 0;
  while (at < n) {
    const std::uint8_t* c = p + at;
    const std::size_t avail = n - at;
    if (c[0] != protocol::kSync0 || (avail >= 2 && c[1] != protocol::kSync1)) {
      at += skip_to_next_sync(c, avail);
      continue;
    }
    if (avail < 3) return at;
    const std::size_t len = c[2];
    if (len > protocol::kMaxPayload) {
      // The length byte alone rules the candidate out.
      ++counters_.length_errors;
      ++counters_.resyncs;
      at += skip_to_next_sync(c, avail);
      continue;
    }
    if (avail < 4) return at;
    const std::uint8_t type = c[3];
    const int fit = check_length(type, len);
    if (fit == 0) {
      ++counters_.length_errors;
      ++counters_.resyncs;
      at += skip_to_next_sync(c, avail);
      continue;
    }
    const std::size_t total = protocol::kOverhead + len;
    if (avail < total) return at;
    if (crc16_ccitt_false(c + 2, 4 + len) != le16(c + protocol::kHeaderSize + len)) {
      ++counters_.crc_errors;
      ++counters_.resyncs;
      at += skip_to_next_sync(c, avail);
      continue;
    }
    DecodedFrame f;
    f.type = type;
    f.seq = le16(c + 4);
    f.payload = c + protocol::kHeaderSize;
    f.len = len;
    if (fit < 0) {
      ++counters_.unknown_type;
    } else if (type == static_cast<std::uint8_t>(FrameType::kPattern) && !pattern_count_fits(f.payload, len)) {
      ++counters_.length_errors;
    } else {
      f.well_formed = true;
      ++counters_.frames_ok;
      f.seq_status = classify(type, f.seq, f.payload);
      if (f.seq_status != SequenceStatus::kNew) ++counters_.replayed;
    }
    if (on_frame) on_frame(f);
    at += total;
  }
  return at;
}

void FrameDecoder::scan_buffer(const Callback& on_frame) {
  const std::size_t used = scan(buf_.data(), size_, on_frame);
  std::memmove(buf_.data(), buf_.data() + used, size_ - used);
  size_ -= used;
}

void FrameDecoder::feed(const std::uint8_t* data, std::size_t n, const Callback& on_frame) {
  std::size_t i = 0;
  // A partial candidate from the last chunk: complete it byte by byte (scan_buffer never leaves a
  // whole frame's worth behind, so one more byte always fits).
  while (i < n && size_ > 0) {
    buf_[size_++] = data[i++];
    scan_buffer(on_frame);
  }
  if (i == n) return;
  // Then straight from the caller's bytes, keeping only a partial candidate at the end.
  const std::size_t used = scan(data + i, n - i, on_frame);
  size_ = n - i - used;
  std::memcpy(buf_.data(), data + i + used, size_);
}

void FrameDecoder::flush(const Callback& on_frame) {
  if (size_ == 0) return;
  ++counters_.truncated;
  while (size_ > 0) {
    // Whatever is left starts with a sync byte; a full sync pair was a candidate frame.
    if (size_ >= 2) ++counters_.resyncs;
    const std::size_t k = skip_to_next_sync(buf_.data(), size_);
    std::memmove(buf_.data(), buf_.data() + k, size_ - k);
    size_ -= k;
    scan_buffer(on_frame);
  }
}

void FrameDecoder::reset() {
  counters_.dropped_bytes += size_;
  size_ = 0;
  has_seq_ = false;
}

}  // namespace navaid::interaction
