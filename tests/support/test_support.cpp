#include "test_support.hpp"

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
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

}  // namespace navaid::testing
