#pragma once
// Shared pieces of the libFuzzer harnesses (docs/robustness.md, "Fuzzing").
//
// Every reader of outside input must either return or throw navaid::Error (IoError, ConfigError)
// naming the file; anything else that escapes (std::out_of_range from a stray std::stoi, a
// YAML::Exception, std::bad_alloc from a length read off the file) is a finding and aborts, so
// libFuzzer keeps the input as a crash.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace navaid::fuzz {

/// A folder of this process's own under the system temp dir, emptied for every input.
const std::filesystem::path& scratch_dir();
/// Removes everything in scratch_dir() and returns it.
const std::filesystem::path& fresh_scratch_dir();

/// Writes `bytes` to `path` (binary).
void write_file(const std::filesystem::path& path, std::string_view bytes);

/// A folder's files in one input, so that libFuzzer mutates names and contents together:
/// a line "=== <relative path>" starts a file, whose bytes run to the next such line. Names with
/// "..", a leading '/', or characters outside [A-Za-z0-9_./-] are dropped (the harness must not
/// write outside its scratch folder). Returns how many files were written under `folder`.
std::size_t unpack_folder(std::string_view input, const std::filesystem::path& folder);

/// Runs `read`; returns normally when it returns or throws navaid::Error, aborts with the
/// exception's type and message for anything else.
void expect_clear_errors(const char* what, const std::function<void()>& read);

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace navaid::fuzz
