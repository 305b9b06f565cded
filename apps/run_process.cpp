#include "run_process.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "navaid/core/errors.hpp"

extern char** environ;

namespace navaid::cli {

int run_process(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], nullptr, nullptr, args.data(), environ);
  if (rc != 0) throw Error("cannot start " + argv[0] + ": " + std::strerror(rc));
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) throw Error("waiting for " + argv[0] + " failed");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string figures_dir() {
  if (const char* env = std::getenv("NAVAID_FIGURES_DIR")) return env;
  if (std::filesystem::is_directory(NAVAID_SOURCE_FIGURES_DIR)) return NAVAID_SOURCE_FIGURES_DIR;
  return NAVAID_INSTALLED_FIGURES_DIR;
}

}  // namespace navaid::cli
