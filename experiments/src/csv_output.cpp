#include "csv_output.hpp"

#include "navaid/core/errors.hpp"

namespace navaid::experiments {

std::ofstream open_csv(const std::filesystem::path& file, const char* header) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write");
  out << header << "\n";
  return out;
}

}  // namespace navaid::experiments
