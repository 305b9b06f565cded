#include "fuzz_support.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <typeinfo>

#include "navaid/core/errors.hpp"

namespace navaid::fuzz {
namespace fs = std::filesystem;

const fs::path& scratch_dir() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("navaid-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

const fs::path& fresh_scratch_dir() {
  const fs::path& dir = scratch_dir();
  for (const auto& entry : fs::directory_iterator(dir)) fs::remove_all(entry.path());
  return dir;
}

void write_file(const fs::path& path, std::string_view bytes) {
  std::error_code ec;  // a name that collides with a folder is skipped, not a finding
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  if (ec) return;
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

namespace {

bool safe_relative_name(std::string_view name) {
  if (name.empty() || name.size() > 128 || name.front() == '/') return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '.' || c == '/' || c == '-';
    if (!ok) return false;
  }
  return name.find("..") == std::string_view::npos && name.find("//") == std::string_view::npos &&
         name.back() != '/';
}

}  // namespace

std::size_t unpack_folder(std::string_view input, const fs::path& folder) {
  constexpr std::string_view kMark = "=== ";
  std::size_t written = 0;
  std::size_t pos = input.rfind(kMark, 0) == 0 ? 0 : input.find(std::string("\n") + std::string(kMark));
  if (pos != 0 && pos != std::string_view::npos) ++pos;  // skip the newline before the first mark
  while (pos != std::string_view::npos) {
    const std::size_t name_begin = pos + kMark.size();
    const std::size_t name_end = input.find('\n', name_begin);
    if (name_end == std::string_view::npos) break;
    const std::string_view name = input.substr(name_begin, name_end - name_begin);
    std::size_t next = input.find(std::string("\n") + std::string(kMark), name_end);
    const std::size_t content_end = next == std::string_view::npos ? input.size() : next + 1;
    if (safe_relative_name(name)) {
      const fs::path target = folder / std::string(name);
      write_file(target, input.substr(name_end + 1, content_end - (name_end + 1)));
      std::error_code ec;
      if (fs::is_regular_file(target, ec)) ++written;
    }
    pos = next == std::string_view::npos ? next : next + 1;
  }
  return written;
}

void expect_clear_errors(const char* what, const std::function<void()>& read) {
  try {
    read();
  } catch (const navaid::Error&) {
    // The contract: a typed error that names the file.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: unclear error escaped: %s: %s\n", what, typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "%s: a non-std exception escaped\n", what);
    std::abort();
  }
}

}  // namespace navaid::fuzz
