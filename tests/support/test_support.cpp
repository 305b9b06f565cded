#include "test_support.hpp"

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

}  // namespace navaid::testing
