#pragma once
// A one-line progress bar on stderr for long work; silent when stderr is not a terminal, so logs
// and CI output stay clean.
#include <chrono>
#include <cstddef>
#include <string>

namespace navaid::experiments {

class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  void update(std::size_t done);
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace navaid::experiments
