// termios in raw mode with poll(2) for timeouts; the port is opened non-blocking so that neither a
// missing carrier nor a full output buffer can hang the guidance loop.
#include "navaid/interaction/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include "navaid/core/errors.hpp"

namespace navaid::interaction {

namespace {

struct BaudEntry {
  int rate;
  speed_t code;
};
constexpr BaudEntry kBauds[] = {{9600, B9600},     {19200, B19200},   {38400, B38400},   {57600, B57600},
                                {115200, B115200}, {230400, B230400}, {460800, B460800}, {921600, B921600}};

std::string errno_text(int err) { return std::strerror(err); }

}  // namespace

const std::vector<int>& supported_baud_rates() {
  static const std::vector<int> rates = [] {
    std::vector<int> r;
    for (const BaudEntry& b : kBauds) r.push_back(b.rate);
    return r;
  }();
  return rates;
}

SerialPort::SerialPort(std::string path, int baud) : path_(std::move(path)), baud_(baud) {
  const BaudEntry* entry = nullptr;
  for (const BaudEntry& b : kBauds) {
    if (b.rate == baud) entry = &b;
  }
  if (entry == nullptr) {
    std::string list;
    for (int r : supported_baud_rates()) list += (list.empty() ? "" : ", ") + std::to_string(r);
    throw IoError(path_, "unsupported baud rate " + std::to_string(baud) + " (supported: " + list + ")");
  }
  fd_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    throw IoError(path_, "cannot open serial port: " + errno_text(err));
  }
  termios tio{};
  if (!::isatty(fd_) || ::tcgetattr(fd_, &tio) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    throw IoError(path_, "not a serial port (tty): " + errno_text(err));
  }
  // Raw 8N1: no echo, no line editing, no CR/LF translation, no software flow control; CLOCAL
  // because adapters without modem lines would otherwise never be "connected".
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (::cfsetispeed(&tio, entry->code) != 0 || ::cfsetospeed(&tio, entry->code) != 0 ||
      ::tcsetattr(fd_, TCSANOW, &tio) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    throw IoError(path_, "cannot configure serial port at " + std::to_string(baud) + " baud: " + errno_text(err));
  }
  // Bytes left over from before we opened belong to nobody.
  ::tcflush(fd_, TCIOFLUSH);
}

SerialPort::~SerialPort() { close(); }

SerialPort::SerialPort(SerialPort&& other) noexcept
    : path_(std::move(other.path_)), baud_(other.baud_), fd_(std::exchange(other.fd_, -1)) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close();
    path_ = std::move(other.path_);
    baud_ = other.baud_;
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

int SerialPort::wait_for(pollfd& p, int timeout_ms) const {
  int r = 0;
  do {
    r = ::poll(&p, 1, timeout_ms);
  } while (r < 0 && errno == EINTR);
  if (r < 0) {
    const int err = errno;
    throw IoError(path_, "waiting for the serial port failed: " + errno_text(err));
  }
  return r;
}

std::size_t SerialPort::read(std::uint8_t* out, std::size_t cap, int timeout_ms) {
  if (fd_ < 0) throw IoError(path_, "serial port is closed");
  pollfd p{fd_, POLLIN, 0};
  if (wait_for(p, timeout_ms) == 0) return 0;
  if ((p.revents & POLLNVAL) != 0) throw IoError(path_, "serial port descriptor is no longer valid");
  // Read even when POLLHUP is set too: the bytes that came before the hang-up still count.
  const ssize_t n = ::read(fd_, out, cap);
  if (n > 0) return static_cast<std::size_t>(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
    if ((p.revents & (POLLHUP | POLLERR)) == 0) return 0;
    throw IoError(path_, "serial device hung up");
  }
  if (n < 0) {
    const int err = errno;
    throw IoError(path_, "serial device went away: " + errno_text(err));
  }
  // Readable but no byte: end of file, the device hung up.
  throw IoError(path_, "serial device hung up");
}

std::size_t SerialPort::write(const std::uint8_t* data, std::size_t n, int timeout_ms) {
  if (fd_ < 0) throw IoError(path_, "serial port is closed");
  std::size_t done = 0;
  bool waited = false;
  while (done < n) {
    const ssize_t w = ::write(fd_, data + done, n - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
      continue;
    }
    if (w < 0 && errno == EINTR) continue;
    if (w < 0 && errno != EAGAIN) {
      const int err = errno;
      throw IoError(path_, "writing to the serial port failed: " + errno_text(err));
    }
    // Output full: wait once for room, then give up on the rest (the frame decoder on the other
    // side drops the partial frame).
    if (waited) break;
    waited = true;
    pollfd p{fd_, POLLOUT, 0};
    const int r = wait_for(p, timeout_ms);
    if ((p.revents & (POLLERR | POLLNVAL)) != 0) throw IoError(path_, "serial device went away");
    if (r == 0) break;
  }
  return done;
}

}  // namespace navaid::interaction
