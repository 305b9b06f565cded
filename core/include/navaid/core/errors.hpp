#pragma once
// Typed errors raised at the boundaries (io, config, CLI). Every message names where the problem is.
#include <stdexcept>
#include <string>

namespace navaid {

/// Base of every error navaid raises on bad input.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file that cannot be opened, read or understood. `line` is 0 when not line-specific.
class IoError : public Error {
 public:
  IoError(std::string file, std::size_t line, const std::string& message);
  IoError(std::string file, const std::string& message) : IoError(std::move(file), 0, message) {}
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }
  /// The message without the "file:line: " prefix.
  const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string detail_;
};

/// A configuration or calibration value that is missing, malformed or out of range.
class ConfigError : public Error {
 public:
  ConfigError(std::string file, std::string key, const std::string& message);
  const std::string& file() const { return file_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  std::string key_;
};

/// A command-line usage problem (unknown option value, missing argument).
class UsageError : public Error {
 public:
  using Error::Error;
};

}  // namespace navaid
