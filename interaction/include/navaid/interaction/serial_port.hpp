#pragma once
// A serial port in raw mode (termios): the host's end of the device link to the vibration
// controller, a USB serial adapter (/dev/ttyUSB0, /dev/ttyACM0), a Bluetooth serial port
// (/dev/rfcomm0) or a pseudo-terminal (the simulated controller, socat).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

struct pollfd;

namespace navaid::interaction {

/// The baud rates SerialPort accepts (termios has no arbitrary rates).
const std::vector<int>& supported_baud_rates();

class SerialPort {
 public:
  /// Opens `path` read-write, raw 8N1, no flow control, at `baud`. Throws IoError naming the path
  /// and the reason (errno text) when it is missing, not a terminal, or the rate is not supported.
  explicit SerialPort(std::string path, int baud = 115200);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;
  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;

  /// Waits up to `timeout_ms` (0: do not wait) for bytes and reads what is there, at most `cap`.
  /// Returns 0 when nothing came in time. Throws IoError when the device went away (unplugged,
  /// the other end of a pseudo-terminal closed) or reading failed.
  std::size_t read(std::uint8_t* out, std::size_t cap, int timeout_ms);
  /// Writes `n` bytes, waiting up to `timeout_ms` for room; returns how many were written (fewer
  /// than `n` only when the output stayed full that long). Throws IoError when writing failed.
  std::size_t write(const std::uint8_t* data, std::size_t n, int timeout_ms = 50);

  bool is_open() const { return fd_ >= 0; }
  void close();
  const std::string& path() const { return path_; }
  int baud() const { return baud_; }
  int fd() const { return fd_; }

 private:
  /// poll() on the port, retried after EINTR; IoError on failure. 0 on timeout.
  int wait_for(struct pollfd& p, int timeout_ms) const;

  std::string path_;
  int baud_ = 0;
  int fd_ = -1;
};

}  // namespace navaid::interaction
