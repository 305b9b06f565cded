#pragma once
// The host's end of the framed serial protocol to the vibration controller
// (docs/device-protocol.md): frame encoders and an incremental decoder with the same counters as
// the controller's C decoder (interaction/firmware/navaid_link.h). Written separately from the C
// code on purpose, so that each implementation tests the other.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

#include "navaid/interaction/actuator_pattern.hpp"

namespace navaid::interaction {

enum class FrameType : std::uint8_t {
  kPattern = 0x01,         ///< host -> device: an ActuatorPattern
  kAllOff = 0x02,          ///< host -> device: switch every actuator off
  kHeartbeat = 0x03,       ///< host -> device: are you there (flags byte)
  kAck = 0x81,             ///< device -> host: acknowledged sequence + status
  kNak = 0x82,             ///< device -> host: refused sequence + reason + detail
  kHeartbeatReply = 0x83,  ///< device -> host: the answer to a heartbeat
};
std::string_view to_string(FrameType type);

enum class AckStatus : std::uint8_t {
  kApplied = 0,    ///< a new frame, carried out
  kDuplicate = 1,  ///< the same sequence as the last accepted frame: not re-applied
  kStale = 2,      ///< older than the last accepted frame: not applied
};
std::string_view to_string(AckStatus status);

enum class NakReason : std::uint8_t {
  kBadLength = 1,    ///< detail: the length byte
  kUnknownType = 2,  ///< detail: the type byte
  kWrongDevice = 3,  ///< detail: the device kind in the pattern
  kBadActuator = 4,  ///< detail: the actuator index (out of range or repeated)
  kBadLevel = 5,     ///< detail: the actuator index (motor level outside [0, 1000])
};
/// "unknown" for values outside the enum (a newer controller may send more).
std::string_view to_string(NakReason reason);

/// Whether a received frame's sequence number is new, the last one again or older.
enum class SequenceStatus : std::uint8_t { kNew, kDuplicate, kStale };

namespace protocol {
constexpr std::uint8_t kSync0 = 0xA5;
constexpr std::uint8_t kSync1 = 0x5A;
constexpr std::size_t kHeaderSize = 6;  ///< sync0 sync1 len type seq_lo seq_hi
constexpr std::size_t kOverhead = kHeaderSize + 2;
constexpr std::size_t kMaxActuators = 8;
constexpr std::size_t kActuatorSize = 9;  ///< index u8, level i16, on_ms, off_ms, hold_ms u16
constexpr std::size_t kMaxPayload = 2 + kMaxActuators * kActuatorSize;
constexpr std::size_t kMaxFrame = kOverhead + kMaxPayload;
constexpr std::size_t kAckSize = 3;
constexpr std::size_t kNakSize = 4;
constexpr std::size_t kHeartbeatSize = 1;
constexpr std::size_t kHeartbeatReplySize = 8;
constexpr std::uint8_t kHeartbeatResync = 0x01;  ///< the receiver takes this sequence as its base
constexpr int kInterbyteTimeoutMs = 50;           ///< a partial frame older than this is abandoned
}  // namespace protocol

using FrameBuffer = std::array<std::uint8_t, protocol::kMaxFrame>;

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, xorout 0): "123456789" -> 0x29B1.
std::uint16_t crc16_ccitt_false(const std::uint8_t* data, std::size_t n, std::uint16_t crc = 0xFFFF);

/// Writes one frame into `out` and returns its size. Throws std::invalid_argument when the
/// payload is longer than protocol::kMaxPayload.
std::size_t encode_frame(std::uint8_t type, std::uint16_t seq, const std::uint8_t* payload, std::size_t len,
                         std::uint8_t* out);
/// A PATTERN frame. The pattern's timestamp stays on the host: the controller times holds from
/// receipt. Throws std::invalid_argument for more than protocol::kMaxActuators commands.
std::size_t encode_pattern(const ActuatorPattern& pattern, std::uint16_t seq, std::uint8_t* out);
std::size_t encode_all_off(std::uint16_t seq, std::uint8_t* out);
std::size_t encode_heartbeat(std::uint16_t seq, bool resync, std::uint8_t* out);

struct Ack {
  std::uint16_t seq = 0;  ///< the acknowledged host sequence
  AckStatus status = AckStatus::kApplied;
};
struct Nak {
  std::uint16_t seq = 0;  ///< the refused host sequence
  std::uint8_t reason = 0;  ///< a NakReason, kept raw so that unknown reasons survive
  std::uint8_t detail = 0;
};
struct HeartbeatReply {
  std::uint16_t seq = 0;  ///< the heartbeat's sequence
  DeviceKind device = DeviceKind::kBelt;
  std::uint8_t active_mask = 0;   ///< bit i: actuator i held
  std::uint16_t frames_ok = 0;    ///< the controller's counters, low 16 bits
  std::uint16_t crc_errors = 0;
};

/// Device-to-host encoders, for simulated controllers and the round-trip tests.
std::size_t encode_ack(std::uint16_t seq, const Ack& ack, std::uint8_t* out);
std::size_t encode_nak(std::uint16_t seq, const Nak& nak, std::uint8_t* out);
std::size_t encode_heartbeat_reply(std::uint16_t seq, const HeartbeatReply& reply, std::uint8_t* out);

/// One frame with a valid CRC. `payload` points into the decoder and is valid during the callback.
struct DecodedFrame {
  std::uint8_t type = 0;
  std::uint16_t seq = 0;
  SequenceStatus seq_status = SequenceStatus::kNew;
  bool well_formed = false;  ///< a known type with a consistent length (false: unknown type or count)
  const std::uint8_t* payload = nullptr;
  std::size_t len = 0;
};

/// Payload parsers; nullopt when the frame is of another type or malformed.
std::optional<Ack> parse_ack(const DecodedFrame& frame);
std::optional<Nak> parse_nak(const DecodedFrame& frame);
std::optional<HeartbeatReply> parse_heartbeat_reply(const DecodedFrame& frame);
std::optional<ActuatorPattern> parse_pattern(const DecodedFrame& frame);

/// The same counters as navaid_link_counters.
struct DecoderCounters {
  std::uint64_t frames_ok = 0;      ///< valid frames of a known type (replays included)
  std::uint64_t crc_errors = 0;
  std::uint64_t length_errors = 0;  ///< length byte too large or wrong for the type
  std::uint64_t unknown_type = 0;
  std::uint64_t replayed = 0;       ///< frames_ok with a duplicate or stale sequence
  std::uint64_t seq_gaps = 0;       ///< sequence numbers skipped between new frames
  std::uint64_t truncated = 0;      ///< partial frames abandoned by flush()
  std::uint64_t resyncs = 0;        ///< candidates dropped to search for the next sync
  std::uint64_t dropped_bytes = 0;  ///< bytes outside every delivered frame
};

/// Which frame types a decoder knows; the others count as unknown_type.
enum class FrameDirection { kDeviceToHost, kHostToDevice, kBoth };

/// Byte-at-a-time decoder that resynchronises on garbage: a candidate that fails (bad length,
/// bad CRC) is dropped from its first byte only, and the bytes after it are searched again, so a
/// good frame that follows a truncated one is not lost. The sequence anchors are HEARTBEAT with
/// the resync flag and every HEARTBEAT_REPLY (the controller restarts its numbering at boot).
class FrameDecoder {
 public:
  using Callback = std::function<void(const DecodedFrame&)>;
  explicit FrameDecoder(FrameDirection direction = FrameDirection::kDeviceToHost);

  void feed(const std::uint8_t* data, std::size_t n, const Callback& on_frame);
  /// Abandons a partial frame (counted as truncated) and searches its bytes again.
  void flush(const Callback& on_frame);
  bool has_partial() const { return size_ > 0; }
  /// The next frame's sequence is accepted as new whatever it is.
  void forget_sequence() { has_seq_ = false; }
  /// Drops buffered bytes and the sequence base; counters stay.
  void reset();
  const DecoderCounters& counters() const { return counters_; }

 private:
  /// 1: known type with a valid length, 0: known type with a wrong length, -1: unknown type.
  int check_length(std::uint8_t type, std::size_t len) const;
  /// Decides every candidate in p[0, n); returns how many bytes were used up (the rest is one
  /// partial candidate).
  std::size_t scan(const std::uint8_t* p, std::size_t n, const Callback& on_frame);
  void scan_buffer(const Callback& on_frame);
  /// Counts and returns how many bytes to drop: the first and those up to the next sync byte.
  std::size_t skip_to_next_sync(const std::uint8_t* p, std::size_t n);
  SequenceStatus classify(std::uint8_t type, std::uint16_t seq, const std::uint8_t* payload);

  FrameDirection direction_;
  std::array<std::uint8_t, protocol::kMaxFrame> buf_{};
  std::size_t size_ = 0;
  bool has_seq_ = false;
  std::uint16_t last_seq_ = 0;
  DecoderCounters counters_;
};

}  // namespace navaid::interaction
