// The vibration controller's side of the device link (interaction/firmware/navaid_link.c) as it
// runs on the device: received bytes at fuzzed times, ticks, and the replies read out. Outputs
// must stay within the motor range and replies must decode on the host.
#include <cstdio>
#include <cstdlib>

#include "device_link_testing.hpp"
#include "fuzz_support.hpp"

namespace {

void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "controller broke a promise: %s\n", what);
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid::interaction;
  if (size < 3) return 0;
  navaid_link_device dev;
  navaid_link_device_init(&dev, static_cast<std::uint8_t>(data[0] % 5), static_cast<std::uint8_t>(data[1]), 0, 0);
  const std::size_t chunk = 1 + data[2] % 32;
  testing::HostCollector replies(FrameDirection::kDeviceToHost);
  std::uint32_t now = 0;
  std::uint8_t out[NAVAID_LINK_TX_BUFFER];
  for (std::size_t i = 3; i < size; i += chunk) {
    const std::size_t m = std::min(chunk, size - i);
    now += 1u + data[i] * 7u;  // from 1 ms to beyond the inter-byte and link timeouts
    navaid_link_device_rx(&dev, data + i, m, now);
    navaid_link_device_tick(&dev, now);
    for (std::uint8_t a = 0; a < NAVAID_LINK_MAX_ACTUATORS; ++a) {
      const int level = navaid_link_device_output(&dev, a);
      // Motors run at [0, 1000] per mille; the wheel's output is a steering angle, any i16.
      if (dev.device_kind == NAVAID_LINK_DEVICE_WHEEL)
        require(level >= -32768 && level <= 32767, "wheel output within i16");
      else
        require(level >= 0 && level <= NAVAID_LINK_MOTOR_LEVEL_MAX, "motor output within [0, 1000]");
      require(a < dev.actuator_count || level == 0, "no output on an actuator the device lacks");
    }
    const std::size_t k = navaid_link_device_tx(&dev, out, sizeof out);
    require(k <= sizeof out, "tx within its buffer");
    replies.feed(out, k);
  }
  replies.flush();
  const DecoderCounters& c = replies.decoder().counters();
  require(c.crc_errors == 0 && c.length_errors == 0 && c.unknown_type == 0, "replies decode cleanly on the host");
  return 0;
}
