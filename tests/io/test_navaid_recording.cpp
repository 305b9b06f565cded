// The navaid recording format: round trip (values and bytes) and one corrupt copy per check.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/nmea.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "fixtures/fixture_util.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using navaid::testing::expect_throw;
using navaid::testing::datasets::replace_text;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

constexpr Timestamp kT0 = 1'403'715'273'262'142'976;  // epoch-sized, as real data

Quat rotation(double ax, double ay, double az, double angle) {
  return Quat(Eigen::AngleAxisd(angle, Vec3(ax, ay, az).normalized()));
}

// Source images written with OpenCV directly, as another tool would.
std::string write_source_png(const fs::path& file, const cv::Mat& image) {
  fs::create_directories(file.parent_path());
  EXPECT_TRUE(cv::imwrite(file.string(), image));
  return file.string();
}

cv::Mat random_mat(int type, int seed, int max_value) {
  cv::Mat m(6, 8, type);
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, max_value);
  return m;
}

Recording make_recording(const fs::path& src) {
  std::mt19937 rng(42);
  std::normal_distribution<double> normal;
  const auto vec = [&](double scale) -> Vec3 { return draw_vector<3>([&] { return normal(rng); }) * scale; };
  Recording r;

  CameraCalibration cam0;
  cam0.name = "cam0";
  cam0.width = 8;
  cam0.height = 6;
  cam0.fx = 5.123456789012345;
  cam0.fy = 5.2;
  cam0.cx = 3.9;
  cam0.cy = 2.7000000000000001;
  cam0.distortion = DistortionModel::kRadialTangential;
  cam0.distortion_coeffs = {0.1, -0.02, 1e-4, -2.5e-5, 1e-7};
  cam0.T_B_C = SE3(rotation(0.3, -1, 0.2, 1.9), Vec3(0.05, -0.01, 0.002));
  cam0.time_offset_s = -0.0123;
  cam0.rate_hz = 30;
  cam0.depth_min_m = 0.3;
  cam0.depth_max_m = 8;
  cam0.depth_baseline_m = 0.05;
  cam0.depth_disparity_sigma_px = 0.1;
  CameraCalibration cam1;
  cam1.name = "cam1";
  cam1.width = 8;
  cam1.height = 6;
  cam1.fx = cam1.fy = 4;
  cam1.cx = cam1.cy = 3;
  cam1.distortion = DistortionModel::kEquidistant;
  cam1.distortion_coeffs = {0.01, 0.002, -3e-4, 4e-5};
  cam1.T_B_C = SE3(rotation(1, 1, 1, 0.7), Vec3(-0.05, 0, 0));
  cam1.rate_hz = 30;
  r.calibration.cameras = {cam0, cam1};
  ImuCalibration imu;
  imu.rate_hz = 200;
  imu.gyro_noise_density = 1.6968e-04;
  imu.gyro_random_walk = 1.9393e-05;
  imu.accel_noise_density = 2.0000e-3;
  imu.accel_random_walk = 3.0000e-3;
  imu.T_B_I = SE3(rotation(0, 0, 1, 0.01), Vec3(0.001, 0, 0));
  r.calibration.imu = imu;
  r.calibration.gps_lever_arm_B = Vec3(0.1, 0.2, 1.3);
  r.calibration.gps_rate_hz = 5;
  r.calibration.mag_rate_hz = 50;
  r.origin = GeodeticOrigin{46.519653, 6.632273, 372.1};

  for (int i = 0; i < 40; ++i) {
    ImuSample s;
    s.t = kT0 + i * 5'000'000;
    s.gyro = vec(0.1);
    s.accel = vec(1) + Vec3(0, 0, 9.81);
    if (i == 3) {
      s.has_gyro = false;
      s.gyro = Vec3::Zero();
    }
    r.imu.push_back(s);
  }
  for (int i = 0; i < 5; ++i) {
    GpsFix f;
    f.t = kT0 + i * 200'000'000 + 7;
    f.latitude_deg = 46.519653 + 1e-5 * normal(rng);
    f.longitude_deg = -6.632273 + 1e-5 * normal(rng);
    f.altitude_m = i == 2 ? std::nan("") : 372.1 + normal(rng);
    f.geoid_separation_m = 48.3;
    f.mode = i == 4 ? GpsFixMode::k2D : GpsFixMode::k3D;
    f.quality = i == 1 ? 4 : 1;
    f.satellites = 7 + i;
    f.hdop = i == 3 ? std::nan("") : 0.9 + 0.1 * i;
    const Mat3 a = Mat3::Random();
    const Mat3 c = a * a.transpose() + Mat3::Identity();
    f.covariance_enu = 0.5 * (c + c.transpose());  // exactly symmetric: the file stores one triangle
    r.gps.push_back(f);
  }
  for (int i = 0; i < 10; ++i) r.mag.push_back(MagSample{kT0 + i * 20'000'000 + 3, vec(2e-5)});
  for (int i = 0; i < 10; ++i) {
    GroundTruthState g;
    g.t = kT0 + i * 10'000'000;
    const Vec3 t_W_B = vec(3);  // drawn last argument first: the order of record (random_draws.hpp)
    const Eigen::Vector4d axis_angle = draw_vector<4>([&] { return normal(rng); });
    g.T_W_B = SE3(rotation(axis_angle[0], axis_angle[1], axis_angle[2], axis_angle[3]), t_W_B);
    if (i % 3 != 0) g.v_W = vec(1);
    if (i % 2 == 0) g.b_g = vec(1e-3);
    if (i % 2 == 0) g.b_a = vec(1e-2);
    r.groundtruth.push_back(g);
  }

  for (int k = 0; k < 3; ++k) {
    const Timestamp t = kT0 + k * 33'333'333;
    RgbdFrame f;
    f.t = t;
    f.index = static_cast<std::uint64_t>(k);
    f.camera = "cam0";
    f.intensity_path = write_source_png(src / ("c0_rgb" + std::to_string(k) + ".png"), random_mat(CV_8UC3, k, 256));
    f.labels_path = write_source_png(src / ("c0_lab" + std::to_string(k) + ".png"), random_mat(CV_8UC1, 10 + k, 20));
    if (k == 0) {
      f.confidence_path = write_source_png(src / "c0_conf0.png", random_mat(CV_8UC1, 40, 256));
    } else if (k == 2) {  // probabilities only in memory, as the simulator makes them
      f.label_confidence = ImageF32(8, 6, 1, 0.5f);
      f.label_confidence->at(1, 2) = 0.0f;
      f.label_confidence->at(3, 4) = 1.0f;
      f.label_confidence->at(5, 0) = 0.9137f;  // 232.99 / 255: rounds to 233
    }
    if (k == 0) {
      cv::Mat d = random_mat(CV_16UC1, 20, 8000);
      d.at<std::uint16_t>(0, 0) = 0;
      f.depth_path = write_source_png(src / "c0_depth0.png", d);
    } else if (k == 1) {  // TUM units: 5000 per metre
      f.depth_path = write_source_png(src / "c0_depth1.png", random_mat(CV_16UC1, 21, 40000));
      f.depth_png_scale_m = 1.0 / 5000;
    } else {  // pixels only in memory, as the simulator makes them
      f.depth = ImageF32(8, 6, 1, 1.234f);
      f.depth.at(2, 3) = 0;
    }
    r.frames.push_back(f);

    RgbdFrame g;
    g.t = t;
    g.index = static_cast<std::uint64_t>(100 + k);
    g.camera = "cam1";
    if (k == 1) {
      g.intensity = ImageU8(8, 6, 1, 77);
    } else {
      g.intensity_path = write_source_png(src / ("c1_" + std::to_string(k) + ".png"), random_mat(CV_8UC1, 30 + k, 256));
    }
    r.frames.push_back(g);
  }

  // Feature observations: cam0 every 33 ms with some depths, cam1 at the same instants (shared
  // time stamps), one cam1 frame without features; ids epoch-sized to exercise 64 bits.
  std::uniform_real_distribution<double> pixel(0, 640);
  for (int k = 0; k < 4; ++k) {
    for (const char* camera : {"cam0", "cam1"}) {
      FeatureFrame ff;
      ff.t = kT0 + k * 33'333'333;
      ff.camera = camera;
      const bool empty = std::string(camera) == "cam1" && k == 2;
      for (std::uint64_t id = 5 + k; !empty && id < 40; id += 3) {
        FeatureObservation o;
        o.track_id = id * 1'000'000'007ull;
        const double v = pixel(rng) * 0.75;  // v before u: the order of record (random_draws.hpp)
        o.uv = Eigen::Vector2d(pixel(rng), v);
        if (id % 2 == 0) o.depth_m = 0.3 + 7 * std::abs(normal(rng));
        ff.features.push_back(o);
      }
      r.features.push_back(ff);
    }
  }
  for (std::uint64_t id = 5; id < 40; ++id) r.landmarks.push_back(Landmark{id * 1'000'000'007ull, vec(10)});
  return r;
}

std::vector<std::string> files_under(const fs::path& root) {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), root).generic_string());
  std::sort(files.begin(), files.end());
  return files;
}

bool has_confidence(const RgbdFrame& f) { return !f.confidence_path.empty() || f.label_confidence.has_value(); }

bool same_number(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

void expect_same_calibration(const RigCalibration& a, const RigCalibration& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (std::size_t i = 0; i < a.cameras.size(); ++i) {
    const auto& x = a.cameras[i];
    const auto& y = b.cameras[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.width, y.width);
    EXPECT_EQ(x.height, y.height);
    EXPECT_EQ(x.fx, y.fx);
    EXPECT_EQ(x.fy, y.fy);
    EXPECT_EQ(x.cx, y.cx);
    EXPECT_EQ(x.cy, y.cy);
    EXPECT_EQ(x.distortion, y.distortion);
    EXPECT_EQ(x.distortion_coeffs, y.distortion_coeffs);
    EXPECT_EQ(x.T_B_C.q.coeffs(), y.T_B_C.q.coeffs());
    EXPECT_EQ(x.T_B_C.t, y.T_B_C.t);
    EXPECT_EQ(x.time_offset_s, y.time_offset_s);
    EXPECT_EQ(x.rate_hz, y.rate_hz);
    EXPECT_EQ(x.depth_min_m, y.depth_min_m);
    EXPECT_EQ(x.depth_max_m, y.depth_max_m);
    EXPECT_EQ(x.depth_baseline_m, y.depth_baseline_m);
    EXPECT_EQ(x.depth_disparity_sigma_px, y.depth_disparity_sigma_px);
  }
  ASSERT_EQ(a.imu.has_value(), b.imu.has_value());
  EXPECT_EQ(a.imu->rate_hz, b.imu->rate_hz);
  EXPECT_EQ(a.imu->gyro_noise_density, b.imu->gyro_noise_density);
  EXPECT_EQ(a.imu->gyro_random_walk, b.imu->gyro_random_walk);
  EXPECT_EQ(a.imu->accel_noise_density, b.imu->accel_noise_density);
  EXPECT_EQ(a.imu->accel_random_walk, b.imu->accel_random_walk);
  EXPECT_EQ(a.imu->T_B_I.q.coeffs(), b.imu->T_B_I.q.coeffs());
  EXPECT_EQ(a.imu->T_B_I.t, b.imu->T_B_I.t);
  EXPECT_EQ(a.gps_lever_arm_B, b.gps_lever_arm_B);
  EXPECT_EQ(a.gps_rate_hz, b.gps_rate_hz);
  EXPECT_EQ(a.mag_rate_hz, b.mag_rate_hz);
}

void expect_same_samples(const Recording& a, const Recording& b) {
  ASSERT_EQ(a.imu.size(), b.imu.size());
  for (std::size_t i = 0; i < a.imu.size(); ++i) {
    EXPECT_EQ(a.imu[i].t, b.imu[i].t);
    EXPECT_EQ(a.imu[i].has_gyro, b.imu[i].has_gyro);
    EXPECT_EQ(a.imu[i].gyro, b.imu[i].gyro);
    EXPECT_EQ(a.imu[i].accel, b.imu[i].accel);
  }
  ASSERT_EQ(a.gps.size(), b.gps.size());
  for (std::size_t i = 0; i < a.gps.size(); ++i) {
    const GpsFix& x = a.gps[i];
    const GpsFix& y = b.gps[i];
    EXPECT_EQ(x.t, y.t);
    EXPECT_EQ(x.latitude_deg, y.latitude_deg);
    EXPECT_EQ(x.longitude_deg, y.longitude_deg);
    EXPECT_TRUE(same_number(x.altitude_m, y.altitude_m));
    EXPECT_EQ(x.geoid_separation_m, y.geoid_separation_m);
    EXPECT_EQ(x.mode, y.mode);
    EXPECT_EQ(x.quality, y.quality);
    EXPECT_EQ(x.satellites, y.satellites);
    EXPECT_TRUE(same_number(x.hdop, y.hdop));
    EXPECT_EQ(x.covariance_enu, y.covariance_enu);
  }
  ASSERT_EQ(a.mag.size(), b.mag.size());
  for (std::size_t i = 0; i < a.mag.size(); ++i) {
    EXPECT_EQ(a.mag[i].t, b.mag[i].t);
    EXPECT_EQ(a.mag[i].field, b.mag[i].field);
  }
  ASSERT_EQ(a.groundtruth.size(), b.groundtruth.size());
  for (std::size_t i = 0; i < a.groundtruth.size(); ++i) {
    const auto& x = a.groundtruth[i];
    const auto& y = b.groundtruth[i];
    EXPECT_EQ(x.t, y.t);
    EXPECT_EQ(x.T_W_B.q.coeffs(), y.T_W_B.q.coeffs());
    EXPECT_EQ(x.T_W_B.t, y.T_W_B.t);
    EXPECT_EQ(x.v_W, y.v_W);
    EXPECT_EQ(x.b_g, y.b_g);
    EXPECT_EQ(x.b_a, y.b_a);
  }
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    EXPECT_EQ(a.frames[i].t, b.frames[i].t);
    EXPECT_EQ(a.frames[i].camera, b.frames[i].camera);
    EXPECT_EQ(a.frames[i].index, b.frames[i].index);
    EXPECT_EQ(has_confidence(a.frames[i]), has_confidence(b.frames[i])) << "frame " << i;
  }
  ASSERT_EQ(a.features.size(), b.features.size());
  for (std::size_t i = 0; i < a.features.size(); ++i) {
    const FeatureFrame& x = a.features[i];
    const FeatureFrame& y = b.features[i];
    EXPECT_EQ(x.t, y.t);
    EXPECT_EQ(x.camera, y.camera);
    ASSERT_EQ(x.features.size(), y.features.size()) << "feature frame " << i;
    for (std::size_t k = 0; k < x.features.size(); ++k) {
      EXPECT_EQ(x.features[k].track_id, y.features[k].track_id);
      EXPECT_EQ(x.features[k].uv, y.features[k].uv);
      EXPECT_EQ(x.features[k].depth_m, y.features[k].depth_m);
    }
  }
  ASSERT_EQ(a.landmarks.size(), b.landmarks.size());
  for (std::size_t i = 0; i < a.landmarks.size(); ++i) {
    EXPECT_EQ(a.landmarks[i].id, b.landmarks[i].id);
    EXPECT_EQ(a.landmarks[i].p_W, b.landmarks[i].p_W);
  }
  ASSERT_EQ(a.origin.has_value(), b.origin.has_value());
  EXPECT_EQ(a.origin->latitude_deg, b.origin->latitude_deg);
  EXPECT_EQ(a.origin->longitude_deg, b.origin->longitude_deg);
  EXPECT_EQ(a.origin->height_m, b.origin->height_m);
}

// Replaces 1-based line `line` of `file` (or appends when line is past the end).
void set_line(const fs::path& file, std::size_t line, const std::string& text) {
  std::istringstream in(read_text(file));
  std::string out, current;
  std::size_t n = 0;
  bool done = false;
  while (std::getline(in, current)) {
    ++n;
    out += (n == line ? text : current) + "\n";
    done = done || n == line;
  }
  if (!done) out += text + "\n";
  write_text(file, out);
}

void remove_line_containing(const fs::path& file, const std::string& needle) {
  std::istringstream in(read_text(file));
  std::string out, current;
  bool removed = false;
  while (std::getline(in, current)) {
    if (!removed && current.find(needle) != std::string::npos) {
      removed = true;
      continue;
    }
    out += current + "\n";
  }
  ASSERT_TRUE(removed) << needle;
  write_text(file, out);
}

class NavaidRecordingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    original_ = make_recording(dir_ / "src");
    write_navaid_recording(original_, good());
  }
  fs::path good() const { return dir_ / "good"; }
  // A fresh copy of the good recording, to break.
  fs::path copy(const std::string& name) {
    const fs::path to = dir_ / name;
    fs::copy(good(), to, fs::copy_options::recursive);
    return to;
  }

  ScratchDir dir_{"navaid-recording"};
  Recording original_;
};

template <typename Fn>
IoError expect_io_error(Fn&& fn, const std::string& filename, std::size_t line, const std::string& needle) {
  const auto e = expect_throw<IoError>(
      std::forward<Fn>(fn), "IoError in " + filename + ":" + std::to_string(line) + " containing '" + needle + "'");
  if (!e) return IoError("", "");
  EXPECT_EQ(fs::path(e->file()).filename().string(), filename) << e->what();
  EXPECT_EQ(e->line(), line) << e->what();
  EXPECT_NE(std::string(e->what()).find(needle), std::string::npos) << e->what();
  return *e;
}

template <typename Fn>
void expect_config_error(Fn&& fn, const std::string& filename, const std::string& key, const std::string& needle) {
  const auto e = expect_throw<ConfigError>(std::forward<Fn>(fn), "ConfigError in " + filename + " key " + key);
  if (!e) return;
  EXPECT_EQ(fs::path(e->file()).filename().string(), filename) << e->what();
  EXPECT_EQ(e->key(), key) << e->what();
  EXPECT_NE(std::string(e->what()).find(needle), std::string::npos) << e->what();
}

TEST_F(NavaidRecordingTest, RoundTripKeepsEveryValue) {
  const Recording read = read_navaid_recording(good());
  EXPECT_EQ(read.format, "navaid");
  EXPECT_EQ(read.report.total(), 0u);
  expect_same_calibration(original_.calibration, read.calibration);
  expect_same_samples(original_, read);
  EXPECT_FALSE(read.imu[3].has_gyro);

  // Frame images: paths into the recording, millimetre depth, pixels as written.
  for (const auto& f : read.frames) {
    EXPECT_EQ(f.depth_png_scale_m, 0.001);
    if (!f.intensity_path.empty()) {
      EXPECT_EQ(fs::path(f.intensity_path).parent_path().filename(), "rgb");
    }
  }
  RgbdFrame f0 = read.frames[0];
  load_frame_images(f0);
  const cv::Mat bgr = cv::imread(original_.frames[0].intensity_path, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(f0.intensity.channels, 3);
  EXPECT_EQ(f0.intensity.at(5, 4, 0), bgr.at<cv::Vec3b>(4, 5)[2]);  // RGB in navaid, BGR in OpenCV
  const cv::Mat depth_mm = cv::imread(original_.frames[0].depth_path, cv::IMREAD_UNCHANGED);
  EXPECT_EQ(f0.depth.at(0, 0), 0.0f);
  EXPECT_EQ(f0.depth.at(3, 2), static_cast<float>(depth_mm.at<std::uint16_t>(2, 3) * 0.001));
  ASSERT_TRUE(f0.labels.has_value());
  EXPECT_EQ(f0.labels->at(7, 5), cv::imread(original_.frames[0].labels_path, cv::IMREAD_UNCHANGED).at<std::uint8_t>(5, 7));

  // Label confidence from an 8-bit source PNG: value / 255.
  ASSERT_TRUE(f0.label_confidence.has_value());
  const cv::Mat conf = cv::imread(original_.frames[0].confidence_path, cv::IMREAD_UNCHANGED);
  EXPECT_EQ(f0.label_confidence->at(6, 1), static_cast<float>(conf.at<std::uint8_t>(1, 6) / 255.0));

  RgbdFrame f1 = read.frames[2];  // TUM depth converted to millimetres
  load_frame_images(f1);
  const cv::Mat tum = cv::imread(original_.frames[2].depth_path, cv::IMREAD_UNCHANGED);
  const double tum_m = tum.at<std::uint16_t>(1, 1) / 5000.0;
  EXPECT_NEAR(f1.depth.at(1, 1), tum_m, 0.0005 + 1e-6);

  EXPECT_TRUE(read.frames[2].confidence_path.empty());
  EXPECT_FALSE(f1.label_confidence.has_value());

  RgbdFrame f2 = read.frames[4];  // depth and label confidence that existed only in memory
  load_frame_images(f2);
  EXPECT_NEAR(f2.depth.at(0, 0), 1.234f, 1e-6);
  EXPECT_EQ(f2.depth.at(2, 3), 0.0f);
  ASSERT_TRUE(f2.label_confidence.has_value());
  EXPECT_EQ(f2.label_confidence->at(0, 0), static_cast<float>(128 / 255.0));  // round(127.5)
  EXPECT_EQ(f2.label_confidence->at(1, 2), 0.0f);
  EXPECT_EQ(f2.label_confidence->at(3, 4), 1.0f);
  EXPECT_EQ(f2.label_confidence->at(5, 0), static_cast<float>(233 / 255.0));

  RgbdFrame g1 = read.frames[3];  // grey intensity that existed only in memory
  load_frame_images(g1);
  EXPECT_EQ(g1.intensity, ImageU8(8, 6, 1, 77));
  EXPECT_TRUE(read.frames[3].depth_path.empty());
  EXPECT_TRUE(read.frames[3].labels_path.empty());
}

TEST_F(NavaidRecordingTest, WriteReadWriteIsByteIdentical) {
  const Recording first = read_navaid_recording(good());
  const fs::path again = dir_ / "again";
  write_navaid_recording(first, again);
  const auto files = files_under(good());
  ASSERT_EQ(files, files_under(again));
  EXPECT_GE(files.size(), 9u + 6u + 3u + 3u + 2u);
  EXPECT_TRUE(fs::exists(good() / "confidence"));
  for (const auto& f : files) EXPECT_EQ(read_text(good() / f), read_text(again / f)) << f;

  // And the third generation reads back the same values as the second.
  const Recording second = read_navaid_recording(again);
  expect_same_calibration(first.calibration, second.calibration);
  expect_same_samples(first, second);
}

TEST_F(NavaidRecordingTest, FormatFilesLookAsDocumented) {
  const std::string imu = read_text(good() / "imu.csv");
  EXPECT_EQ(imu.substr(0, imu.find('\n')), "t_ns,gx,gy,gz,ax,ay,az");
  EXPECT_NE(imu.find("\n1403715273277142976,,,,"), std::string::npos);  // accelerometer only
  const std::string gps = read_text(good() / "gps.csv");
  EXPECT_EQ(gps.rfind("t_ns,lat,lon,alt,", 0), 0u);
  const std::string rec = read_text(good() / "recording.yaml");
  EXPECT_NE(rec.find("format: navaid-recording\nversion: 2\n"), std::string::npos);
  EXPECT_NE(rec.find("sensors: [imu, frames, gps, mag, groundtruth, features, landmarks]"), std::string::npos);
  EXPECT_NE(rec.find("latitude_deg: 46.519653"), std::string::npos);
  const std::string frames = read_text(good() / "frames.csv");
  EXPECT_EQ(frames.substr(0, frames.find('\n')), "t_ns,camera,index,intensity,depth,labels,confidence");
  EXPECT_NE(frames.find("1403715273262142976,cam0,0,rgb/cam0_1403715273262142976.png,"
                        "depth/cam0_1403715273262142976.png,labels/cam0_1403715273262142976.png,"
                        "confidence/cam0_1403715273262142976.png\n"),
            std::string::npos);
  EXPECT_NE(frames.find("1403715273262142976,cam1,100,rgb/cam1_1403715273262142976.png,,,\n"), std::string::npos);
  const std::string features = read_text(good() / "features.csv");
  EXPECT_EQ(features.substr(0, features.find('\n')), "t_ns,camera,track_id,u,v,depth");
  EXPECT_NE(features.find("\n1403715273262142976,cam0,5000000035,"), std::string::npos);
  EXPECT_NE(features.find("\n1403715273328809642,cam1,,,,\n"), std::string::npos);  // frame without features
  const std::string landmarks = read_text(good() / "landmarks.csv");
  EXPECT_EQ(landmarks.rfind("track_id,x,y,z\n5000000035,", 0), 0u);
  EXPECT_TRUE(is_navaid_recording(good()));
  EXPECT_FALSE(is_navaid_recording(dir_ / "src"));
}

TEST_F(NavaidRecordingTest, HandWrittenFourByFourTransformIsAccepted) {
  const fs::path bad = copy("matrix");
  const fs::path cal = bad / "calibration.yaml";
  std::string text = read_text(cal);
  const auto at = text.find("  T_B_I:\n");
  ASSERT_NE(at, std::string::npos);
  text = text.substr(0, at) +
         "  T_B_I: [[0, -1, 0, 0.5], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n";
  text += "gps:\n  lever_arm_B_m: [0, 0, 1]\n";
  write_text(cal, text);
  const Recording r = read_navaid_recording(bad);
  EXPECT_TRUE(r.calibration.imu->T_B_I.is_approx(SE3(rotation(0, 0, 1, M_PI / 2), Vec3(0.5, 0, 0)), 1e-12));
  EXPECT_FALSE(r.calibration.mag_rate_hz.has_value());
}

// ---- CSV corruption: every case names the file and the line -----------------------------------

TEST_F(NavaidRecordingTest, CsvWrongFieldCount) {
  const fs::path bad = copy("fields");
  set_line(bad / "imu.csv", 4, "1403715273272142976,0.1,0.2,0.3,1,2");
  expect_io_error([&] { read_navaid_recording(bad); }, "imu.csv", 4, "expected 7 fields, found 6");
}

TEST_F(NavaidRecordingTest, CsvNonNumericField) {
  const fs::path bad = copy("text");
  set_line(bad / "mag.csv", 3, "1403715273282142979,1e-5,abc,2e-5");
  expect_io_error([&] { read_navaid_recording(bad); }, "mag.csv", 3, "column 'my': 'abc' is not a number");
}

TEST_F(NavaidRecordingTest, CsvNonFiniteField) {
  const fs::path bad = copy("nan");
  set_line(bad / "imu.csv", 2, "1403715273262142976,nan,0,0,0,0,9.8");
  expect_io_error([&] { read_navaid_recording(bad); }, "imu.csv", 2, "column 'gx': 'nan' is not a finite number");
  set_line(bad / "imu.csv", 2, "1403715273262142976,0,0,0,0,0,inf");
  expect_io_error([&] { read_navaid_recording(bad); }, "imu.csv", 2, "column 'az'");
}

TEST_F(NavaidRecordingTest, CsvTimeNotIncreasing) {
  const fs::path bad = copy("time");
  set_line(bad / "groundtruth.csv", 5, "1403715273262142976,0,0,0,1,0,0,0,,,,,,,,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "groundtruth.csv", 5, "decreasing timestamp");
  set_line(bad / "groundtruth.csv", 5, "1403715273282142976,0,0,0,1,0,0,0,,,,,,,,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "groundtruth.csv", 5, "duplicate timestamp");
}

TEST_F(NavaidRecordingTest, CsvBadTimestamp) {
  const fs::path bad = copy("t");
  set_line(bad / "gps.csv", 2, "1403715273.262,46.5,6.6,372,48,3,1,7,0.9,1,0,0,1,0,1");
  expect_io_error([&] { read_navaid_recording(bad); }, "gps.csv", 2, "not an integer time in nanoseconds");
}

TEST_F(NavaidRecordingTest, CsvWrongHeader) {
  const fs::path bad = copy("header");
  set_line(bad / "gps.csv", 1, "t_ns,lat_rad,lon_rad,alt,geoid_sep,mode,quality,satellites,hdop,cov_ee,cov_en,"
                                   "cov_eu,cov_nn,cov_nu,cov_uu");
  expect_io_error([&] { read_navaid_recording(bad); }, "gps.csv", 1, "header must be 't_ns,lat,lon,alt,");
}

TEST_F(NavaidRecordingTest, GpsLatitudeOutOfRange) {
  const fs::path bad = copy("lat");
  set_line(bad / "gps.csv", 3, "1403715273462142983,146.5,6.6,372,48,3,1,7,0.9,1,0,0,1,0,1");
  expect_io_error([&] { read_navaid_recording(bad); }, "gps.csv", 3, "column 'lat': 146.5 is outside [-90, 90]");
}

TEST_F(NavaidRecordingTest, PartialOptionalGroup) {
  const fs::path bad = copy("partial");
  set_line(bad / "groundtruth.csv", 2, "1403715273262142976,0,0,0,1,0,0,0,1,,,,,,,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "groundtruth.csv", 2, "must be all set or all empty");
}

TEST_F(NavaidRecordingTest, NonUnitQuaternion) {
  const fs::path bad = copy("quat");
  set_line(bad / "groundtruth.csv", 2, "1403715273262142976,0,0,0,1,0.1,0,0,,,,,,,,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "groundtruth.csv", 2, "norm");
}

TEST_F(NavaidRecordingTest, MissingFrameImageNamesFramesCsvLine) {
  const fs::path bad = copy("image");
  fs::remove(bad / "depth" / "cam0_1403715273295476309.png");  // second cam0 frame: row 4
  expect_io_error([&] { read_navaid_recording(bad); }, "frames.csv", 4, "does not exist");
}

TEST_F(NavaidRecordingTest, FramePathEscapingTheFolder) {
  const fs::path bad = copy("escape");
  set_line(bad / "frames.csv", 2, "1403715273262142976,cam0,0,../good/rgb/cam0_1403715273262142976.png,,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "frames.csv", 2, "no '..'");
}

TEST_F(NavaidRecordingTest, FramesOutOfOrder) {
  const fs::path bad = copy("frames-order");
  set_line(bad / "frames.csv", 4, "1403715273262142975,cam0,1,,,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "frames.csv", 4, "time order");
}

TEST_F(NavaidRecordingTest, ListedSensorWithoutFile) {
  const fs::path bad = copy("listed");
  fs::remove(bad / "mag.csv");
  expect_io_error([&] { read_navaid_recording(bad); }, "mag.csv", 0, "recording.yaml lists sensor 'mag'");
}

TEST_F(NavaidRecordingTest, UnlistedFileIsIgnoredWithAWarning) {
  const fs::path bad = copy("unlisted");
  replace_text(bad / "recording.yaml", "sensors: [imu, frames, gps, mag, groundtruth, features, landmarks]",
               "sensors: [imu, frames]");
  const Recording r = read_navaid_recording(bad);
  EXPECT_TRUE(r.gps.empty());
  EXPECT_TRUE(r.features.empty());
  EXPECT_EQ(r.report.total(), 5u);
}

// ---- Feature observations, landmarks and label confidence (version 2) --------------------------

// features.csv of the good recording: line 2..13 frame (kT0, cam0) with ids 5, 8, ... 38 (times
// 1000000007), 14..25 (kT0, cam1), 26.. (kT0 + 33 ms, cam0).
TEST_F(NavaidRecordingTest, FeaturesWrongHeader) {
  const fs::path bad = copy("f-header");
  set_line(bad / "features.csv", 1, "t_ns,camera,track_id,u,v,depth_mm");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 1, "header must be 't_ns,camera,track_id");
}

TEST_F(NavaidRecordingTest, FeaturesDuplicateTrackIdInAFrame) {
  const fs::path bad = copy("f-dup");
  set_line(bad / "features.csv", 3, "1403715273262142976,cam0,5000000035,10,20,");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 3,
                  "column 'track_id': 5000000035 after 5000000035 in the same frame");
}

TEST_F(NavaidRecordingTest, FeaturesTimeOrder) {
  const fs::path bad = copy("f-time");
  set_line(bad / "features.csv", 26, "1403715273262142975,cam0,6000000042,10,20,");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 26, "rows must be in time order");
  // A second frame of the same camera at the same time (rows of a frame split apart).
  set_line(bad / "features.csv", 26, "1403715273262142976,cam0,6000000042,10,20,");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 26, "camera 'cam0' has a second frame");
}

TEST_F(NavaidRecordingTest, FeaturesBadNumbers) {
  const fs::path bad = copy("f-numbers");
  set_line(bad / "features.csv", 2, "1403715273262142976,cam0,5000000035,10,20,far");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 2, "column 'depth': 'far' is not a number");
  set_line(bad / "features.csv", 2, "1403715273262142976,cam0,5000000035,nan,20,");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 2, "column 'u': 'nan' is not a finite number");
  set_line(bad / "features.csv", 2, "1403715273262142976,cam0,5000000035,10,20,-1.5");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 2, "column 'depth': -1.5 must be positive");
  set_line(bad / "features.csv", 2, "1403715273262142976,cam0,5000000035,10,20,0");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 2, "column 'depth': 0 must be positive");
  set_line(bad / "features.csv", 2, "1403715273262142976,cam0,-5,10,20,");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 2, "column 'track_id': -5 is outside");
  set_line(bad / "features.csv", 2, "1403715273262142976,cam0,5000000035,10,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 2, "column 'v' is empty");
}

TEST_F(NavaidRecordingTest, FeaturesEmptyFrameMarkerMustBeAlone) {
  const fs::path bad = copy("f-marker");
  set_line(bad / "features.csv", 3, "1403715273262142976,cam0,,,,");
  expect_io_error([&] { read_navaid_recording(bad); }, "features.csv", 3, "must be the only row of its frame");
}

TEST_F(NavaidRecordingTest, LandmarksMustBeSortedAndWellFormed) {
  const fs::path bad = copy("l-order");
  set_line(bad / "landmarks.csv", 3, "5000000035,1,2,3");
  expect_io_error([&] { read_navaid_recording(bad); }, "landmarks.csv", 3, "must be strictly increasing");
  set_line(bad / "landmarks.csv", 3, "6000000042,1,inf,3");
  expect_io_error([&] { read_navaid_recording(bad); }, "landmarks.csv", 3, "column 'y'");
  set_line(bad / "landmarks.csv", 1, "t_ns,track_id,x,y,z");
  expect_io_error([&] { read_navaid_recording(bad); }, "landmarks.csv", 1, "header must be 'track_id,x,y,z'");
}

TEST_F(NavaidRecordingTest, ConfidenceNeedsLabels) {
  const fs::path bad = copy("c-labels");
  set_line(bad / "frames.csv", 2,
               "1403715273262142976,cam0,0,,,,confidence/cam0_1403715273262142976.png");
  expect_io_error([&] { read_navaid_recording(bad); }, "frames.csv", 2, "a label confidence needs labels");
}

TEST_F(NavaidRecordingTest, ConfidencePngMustBe8BitAndLabelSized) {
  const fs::path bad = copy("c-png");
  const fs::path png = bad / "confidence" / "cam0_1403715273262142976.png";
  ASSERT_TRUE(cv::imwrite(png.string(), cv::Mat(6, 8, CV_16UC1, cv::Scalar(40000))));
  Recording r = read_navaid_recording(bad);  // pixels are read lazily
  expect_io_error([&] { load_frame_images(r.frames[0]); }, png.filename().string(), 0,
                  "must be an 8-bit single-channel PNG");
  ASSERT_TRUE(cv::imwrite(png.string(), cv::Mat(5, 8, CV_8UC1, cv::Scalar(200))));
  expect_io_error([&] { load_frame_images(r.frames[0]); }, png.filename().string(), 0,
                  "label confidence is 8x5 but the labels are 8x6");
  // The writer checks the same when it re-encodes from such a source.
  expect_io_error([&] { write_navaid_recording(r, dir_ / "c-png-out"); }, png.filename().string(), 0,
                  "label confidence is 8x5 but the labels are 8x6");
}

TEST_F(NavaidRecordingTest, WriterRefusesBadFeaturesLandmarksAndConfidence) {
  Recording r;
  FeatureFrame f;
  f.features = {FeatureObservation{4, Eigen::Vector2d(1, 2), 1.5}, FeatureObservation{4, Eigen::Vector2d(3, 4), {}}};
  r.features = {f};
  expect_io_error([&] { write_navaid_recording(r, dir_ / "wf"); }, "features.csv", 0,
                  "feature frame 0: track id 4 after 4");
  r.features[0].features[1].track_id = 7;
  r.features[0].features[0].depth_m = -1.0;
  expect_io_error([&] { write_navaid_recording(r, dir_ / "wf"); }, "features.csv", 0, "depth -1 is not a positive");
  r.features[0].features[0].depth_m = 1.0;
  r.features[0].features[1].uv.y() = std::nan("");
  expect_io_error([&] { write_navaid_recording(r, dir_ / "wf"); }, "features.csv", 0, "column 'v' is not finite");
  r.features[0].features[1].uv.y() = 3;
  r.features.push_back(r.features[0]);  // same camera, same time
  expect_io_error([&] { write_navaid_recording(r, dir_ / "wf"); }, "features.csv", 0,
                  "feature frame 1: timestamp");
  r.features.pop_back();

  r.landmarks = {Landmark{3, Vec3::Zero()}, Landmark{2, Vec3::Ones()}};
  expect_io_error([&] { write_navaid_recording(r, dir_ / "wf"); }, "landmarks.csv", 0, "landmark 1: track id 2 after 3");
  r.landmarks[1].id = 9;

  RgbdFrame frame;
  frame.labels = ImageU8(4, 3, 1, 2);
  frame.label_confidence = ImageF32(4, 3, 1, 0.5f);
  frame.label_confidence->at(2, 1) = 1.25f;
  r.frames = {frame};
  expect_io_error([&] { write_navaid_recording(r, dir_ / "wf"); }, "cam0_0.png", 0,
                  "pixel (2, 1): label confidence 1.25");
  r.frames[0].labels.reset();
  NavaidWriteOptions overwrite;
  overwrite.overwrite = true;
  expect_io_error([&] { write_navaid_recording(r, dir_ / "wf", overwrite); }, "frames.csv", 0,
                  "has a label confidence but no labels");
  EXPECT_FALSE(fs::exists(dir_ / "wf" / "features.csv"));
}

TEST_F(NavaidRecordingTest, FeaturesOfAnUncalibratedCameraAreReadWithAWarning) {
  Recording r;
  FeatureFrame f;
  f.camera = "cam7";
  f.t = 100;
  r.features = {f};  // also: a frame without features round trips
  write_navaid_recording(r, dir_ / "uncal");
  const Recording read = read_navaid_recording(dir_ / "uncal");
  ASSERT_EQ(read.features.size(), 1u);
  EXPECT_EQ(read.features[0].camera, "cam7");
  EXPECT_EQ(read.features[0].t, 100);
  EXPECT_TRUE(read.features[0].features.empty());
  EXPECT_EQ(read.report.total(), 1u);
}

// A version 1 folder (no confidence column, no features or landmarks) is still read; writing it
// again gives exactly the version 2 folder of the same data.
TEST_F(NavaidRecordingTest, Version1FolderReadsAndBecomesVersion2) {
  Recording r = original_;
  r.features.clear();
  r.landmarks.clear();
  for (auto& f : r.frames) {
    f.confidence_path.clear();
    f.label_confidence.reset();
  }
  const fs::path v2 = dir_ / "v2";
  write_navaid_recording(r, v2);
  const fs::path v1 = dir_ / "v1";
  fs::copy(v2, v1, fs::copy_options::recursive);
  replace_text(v1 / "recording.yaml", "version: 2", "version: 1");
  replace_text(v1 / "calibration.yaml", "format version 2", "format version 1");
  std::istringstream in(read_text(v1 / "frames.csv"));
  std::string v1_frames, line;
  while (std::getline(in, line)) {
    ASSERT_TRUE(line.size() > 1 && (line.back() == ',' || line.rfind("t_ns", 0) == 0)) << line;
    v1_frames += line.substr(0, line.rfind(',')) + "\n";
  }
  write_text(v1 / "frames.csv", v1_frames);
  EXPECT_EQ(read_text(v1 / "frames.csv").substr(0, 41), "t_ns,camera,index,intensity,depth,labels\n");

  const Recording read = read_navaid_recording(v1);
  EXPECT_EQ(read.report.total(), 0u);
  expect_same_calibration(r.calibration, read.calibration);
  expect_same_samples(r, read);
  const fs::path again = dir_ / "v1-again";
  write_navaid_recording(read, again);
  const auto files = files_under(v2);
  ASSERT_EQ(files, files_under(again));
  for (const auto& f : files) EXPECT_EQ(read_text(v2 / f), read_text(again / f)) << f;

  // Version 1 knows neither the confidence column nor the new sensors.
  write_text(v1 / "frames.csv", read_text(v2 / "frames.csv"));
  expect_io_error([&] { read_navaid_recording(v1); }, "frames.csv", 1, "header must be");
  replace_text(v1 / "recording.yaml", "groundtruth]", "groundtruth, landmarks]");
  expect_config_error([&] { read_navaid_recording(v1); }, "recording.yaml", "sensors[5]",
                      "sensor 'landmarks' needs format version 2");
}

// ---- YAML corruption: every case names the file and the key -----------------------------------

TEST_F(NavaidRecordingTest, UnknownVersion) {
  const fs::path bad = copy("version");
  replace_text(bad / "recording.yaml", "version: 2", "version: 3\nkey_of_version_3: true");
  expect_config_error([&] { read_navaid_recording(bad); }, "recording.yaml", "version",
                      "unsupported navaid recording version 3; this build reads versions 1 to 2");
  replace_text(bad / "recording.yaml", "version: 3", "version: 0");
  expect_config_error([&] { read_navaid_recording(bad); }, "recording.yaml", "version",
                      "unsupported navaid recording version 0");
}

TEST_F(NavaidRecordingTest, WrongFormatName) {
  const fs::path bad = copy("format");
  replace_text(bad / "recording.yaml", "format: navaid-recording", "format: euroc");
  expect_config_error([&] { read_navaid_recording(bad); }, "recording.yaml", "format", "not a navaid recording");
}

TEST_F(NavaidRecordingTest, MissingCalibrationKeys) {
  struct Case {
    std::string line, key;
  };
  const std::vector<Case> cases = {
      {"    intrinsics:", "cameras[0].intrinsics"},
      {"      baseline_m:", "cameras[0].depth.baseline_m"},
      {"      q_wxyz:", "cameras[0].T_B_C.q_wxyz"},
      {"  gyroscope_random_walk:", "imu.gyroscope_random_walk"},
      {"  lever_arm_B_m:", "gps.lever_arm_B_m"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const fs::path bad = copy("key" + std::to_string(n++));
    remove_line_containing(bad / "calibration.yaml", c.line);
    expect_config_error([&] { read_navaid_recording(bad); }, "calibration.yaml", c.key, "missing");
  }
}

TEST_F(NavaidRecordingTest, BadCalibrationValues) {
  const fs::path bad = copy("values");
  replace_text(bad / "calibration.yaml", "distortion_model: equidistant", "distortion_model: fisheye");
  expect_config_error([&] { read_navaid_recording(bad); }, "calibration.yaml", "cameras[1].distortion_model",
                      "not one of none, radtan, equidistant");
  const fs::path bad2 = copy("values2");
  replace_text(bad2 / "calibration.yaml", "resolution: [8, 6]", "resolution: [8.5, 6]");
  expect_config_error([&] { read_navaid_recording(bad2); }, "calibration.yaml", "cameras[0].resolution[0]",
                      "not an integer");
  const fs::path bad3 = copy("values3");
  replace_text(bad3 / "calibration.yaml", "rate_hz: 200", "rate_hz: fast");
  expect_config_error([&] { read_navaid_recording(bad3); }, "calibration.yaml", "imu.rate_hz", "not a number");
}

TEST_F(NavaidRecordingTest, InvalidYamlSyntaxNamesTheLine) {
  const fs::path bad = copy("syntax");
  set_line(bad / "calibration.yaml", 4, "    resolution: [8, 6");
  // yaml-cpp reports where it noticed the unclosed list: the next line.
  expect_io_error([&] { read_navaid_recording(bad); }, "calibration.yaml", 5, "invalid YAML");
}

TEST_F(NavaidRecordingTest, UnknownYamlKeysAreErrors) {
  const fs::path bad = copy("typo");
  replace_text(bad / "calibration.yaml", "  T_B_I:", "  T_B_l:");
  expect_config_error([&] { read_navaid_recording(bad); }, "calibration.yaml", "imu.T_B_l", "unknown key");
  const fs::path bad2 = copy("typo2");
  replace_text(bad2 / "recording.yaml", "origin:", "orign:");
  expect_config_error([&] { read_navaid_recording(bad2); }, "recording.yaml", "orign", "unknown key");
}

TEST_F(NavaidRecordingTest, MissingRecordingYaml) {
  const fs::path bad = copy("noyaml");
  fs::remove(bad / "recording.yaml");
  expect_io_error([&] { read_navaid_recording(bad); }, "recording.yaml", 0, "does not exist");
}

// ---- Writer refusals --------------------------------------------------------------------------

TEST_F(NavaidRecordingTest, WriterRefusesNonEmptyFolderUnlessOverwrite) {
  expect_io_error([&] { write_navaid_recording(original_, good()); }, "good", 0, "not empty");
  NavaidWriteOptions overwrite;
  overwrite.overwrite = true;
  write_text(good() / "notes.txt", "mine");
  write_navaid_recording(original_, good(), overwrite);
  EXPECT_EQ(read_text(good() / "notes.txt"), "mine");  // not ours: kept
  const Recording read = read_navaid_recording(good());
  expect_io_error([&] { write_navaid_recording(read, good(), overwrite); }, "good", 0,
                  "cannot overwrite the folder that frame images are read from");
}

TEST_F(NavaidRecordingTest, WriterRefusesUnrepresentableDepth) {
  Recording r;
  RgbdFrame f;
  f.depth = ImageF32(4, 3, 1, 70.0f);  // beyond 65.535 m in millimetres
  r.frames.push_back(f);
  const fs::path out = dir_ / "deep";
  expect_io_error([&] { write_navaid_recording(r, out); }, "cam0_0.png", 0, "exceeds the 16-bit range");
  r.frames[0].depth = ImageF32(4, 3, 1, std::nanf(""));
  NavaidWriteOptions overwrite;
  overwrite.overwrite = true;
  expect_io_error([&] { write_navaid_recording(r, dir_ / "nan-depth", overwrite); }, "cam0_0.png", 0,
                  "only finite depth");
}

TEST_F(NavaidRecordingTest, WriterRefusesOutOfOrderAndNonFinite) {
  Recording r;
  r.imu = {ImuSample{10, Vec3::Zero(), Vec3::Zero(), true}, ImuSample{10, Vec3::Zero(), Vec3::Zero(), true}};
  expect_io_error([&] { write_navaid_recording(r, dir_ / "w1"); }, "imu.csv", 0, "sample 1: timestamp");
  r.imu = {ImuSample{10, Vec3(0, std::nan(""), 0), Vec3::Zero(), true}};
  expect_io_error([&] { write_navaid_recording(r, dir_ / "w2"); }, "imu.csv", 0, "column 'gy' is not finite");
  EXPECT_FALSE(fs::exists(dir_ / "w2"));  // validated before touching the disk
}

TEST_F(NavaidRecordingTest, WriterRefusesClassProbabilitiesUnlessDropped) {
  Recording r;
  RgbdFrame f;
  f.intensity = ImageU8(4, 3, 1, 9);
  f.class_probabilities = ImageF32(4, 3, 5, 0.2f);
  r.frames.push_back(f);
  expect_io_error([&] { write_navaid_recording(r, dir_ / "p1"); }, "frames.csv", 0, "per-class probabilities");
  NavaidWriteOptions drop;
  drop.drop_class_probabilities = true;
  write_navaid_recording(r, dir_ / "p2", drop);
  EXPECT_EQ(read_navaid_recording(dir_ / "p2").frames.size(), 1u);
}

TEST_F(NavaidRecordingTest, WriterChecksDepthUnitsOfTheSource) {
  Recording r;
  RgbdFrame f;
  cv::Mat metres(6, 8, CV_16UC1, cv::Scalar(3));  // 3 "m" stored in a millimetre PNG
  f.depth_path = write_source_png(dir_ / "src" / "metres.png", metres);
  r.frames.push_back(f);
  expect_io_error([&] { write_navaid_recording(r, dir_ / "units"); }, "metres.png", 0, "looks like depth in metres");
}

TEST_F(NavaidRecordingTest, EmptyRecordingRoundTrips) {
  Recording r;
  write_navaid_recording(r, dir_ / "empty");
  const Recording read = read_navaid_recording(dir_ / "empty");
  EXPECT_TRUE(read.empty());
  EXPECT_TRUE(read.calibration.cameras.empty());
  EXPECT_FALSE(read.origin.has_value());
  EXPECT_EQ(read_text(dir_ / "empty" / "calibration.yaml").find("gps:"), std::string::npos);
}

// Real numbers (receiver fixes with unknown fields, motion-capture poses) through the format.
TEST(NavaidRecordingRealData, NmeaCapturesAndEurocGroundTruthRoundTrip) {
  NAVAID_REQUIRE_SHARED_DATA();
  const fs::path data = navaid::testing::shared_data_dir();
  ScratchDir dir("navaid-recording-real");
  std::size_t captures = 0, fixes = 0, unknown_satellites = 0, unknown_geoid = 0;
  const Recording truth =
      read_tum_trajectory_recording(data / "rpg-euroc-V1_02" / "vislam_rp" / "stamped_groundtruth.txt");
  for (const auto& entry : fs::directory_iterator(data / "gpsd-nmea")) {
    if (entry.path().extension() != ".log") continue;
    Recording r = read_nmea_capture(entry.path());
    if (r.gps.empty()) continue;
    if (captures == 0) r.groundtruth = truth.groundtruth;  // once: 16k poses are slow to repeat
    r.calibration.gps_rate_hz = 1;
    const fs::path a = dir / (entry.path().stem().string() + "-a");
    const fs::path b = dir / (entry.path().stem().string() + "-b");
    write_navaid_recording(r, a);
    const Recording read = read_navaid_recording(a);
    ASSERT_EQ(read.gps.size(), r.gps.size()) << entry.path();
    for (std::size_t i = 0; i < r.gps.size(); ++i) {
      const GpsFix& x = r.gps[i];
      const GpsFix& y = read.gps[i];
      ASSERT_EQ(x.t, y.t);
      EXPECT_EQ(x.latitude_deg, y.latitude_deg);
      EXPECT_EQ(x.longitude_deg, y.longitude_deg);
      EXPECT_TRUE(same_number(x.altitude_m, y.altitude_m));
      EXPECT_TRUE(same_number(x.geoid_separation_m, y.geoid_separation_m));
      EXPECT_TRUE(same_number(x.hdop, y.hdop));
      EXPECT_EQ(x.satellites, y.satellites);
      EXPECT_EQ(x.mode, y.mode);
      EXPECT_EQ(x.quality, y.quality);
      EXPECT_TRUE(x.covariance_enu.isApprox(y.covariance_enu, 1e-15)) << entry.path() << " fix " << i;
    }
    ASSERT_EQ(read.groundtruth.size(), r.groundtruth.size());
    for (std::size_t i = 0; i < r.groundtruth.size(); ++i) {
      EXPECT_EQ(read.groundtruth[i].T_W_B.t, r.groundtruth[i].T_W_B.t);
      EXPECT_LT(read.groundtruth[i].T_W_B.q.angularDistance(r.groundtruth[i].T_W_B.q), 1e-15);
    }
    for (const auto& f : r.gps) {
      unknown_satellites += f.satellites < 0;
      unknown_geoid += std::isnan(f.geoid_separation_m);
    }
    write_navaid_recording(read, b);
    for (const auto& f : files_under(a)) EXPECT_EQ(read_text(a / f), read_text(b / f)) << entry.path() << " " << f;
    ++captures;
    fixes += r.gps.size();
  }
  EXPECT_GE(captures, 5u);
  EXPECT_GE(fixes, 100u);
  std::cout << "[ info ] " << captures << " captures, " << fixes << " fixes (" << unknown_satellites
            << " without satellite count, " << unknown_geoid << " without geoid separation)\n";
}

}  // namespace
}  // namespace navaid::io
