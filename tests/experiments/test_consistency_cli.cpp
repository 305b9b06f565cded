// End-to-end tests of `navaid consistency`: run folders as `navaid run` writes them (estimates.csv,
// summary.json naming a recording with ground truth), given by a shell glob that also matches log
// files; the CSV agrees with the library, JSON / Markdown / figure are written, bad runs fail clearly.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "navaid/core/random_draws.hpp"
#include "navaid/evaluation/monte_carlo_nees.hpp"
#include "navaid/experiments/run_folder.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "synthetic_trajectory.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::CliRun;
using navaid::testing::navaid_cli;
using navaid::testing::ScratchDir;

namespace {

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

constexpr const char* kHeader =
    "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz,mode,"
    "cov_pxx,cov_pxy,cov_pxz,cov_pyy,cov_pyz,cov_pzz,cov_rxx,cov_rxy,cov_rxz,cov_ryy,cov_ryz,cov_rzz,"
    "enu_yaw,enu_x,enu_y,enu_z\n";

// A run folder whose estimates are the ground truth plus seeded errors of the stated standard
// deviations (exact at the first estimate), skipping the epochs in `missing`.
void write_run(const fs::path& folder, const fs::path& recording, const std::vector<navaid::io::StampedPose>& gt,
               unsigned seed, std::size_t missing = static_cast<std::size_t>(-1)) {
  fs::create_directories(folder);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  const double sp = 0.05, sr = 0.01;
  std::ostringstream csv;
  csv.precision(17);
  csv << kHeader;
  for (std::size_t k = 0; k < gt.size(); ++k) {
    const double f = k == 0 ? 0.0 : 1.0;
    // Drawn last argument first, each vector last coefficient first: the order of record
    // (random_draws.hpp).
    const navaid::Vec3 dp = navaid::draw_vector<3>([&] { return n01(rng); }) * (f * sp);
    const navaid::Vec3 rpy = navaid::draw_vector<3>([&] { return n01(rng); }) * (f * sr);
    const navaid::SE3 e(navaid::quat_from_rpy(rpy.x(), rpy.y(), rpy.z()), dp);
    if (k == missing) continue;
    const navaid::SE3 T(gt[k].T_W_B.q * e.q, gt[k].T_W_B.t + e.t);
    csv << gt[k].t << ',' << T.t.x() << ',' << T.t.y() << ',' << T.t.z() << ',' << T.q.w() << ',' << T.q.x() << ','
        << T.q.y() << ',' << T.q.z() << ",0,0,0,0,0,0,0,0,0,rgbd-vio," << sp * sp << ",0,0," << sp * sp << ",0,"
        << sp * sp << ',' << sr * sr << ",0,0," << sr * sr << ",0," << sr * sr << ",,,,\n";
  }
  navaid::testing::write_text(folder / "estimates.csv", csv.str());
  navaid::testing::write_text(folder / "summary.json", nlohmann::json{{"recording", recording.string()}}.dump());
  navaid::testing::write_text(folder.string() + ".log", "log of the run, not a run folder\n");
}

struct Study {
  ScratchDir dir{"consistency-cli"};
  std::vector<navaid::io::StampedPose> gt = navaid::testing::synthetic_trajectory(60);
  Study() {
    navaid::io::Recording rec;
    rec.format = "navaid";
    for (const auto& p : gt) rec.groundtruth.push_back({p.t, p.T_W_B, std::nullopt, std::nullopt, std::nullopt});
    navaid::io::write_navaid_recording(rec, dir / "rec");
    for (unsigned s = 1; s <= 4; ++s) write_run(dir / "runs" / ("seed" + std::to_string(s)), dir / "rec", gt, s);
  }
};

}  // namespace

TEST(ConsistencyCli, GlobOfRunFoldersGivesTheLibrarysAnees) {
  Study study;
  const fs::path out = study.dir / "out";
  // Unquoted glob: the shell expands it, the seed<k>.log files included.
  const CliRun run = navaid_cli("consistency --runs " + (study.dir / "runs").string() + "/seed* --out " + quote(out));
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("position: ANEES"), std::string::npos) << run.output;
  for (const char* f : {"consistency.csv", "consistency.json", "consistency.md", "consistency.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;

  std::vector<navaid::evaluation::NeesSeries> series;
  for (unsigned s = 1; s <= 4; ++s) {
    const fs::path folder = study.dir / "runs" / ("seed" + std::to_string(s));
    series.push_back(navaid::evaluation::first_state_nees_series(
        folder.string(), navaid::experiments::read_estimates_csv(folder / "estimates.csv"), study.gt));
  }
  const auto m = navaid::evaluation::monte_carlo_nees(series);
  std::ifstream csv(out / "consistency.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "epoch,t,anees_pos,anees_rot,runs");
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    std::string epoch, t, pos, rot, runs;
    std::getline(ss, epoch, ',');
    std::getline(ss, t, ',');
    std::getline(ss, pos, ',');
    std::getline(ss, rot, ',');
    std::getline(ss, runs, ',');
    ASSERT_LT(rows, m.t.size());
    EXPECT_EQ(std::stoul(epoch), rows);
    EXPECT_EQ(t, navaid::format_seconds(m.t[rows]));
    EXPECT_DOUBLE_EQ(std::stod(pos), m.position.anees[rows]);
    EXPECT_DOUBLE_EQ(std::stod(rot), m.orientation.anees[rows]);
    EXPECT_EQ(runs, "4");
    ++rows;
  }
  EXPECT_EQ(rows, study.gt.size());

  const auto j = nlohmann::json::parse(navaid::testing::read_text(out / "consistency.json"));
  EXPECT_EQ(j["runs"].size(), 4u);
  EXPECT_DOUBLE_EQ(j["position"]["time_average"].get<double>(), m.position.time_average);
  EXPECT_DOUBLE_EQ(j["orientation"]["time_average_bounds"]["conservative"]["upper"].get<double>(),
                   m.orientation.conservative_bounds.upper);
  EXPECT_EQ(j["position"]["consistent"].get<bool>(), m.position.consistent());
}

TEST(ConsistencyCli, RunsOfDifferentRecordingsOrMissingDataFailClearly) {
  Study study;
  write_run(study.dir / "other" / "gap", study.dir / "rec", study.gt, 9, 30);
  CliRun run = navaid_cli("consistency --no-plot --runs " + quote(study.dir / "runs" / "seed1") + " " +
                          quote(study.dir / "other" / "gap") + " --out " + quote(study.dir / "out"));
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("do not share their epochs"), std::string::npos) << run.output;

  write_run(study.dir / "other" / "lost", study.dir / "no-such-recording", study.gt, 9);
  run = navaid_cli("consistency --no-plot --runs " + quote(study.dir / "runs" / "seed1") + " " +
                   quote(study.dir / "other" / "lost") + " --out " + quote(study.dir / "out"));
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("no-such-recording"), std::string::npos) << run.output;

  run = navaid_cli("consistency --runs " + quote(study.dir / "runs" / "seed1") + " --out " + quote(study.dir / "out"));
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("at least 2 run folders"), std::string::npos) << run.output;
}
