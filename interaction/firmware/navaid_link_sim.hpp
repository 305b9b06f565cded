#pragma once
// The controller firmware (navaid_link.c) running on the host behind a serial line, for tests,
// benchmarks and trying the device link without hardware (docs/device-protocol.md).
//
// Two ways to stand in for the controller:
//   - create a pseudo-terminal (posix_openpt): the host opens slave_path(), or link_path, a
//     symlink kept pointing at the current pty, so that a restarted controller is found again;
//   - attach to an existing tty, e.g. one end of a socat null-modem pair.
// A thread runs the firmware loop: read bytes, navaid_link_device_rx/tick with a millisecond
// clock, write the replies. Header-only C++ (POSIX) on purpose: it is not part of the firmware
// that goes on a microcontroller, and it needs nothing but the C library navaid_device_firmware.
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "navaid_link.h"

namespace navaid::firmware_sim {

/// What the simulated controller is doing, copied under its lock.
struct ControllerSnapshot {
  navaid_link_device_counters device{};
  navaid_link_counters decoder{};
  std::int16_t outputs[NAVAID_LINK_MAX_ACTUATORS] = {};
  std::uint8_t active_mask = 0;
  bool link_alive = false;
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
};

class SimulatedController {
 public:
  /// A controller of `device_kind` (NAVAID_LINK_DEVICE_*) with `actuators` outputs behind a new
  /// pseudo-terminal; when `link_path` is not empty, a symlink there points at the pty.
  SimulatedController(std::uint8_t device_kind, std::uint8_t actuators, std::string link_path = {})
      : kind_(device_kind), actuators_(actuators), link_path_(std::move(link_path)) {
    start();
  }
  /// An existing tty to run on instead of a new pty.
  struct AttachTo {
    std::string path;
  };
  /// A controller on an existing tty (e.g. one end of a socat pair).
  SimulatedController(std::uint8_t device_kind, std::uint8_t actuators, AttachTo tty)
      : kind_(device_kind), actuators_(actuators), attach_(true), attach_path_(tty.path), slave_path_(tty.path) {
    start();
  }
  static SimulatedController attach(std::uint8_t device_kind, std::uint8_t actuators, const std::string& attach_path) {
    return SimulatedController(device_kind, actuators, AttachTo{attach_path});
  }
  ~SimulatedController() { stop(); }
  SimulatedController(const SimulatedController&) = delete;
  SimulatedController& operator=(const SimulatedController&) = delete;
  SimulatedController(SimulatedController&& o) noexcept = delete;

  /// Starts (or restarts after stop()) with a fresh firmware state, as a power cycle does. A pty
  /// controller gets a new pty; link_path is re-pointed at it.
  void start() {
    if (running_) return;
    if (attach_) {
      fd_ = open_raw(attach_path_);
      hold_fd_ = -1;
    } else {
      open_pty();
    }
    navaid_link_device_init(&dev_, kind_, actuators_, 0, now_ms());
    stop_flag_ = false;
    running_ = true;
    thread_ = std::thread([this] { loop(); });
  }

  /// Stops the firmware loop and closes the line (the host sees the device hang up). link_path
  /// is removed, as an unplugged adapter's device node is: the freed pty number may be handed to
  /// another program at once, and a host reopening the old link must not land there.
  void stop() {
    if (!running_) return;
    stop_flag_ = true;
    thread_.join();
    running_ = false;
    if (!attach_ && !link_path_.empty()) ::unlink(link_path_.c_str());
    if (fd_ >= 0) ::close(fd_);
    if (hold_fd_ >= 0) ::close(hold_fd_);
    fd_ = -1;
    hold_fd_ = -1;
  }
  bool running() const { return running_; }

  /// Keeps the line open but stops answering (and listening): a controller that hangs.
  void set_mute(bool mute) { mute_ = mute; }

  /// Bytes written to the host as they are, e.g. line noise between replies.
  void inject_to_host(const std::vector<std::uint8_t>& bytes) {
    std::lock_guard<std::mutex> lock(mu_);
    pending_out_.insert(pending_out_.end(), bytes.begin(), bytes.end());
  }
  /// Bytes fed to the firmware as if received, e.g. noise on the host's line.
  void inject_to_device(const std::vector<std::uint8_t>& bytes) {
    std::lock_guard<std::mutex> lock(mu_);
    navaid_link_device_rx(&dev_, bytes.data(), bytes.size(), now_ms());
  }

  /// The pty the host opens (the attach path for an attached controller).
  const std::string& slave_path() const { return slave_path_; }
  /// link_path when given, else slave_path().
  const std::string& host_path() const { return link_path_.empty() ? slave_path_ : link_path_; }

  ControllerSnapshot snapshot() const {
    std::lock_guard<std::mutex> lock(mu_);
    ControllerSnapshot s;
    s.device = dev_.counters;
    s.decoder = dev_.dec.counters;
    for (std::uint8_t i = 0; i < NAVAID_LINK_MAX_ACTUATORS; ++i) s.outputs[i] = navaid_link_device_output(&dev_, i);
    s.active_mask = navaid_link_device_active_mask(&dev_);
    s.link_alive = dev_.link_alive != 0;
    s.bytes_in = bytes_in_;
    s.bytes_out = bytes_out_;
    return s;
  }

  /// The controller's free-running millisecond counter (as millis() on an Arduino).
  static std::uint32_t now_ms() {
    using namespace std::chrono;
    return static_cast<std::uint32_t>(duration_cast<milliseconds>(steady_clock::now().time_since_epoch()).count());
  }

 private:
  static void make_raw(int fd, const std::string& what) {
    termios tio{};
    if (::tcgetattr(fd, &tio) != 0) throw std::runtime_error(what + ": tcgetattr: " + std::strerror(errno));
    ::cfmakeraw(&tio);
    tio.c_cflag |= CLOCAL | CREAD;
    tio.c_cc[VMIN] = 0;
    tio.c_cc[VTIME] = 0;
    ::cfsetispeed(&tio, B115200);
    ::cfsetospeed(&tio, B115200);
    if (::tcsetattr(fd, TCSANOW, &tio) != 0) throw std::runtime_error(what + ": tcsetattr: " + std::strerror(errno));
  }

  static int open_raw(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
    make_raw(fd, path);
    return fd;
  }

  void open_pty() {
    const int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (master < 0) throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
    if (::grantpt(master) != 0 || ::unlockpt(master) != 0) {
      const std::string err = std::strerror(errno);
      ::close(master);
      throw std::runtime_error("grantpt/unlockpt: " + err);
    }
    char name[128] = {};
    if (::ptsname_r(master, name, sizeof name) != 0) {
      const std::string err = std::strerror(errno);
      ::close(master);
      throw std::runtime_error("ptsname: " + err);
    }
    slave_path_ = name;
    // Holding the slave open ourselves keeps the master readable while the host is away (a master
    // without any slave open reads EIO) and lets us set raw mode before the host arrives.
    hold_fd_ = open_raw(slave_path_);
    fd_ = master;
    if (!link_path_.empty()) {
      const std::string tmp = link_path_ + ".new";
      ::unlink(tmp.c_str());
      if (::symlink(slave_path_.c_str(), tmp.c_str()) != 0 || ::rename(tmp.c_str(), link_path_.c_str()) != 0) {
        throw std::runtime_error(link_path_ + ": cannot link to " + slave_path_ + ": " + std::strerror(errno));
      }
    }
  }

  void loop() {
    std::uint8_t buf[256];
    while (!stop_flag_) {
      pollfd p{fd_, POLLIN, 0};
      ::poll(&p, 1, 1);
      ssize_t n = 0;
      if (!mute_ && (p.revents & POLLIN) != 0) n = ::read(fd_, buf, sizeof buf);
      std::vector<std::uint8_t> out;
      {
        std::lock_guard<std::mutex> lock(mu_);
        const std::uint32_t now = now_ms();
        if (n > 0) {
          bytes_in_ += static_cast<std::uint64_t>(n);
          navaid_link_device_rx(&dev_, buf, static_cast<std::size_t>(n), now);
        } else {
          navaid_link_device_tick(&dev_, now);
        }
        std::uint8_t tx[NAVAID_LINK_TX_BUFFER];
        const std::size_t k = navaid_link_device_tx(&dev_, tx, sizeof tx);
        out.swap(pending_out_);
        if (!mute_) out.insert(out.end(), tx, tx + k);
      }
      std::size_t done = 0;
      while (done < out.size()) {
        const ssize_t w = ::write(fd_, out.data() + done, out.size() - done);
        if (w <= 0) break;  // nobody reading: the bytes are lost, as on a real UART
        done += static_cast<std::size_t>(w);
      }
      bytes_out_ += done;
    }
  }

  std::uint8_t kind_;
  std::uint8_t actuators_;
  bool attach_ = false;
  std::string attach_path_;
  std::string link_path_;
  std::string slave_path_;
  int fd_ = -1;
  int hold_fd_ = -1;
  mutable std::mutex mu_;
  navaid_link_device dev_{};
  std::vector<std::uint8_t> pending_out_;
  std::atomic<std::uint64_t> bytes_in_{0};
  std::atomic<std::uint64_t> bytes_out_{0};
  std::thread thread_;
  std::atomic<bool> stop_flag_{false};
  std::atomic<bool> mute_{false};
  bool running_ = false;
};

}  // namespace navaid::firmware_sim
