#pragma once
// Helpers for the device link tests: both decoders collecting what they deliver, so that the
// host's C++ implementation and the controller's C implementation can be compared frame by frame.
#include <cstdint>
#include <vector>

#include "navaid/interaction/device_protocol.hpp"
#include "navaid_link.h"

namespace navaid::interaction::testing {

using Bytes = std::vector<std::uint8_t>;

/// A delivered frame, copied out of the decoder.
struct Delivered {
  std::uint8_t type = 0;
  std::uint16_t seq = 0;
  int seq_status = 0;  ///< 0 new, 1 duplicate, 2 stale (as NAVAID_LINK_SEQ_*)
  Bytes payload;
  bool operator==(const Delivered& o) const {
    return type == o.type && seq == o.seq && seq_status == o.seq_status && payload == o.payload;
  }
};

/// The host decoder, remembering every frame.
class HostCollector {
 public:
  explicit HostCollector(FrameDirection direction) : dec_(direction) {}
  void feed(const Bytes& b) { feed(b.data(), b.size()); }
  void feed(const std::uint8_t* p, std::size_t n) {
    dec_.feed(p, n, [this](const DecodedFrame& f) { keep(f); });
  }
  void flush() {
    dec_.flush([this](const DecodedFrame& f) { keep(f); });
  }
  FrameDecoder& decoder() { return dec_; }
  /// Frame i as the parsers take it (a new, well-formed frame; the payload is kept here).
  DecodedFrame decoded(std::size_t i) const {
    return DecodedFrame{frames[i].type, frames[i].seq, SequenceStatus::kNew, true, frames[i].payload.data(),
                        frames[i].payload.size()};
  }
  std::vector<Delivered> frames;
  std::vector<bool> well_formed;

 private:
  void keep(const DecodedFrame& f) {
    frames.push_back({f.type, f.seq, static_cast<int>(f.seq_status), Bytes(f.payload, f.payload + f.len)});
    well_formed.push_back(f.well_formed);
  }
  FrameDecoder dec_;
};

/// The firmware's decoder, remembering every frame.
class FirmwareCollector {
 public:
  FirmwareCollector() { navaid_link_decoder_init(&dec_); }
  void feed(const Bytes& b) { feed(b.data(), b.size()); }
  void feed(const std::uint8_t* p, std::size_t n) { navaid_link_decoder_feed(&dec_, p, n, &keep, this); }
  void flush() { navaid_link_decoder_flush(&dec_, &keep, this); }
  const navaid_link_counters& counters() const { return dec_.counters; }
  std::vector<Delivered> frames;

 private:
  static void keep(void* ctx, const navaid_link_frame* f) {
    auto* self = static_cast<FirmwareCollector*>(ctx);
    self->frames.push_back({f->type, f->seq, f->seq_status, Bytes(f->payload, f->payload + f->len)});
  }
  navaid_link_decoder dec_;
};

inline Bytes frame_bytes(const std::uint8_t* p, std::size_t n) { return Bytes(p, p + n); }

inline Bytes host_pattern(const ActuatorPattern& p, std::uint16_t seq) {
  FrameBuffer b;
  return frame_bytes(b.data(), encode_pattern(p, seq, b.data()));
}
inline Bytes host_all_off(std::uint16_t seq) {
  FrameBuffer b;
  return frame_bytes(b.data(), encode_all_off(seq, b.data()));
}
inline Bytes host_heartbeat(std::uint16_t seq, bool resync = false) {
  FrameBuffer b;
  return frame_bytes(b.data(), encode_heartbeat(seq, resync, b.data()));
}
inline Bytes raw_frame(std::uint8_t type, std::uint16_t seq, const Bytes& payload) {
  FrameBuffer b;
  return frame_bytes(b.data(), encode_frame(type, seq, payload.data(), payload.size(), b.data()));
}

inline ActuatorPattern belt_pattern(std::uint8_t actuator, std::int16_t level, std::uint16_t hold_ms,
                                    std::uint16_t on_ms = 0, std::uint16_t off_ms = 0) {
  ActuatorPattern p;
  p.device = DeviceKind::kBelt;
  p.commands.push_back({actuator, level, on_ms, off_ms, hold_ms});
  return p;
}

inline Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

}  // namespace navaid::interaction::testing
