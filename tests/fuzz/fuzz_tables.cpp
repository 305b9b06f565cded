// The small CSV tables that navaid reads back (targets, obstacle scans, guidance timelines) and the
// study files (ablation matrices). The first byte picks the reader, the rest is the file.
#include "fuzz_support.hpp"
#include "navaid/experiments/ablation.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/io/targets_csv.hpp"
#include "navaid/planning/obstacle_scan_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  if (size == 0) return 0;
  const auto file = fuzz::fresh_scratch_dir() / "table";
  fuzz::write_file(file, fuzz::as_text(data + 1, size - 1));
  switch (data[0] % 4) {
    case 0: fuzz::expect_clear_errors("read_targets_csv", [&] { (void)io::read_targets_csv(file); }); break;
    case 1:
      fuzz::expect_clear_errors("read_obstacle_scan_csv", [&] { (void)planning::read_obstacle_scan_csv(file); });
      break;
    case 2:
      fuzz::expect_clear_errors("read_guidance_timeline_csv",
                                [&] { (void)interaction::read_guidance_timeline_csv(file); });
      break;
    default:
      fuzz::expect_clear_errors("read_ablation_matrix", [&] { (void)experiments::read_ablation_matrix(file); });
  }
  return 0;
}
