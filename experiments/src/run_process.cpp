#include "navaid/experiments/run_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>
#include <sys/wait.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "navaid/core/errors.hpp"

extern char** environ;

namespace navaid::experiments {

int run_process(const std::vector<std::string>& argv, const std::string& log_file) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!log_file.empty()) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  }
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw Error("cannot start " + argv[0] + ": " + std::strerror(rc));
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) throw Error("waiting for " + argv[0] + " failed");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string self_executable() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error("cannot find the navaid executable (/proc/self/exe): " + ec.message());
  return p.string();
}

std::string figures_dir() {
  if (const char* env = std::getenv("NAVAID_FIGURES_DIR")) return env;
  if (std::filesystem::is_directory(NAVAID_SOURCE_FIGURES_DIR)) return NAVAID_SOURCE_FIGURES_DIR;
  return NAVAID_INSTALLED_FIGURES_DIR;
}

std::string workflow_dir() {
  if (const char* env = std::getenv("NAVAID_WORKFLOW_DIR")) return env;
  return (std::filesystem::path(figures_dir()).parent_path() / "workflow").string();
}

}  // namespace navaid::experiments
