#pragma once
// Opens a page in headless Chromium (Debian's chromium, installed by scripts/install-deps.sh) and
// reads what the page's own load check wrote on <body> (experiments/figures/run_report.py):
// data-status, data-figures, data-errors.
#include <filesystem>
#include <string>

namespace navaid::testing {

struct PageCheck {
  bool browser = false;  ///< false: no /usr/bin/chromium on this machine
  std::string status, figures, errors;
  std::string dom;  ///< the DOM after the page's scripts ran
};

PageCheck check_page_in_chromium(const std::filesystem::path& html);

/// True when the browser is there; otherwise records a skip on a developer machine and a failure
/// in CI (CI=true), where install-deps.sh installs it. Use as `if (!browser_available(c)) return;`.
bool browser_available(const PageCheck& check);

}  // namespace navaid::testing
