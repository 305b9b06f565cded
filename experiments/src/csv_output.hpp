#pragma once
// A CSV file of a run or trial folder, opened for writing with its header line.
#include <filesystem>
#include <fstream>

namespace navaid::experiments {

/// `file` truncated, with `header` as its first line. Throws IoError when it cannot be written.
std::ofstream open_csv(const std::filesystem::path& file, const char* header);

}  // namespace navaid::experiments
