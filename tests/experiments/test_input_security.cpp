// Security of inputs (docs/robustness.md): user-supplied strings (paths, names) never reach a
// shell. navaid starts child programs (figure scripts, its own subcommands) only through
// run_process(), argv without a shell; recordings' own paths are confined to their folder (the
// corrupt-recording matrix tests that) and the device link rejects oversized frames
// (DeviceProtocol.BadLengthsAndUnknownTypes).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "navaid/experiments/run_process.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

// A string that does harm when a shell reads it: command substitution, a second command.
std::string hostile(const fs::path& dir) {
  return "x $(touch " + (dir / "pwned1").string() + "); touch " + (dir / "pwned2").string() + " `touch " +
         (dir / "pwned3").string() + "`";
}

void expect_no_shell_ran(const fs::path& dir) {
  for (const char* f : {"pwned1", "pwned2", "pwned3"}) EXPECT_FALSE(fs::exists(dir / f)) << f << ": a shell ran";
}

TEST(InputSecurity, ChildProgramsGetTheirArgumentsLiterally) {
  const ScratchDir dir("security-run-process");
  const std::string arg = hostile(dir.path());
  const fs::path log = dir / "echo.log";
  ASSERT_EQ(navaid::experiments::run_process({"/bin/echo", arg}, log.string()), 0);
  EXPECT_EQ(read_text(log), arg + "\n");
  expect_no_shell_ran(dir.path());
}

TEST(InputSecurity, AHostileOutputFolderIsJustAFolderName) {
  // The run's figure script (python) gets the folder as an argument: the plot lands in the
  // literal folder and nothing else happens.
  const ScratchDir dir("security-cli");
  const fs::path rec = dir / "rec";
  ASSERT_EQ(navaid_cli("simulate --scenario route1 --set simulation.mode=features --set duration=3 --threads 1 --out '" +
                       rec.string() + "'")
                .status,
            0);
  const fs::path out = dir / hostile(dir.path());
  // The test's own shell needs the single quotes; navaid gets the string as one argument.
  const auto run = navaid_cli("run --recording '" + rec.string() + "' --out '" + out.string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(fs::exists(out / "topview.png")) << run.output;
  expect_no_shell_ran(dir.path());
}

TEST(InputSecurity, NoSourceStartsAShell) {
  // Every child program starts in run_process() (posix_spawn, argv). A std::system, popen or
  // /bin/sh anywhere else in navaid's own code would take strings through a shell. Python (the
  // figures, the Snakemake workflow and its Slurm status script) may start programs only as
  // subprocess.run([argv list]), never through a shell.
  const fs::path root = NAVAID_SOURCE_DIR;
  // (A bare `system(` is a member of the cue generator, so libc's is caught as std:: or ::.)
  const std::regex native(R"((std::system|(^|[^:\w])::system|\bpopen|\bexec[lv]p?e?|\bposix_spawnp?)\s*\(|/bin/sh)");
  const std::regex python(
      R"(os\.system|os\.popen|\bshell\s*=\s*True|/bin/sh|subprocess\.(call|check_call|check_output|Popen|getoutput|getstatusoutput)\b|subprocess\.run\s*\(\s*[^\[\s])");
  int files = 0;
  for (const char* room : {"apps", "core", "io", "simulation", "estimation", "mapping", "planning", "interaction",
                           "evaluation", "runtime", "experiments", "examples"}) {
    if (!fs::exists(root / room)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root / room)) {
      const std::string ext = e.path().extension().string();
      const bool is_python = ext == ".py" || e.path().filename() == "Snakefile";
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp" && ext != ".c" && ext != ".h" && !is_python))
        continue;
      ++files;
      if (e.path().filename() == "run_process.cpp") continue;
      std::ifstream in(e.path());
      std::string line;
      for (int n = 1; std::getline(in, line); ++n) {
        EXPECT_FALSE(std::regex_search(line, is_python ? python : native)) << e.path().string() << ":" << n << ": " << line;
      }
    }
  }
  EXPECT_GT(files, 300);
  // The rule itself can fail.
  EXPECT_TRUE(std::regex_search(std::string("subprocess.run('ls ' + x, shell=True)"), python));
  EXPECT_TRUE(std::regex_search(std::string("subprocess.check_output(['ls'])"), python));
  EXPECT_FALSE(std::regex_search(std::string("subprocess.run([NAVAID, 'ablate-job', plan], check=True)"), python));
}

}  // namespace
