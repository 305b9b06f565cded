#include "test_support.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <stdexcept>

namespace navaid::testing {

std::filesystem::path shared_data_dir() { return std::filesystem::path(NAVAID_SHARED_DATA_DIR); }

bool have_shared_data() { return std::filesystem::is_directory(shared_data_dir()); }

ScratchDir::ScratchDir(const std::string& name) {
  std::random_device rd;
  path_ = std::filesystem::temp_directory_path() / ("navaid-test-" + name + "-" + std::to_string(rd()));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

void write_text(const std::filesystem::path& file, const std::string& content) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  out << content;
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

ImuCalibration euroc_imu_calibration(double rate_hz) {
  ImuCalibration c;
  c.rate_hz = rate_hz;
  c.gyro_noise_density = 1.6968e-4;
  c.gyro_random_walk = 1.9393e-5;
  c.accel_noise_density = 2.0e-3;
  c.accel_random_walk = 3.0e-3;
  return c;
}

std::map<std::string, std::string> folder_contents(const std::filesystem::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root))
    if (e.is_regular_file()) files[std::filesystem::relative(e.path(), root).string()] = read_text(e.path());
  return files;
}

CliRun navaid_cli(const std::string& args, bool with_stderr) {
  const std::string command = "'" + std::string(NAVAID_CLI_PATH) + "' " + args + (with_stderr ? " 2>&1" : " 2>/dev/null");
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

namespace {

/// Holds an exclusive flock on a file while it lives.
class FileLock {
 public:
  explicit FileLock(const std::filesystem::path& file) : fd_(::open(file.c_str(), O_CREAT | O_RDWR, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) throw std::runtime_error("cannot lock " + file.string());
  }
  ~FileLock() { ::close(fd_); }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

}  // namespace

std::filesystem::path shared_fixture(const std::string& name, const std::string& recipe,
                                     const std::function<void(const std::filesystem::path&)>& make) {
  namespace fs = std::filesystem;
  const fs::path root(NAVAID_FIXTURE_DIR);
  fs::create_directories(root);
  // The key: the recipe and the program that makes and reads the inputs.
  const auto stamp = fs::last_write_time(NAVAID_CLI_PATH).time_since_epoch().count();
  const std::size_t key = std::hash<std::string>{}(recipe + "\n" + std::to_string(stamp));
  const fs::path folder = root / (name + "-" + std::to_string(key));
  const FileLock lock(root / (name + ".lock"));
  if (fs::exists(folder / ".complete")) return folder;
  // Made by an older program or recipe, or left half-made: gone before it is made anew.
  for (const auto& e : fs::directory_iterator(root)) {
    const std::string other = e.path().filename().string();
    const bool same_name = other.size() > name.size() + 1 && other.compare(0, name.size() + 1, name + "-") == 0 &&
                           other.find_first_not_of("0123456789", name.size() + 1) == std::string::npos;
    if (e.is_directory() && same_name) fs::remove_all(e.path());
  }
  fs::create_directories(folder);
  try {
    make(folder);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot make the test fixture " + name + ": " + e.what());
  }
  write_text(folder / ".complete", recipe);
  return folder;
}

std::filesystem::path shared_cli_fixture(const std::string& name, const std::vector<std::string>& commands) {
  std::string recipe;
  for (const auto& c : commands) recipe += c + "\n";
  return shared_fixture(name, recipe, [&](const std::filesystem::path& folder) {
    for (std::string command : commands) {
      for (std::size_t at; (at = command.find("{dir}")) != std::string::npos;)
        command.replace(at, 5, "'" + folder.string() + "'");
      const CliRun run = navaid_cli(command);
      if (run.status != 0) throw std::runtime_error("navaid " + command + " failed:\n" + run.output);
    }
  });
}

}  // namespace navaid::testing
