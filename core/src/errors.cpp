#include "navaid/core/errors.hpp"

namespace navaid {
namespace {
std::string where(const std::string& file, std::size_t line) {
  return line > 0 ? file + ":" + std::to_string(line) : file;
}
}  // namespace

IoError::IoError(std::string file, std::size_t line, const std::string& message)
    : Error(where(file, line) + ": " + message), file_(std::move(file)), line_(line), detail_(message) {}

ConfigError::ConfigError(std::string file, std::string key, const std::string& message)
    : Error(file + ": key '" + key + "': " + message), file_(std::move(file)), key_(std::move(key)) {}

}  // namespace navaid
