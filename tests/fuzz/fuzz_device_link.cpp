// The device link's two decoders (interaction/device_protocol.cpp on the host, the controller's C99
// decoder in interaction/firmware) fed the same bytes in the same chunks: they must deliver the
// same frames and count the same errors. Every frame the host delivers also goes through the
// payload parsers. The first byte sets the chunk size.
#include <cstdio>
#include <cstdlib>

#include "device_link_testing.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace navaid::interaction;

void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "host and controller decoders disagree: %s\n", what);
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 64;
  const std::uint8_t* p = data + 1;
  const std::size_t n = size - 1;
  testing::HostCollector host(FrameDirection::kHostToDevice);
  testing::FirmwareCollector fw;
  testing::HostCollector both(FrameDirection::kBoth);
  for (std::size_t i = 0; i < n; i += chunk) {
    const std::size_t m = std::min(chunk, n - i);
    host.feed(p + i, m);
    fw.feed(p + i, m);
    both.feed(p + i, m);
  }
  host.flush();
  fw.flush();
  both.flush();

  require(host.frames == fw.frames, "delivered frames");
  const DecoderCounters& h = host.decoder().counters();
  const navaid_link_counters& c = fw.counters();
  require(h.frames_ok == c.frames_ok, "frames_ok");
  require(h.crc_errors == c.crc_errors, "crc_errors");
  require(h.length_errors == c.length_errors, "length_errors");
  require(h.unknown_type == c.unknown_type, "unknown_type");
  require(h.replayed == c.replayed, "replayed");
  require(h.seq_gaps == c.seq_gaps, "seq_gaps");
  require(h.truncated == c.truncated, "truncated");
  require(h.resyncs == c.resyncs, "resyncs");
  require(h.dropped_bytes == c.dropped_bytes, "dropped_bytes");

  for (std::size_t i = 0; i < both.frames.size(); ++i) {
    const DecodedFrame f = both.decoded(i);
    (void)parse_ack(f);
    (void)parse_nak(f);
    (void)parse_heartbeat_reply(f);
    (void)parse_pattern(f);
  }
  return 0;
}
