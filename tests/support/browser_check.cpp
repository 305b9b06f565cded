#include "browser_check.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <regex>

namespace navaid::testing {

namespace {

std::string attribute(const std::string& tag, const std::string& name) {
  std::smatch m;
  const std::regex re(name + "=\"([^\"]*)\"");
  return std::regex_search(tag, m, re) ? m[1].str() : std::string();
}

}  // namespace

PageCheck check_page_in_chromium(const std::filesystem::path& html) {
  PageCheck check;
  if (!std::filesystem::exists("/usr/bin/chromium")) return check;
  check.browser = true;
  // --virtual-time-budget lets the page's load handler run before the DOM is dumped; no sandbox,
  // GPU or D-Bus in a CI container.
  const std::string command = "/usr/bin/chromium --headless --no-sandbox --disable-gpu --virtual-time-budget=10000 "
                              "--dump-dom 'file://" + std::filesystem::absolute(html).string() + "' 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return check;
  char buffer[65536];
  std::size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) check.dom.append(buffer, n);
  pclose(pipe);
  const auto body = check.dom.find("<body");
  if (body == std::string::npos) return check;
  const std::string tag = check.dom.substr(body, check.dom.find('>', body) - body);
  check.status = attribute(tag, "data-status");
  check.figures = attribute(tag, "data-figures");
  check.errors = attribute(tag, "data-errors");
  return check;
}

bool browser_available(const PageCheck& check) {
  if (check.browser) return true;
  const char* ci = std::getenv("CI");
  if (ci && std::string(ci) == "true") {
    ADD_FAILURE() << "/usr/bin/chromium is missing in CI (scripts/install-deps.sh installs it)";
  } else {
    GTEST_MESSAGE_("/usr/bin/chromium is not installed", ::testing::TestPartResult::kSkip);
  }
  return false;
}

}  // namespace navaid::testing
