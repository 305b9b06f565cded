// Frame image loading and PNG writing, including the error cases.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"
#include "test_support.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using navaid::testing::error_message;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

std::string imwrite(const fs::path& file, const cv::Mat& m) {
  EXPECT_TRUE(cv::imwrite(file.string(), m));
  return file.string();
}


class ImageIoTest : public ::testing::Test {
 protected:
  ScratchDir dir_{"image-io"};
};

TEST_F(ImageIoTest, LoadsGreyColourDepthAndLabels) {
  cv::Mat bgr(4, 5, CV_8UC3, cv::Scalar(10, 20, 30));  // B, G, R
  cv::Mat depth(4, 5, CV_16UC1, cv::Scalar(1500));
  depth.at<std::uint16_t>(1, 2) = 0;
  depth.at<std::uint16_t>(3, 4) = 65535;
  cv::Mat labels(4, 5, CV_8UC1, cv::Scalar(7));
  RgbdFrame f;
  f.intensity_path = imwrite(dir_ / "rgb.png", bgr);
  f.depth_path = imwrite(dir_ / "depth.png", depth);
  f.labels_path = imwrite(dir_ / "labels.png", labels);
  load_frame_images(f);
  ASSERT_EQ(f.intensity.channels, 3);
  EXPECT_EQ(f.intensity.width, 5);
  EXPECT_EQ(f.intensity.height, 4);
  EXPECT_EQ(f.intensity.at(0, 0, 0), 30);  // R first
  EXPECT_EQ(f.intensity.at(0, 0, 2), 10);
  EXPECT_FLOAT_EQ(f.depth.at(0, 0), 1.5f);
  EXPECT_EQ(f.depth.at(2, 1), 0.0f);  // invalid stays invalid
  EXPECT_FLOAT_EQ(f.depth.at(4, 3), 65.535f);
  ASSERT_TRUE(f.labels.has_value());
  EXPECT_EQ(f.labels->at(4, 3), 7);

  cv::Mat grey(4, 5, CV_8UC1, cv::Scalar(200));
  RgbdFrame g;
  g.intensity_path = imwrite(dir_ / "grey.png", grey);
  load_frame_images(g);
  EXPECT_EQ(g.intensity.channels, 1);
  EXPECT_EQ(g.intensity.at(4, 3), 200);
  EXPECT_TRUE(g.depth.empty());
  EXPECT_FALSE(g.labels.has_value());

  release_frame_images(f);
  EXPECT_TRUE(f.intensity.empty());
  EXPECT_FALSE(f.labels.has_value());
  EXPECT_FALSE(f.depth_path.empty());
}

TEST_F(ImageIoTest, DepthScaleOfTheFrameIsApplied) {
  RgbdFrame f;
  f.depth_path = imwrite(dir_ / "tum.png", cv::Mat(2, 2, CV_16UC1, cv::Scalar(5000)));
  f.depth_png_scale_m = 1.0 / 5000;
  load_frame_images(f);
  EXPECT_FLOAT_EQ(f.depth.at(1, 1), 1.0f);
}

TEST_F(ImageIoTest, RgbaDropsAlpha) {
  cv::Mat bgra(2, 3, CV_8UC4, cv::Scalar(1, 2, 3, 128));
  const ImageU8 image = read_intensity_image(imwrite(dir_ / "rgba.png", bgra));
  ASSERT_EQ(image.channels, 3);
  EXPECT_EQ(image.at(2, 1, 0), 3);
  EXPECT_EQ(image.at(2, 1, 2), 1);
}

TEST_F(ImageIoTest, WrittenPngsReadBackExactly) {
  ImageU8 rgb(7, 3, 3);
  ImageU8 grey(7, 3, 1);
  ImageU16 deep(7, 3, 1);
  for (std::size_t i = 0; i < rgb.pixels.size(); ++i) rgb.pixels[i] = static_cast<std::uint8_t>(i * 7);
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) grey.pixels[i] = static_cast<std::uint8_t>(255 - i);
  for (std::size_t i = 0; i < deep.pixels.size(); ++i) deep.pixels[i] = static_cast<std::uint16_t>(i * 3001);
  write_png((dir_ / "rgb.png").string(), rgb);
  write_png((dir_ / "grey.png").string(), grey);
  write_png((dir_ / "deep.png").string(), deep);
  EXPECT_EQ(read_intensity_image((dir_ / "rgb.png").string()), rgb);
  EXPECT_EQ(read_intensity_image((dir_ / "grey.png").string()), grey);
  EXPECT_EQ(read_label_image((dir_ / "grey.png").string()), grey);
  EXPECT_EQ(read_depth_png_raw((dir_ / "deep.png").string(), 0.001), deep);
  // OpenCV sees BGR: the writer swapped the channels.
  const cv::Mat m = cv::imread((dir_ / "rgb.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(m.at<cv::Vec3b>(0, 1)[2], rgb.at(1, 0, 0));
  // Same pixels, same bytes.
  write_png((dir_ / "rgb2.png").string(), rgb);
  EXPECT_EQ(read_text(dir_ / "rgb.png"), read_text(dir_ / "rgb2.png"));
}

TEST_F(ImageIoTest, MissingFile) {
  RgbdFrame f;
  f.depth_path = (dir_ / "nope.png").string();
  const std::string message = error_message<IoError>([&] { load_frame_images(f); });
  EXPECT_NE(message.find("nope.png: image file does not exist"), std::string::npos) << message;
}

TEST_F(ImageIoTest, CorruptPng) {
  const cv::Mat good(8, 8, CV_8UC1, cv::Scalar(3));
  imwrite(dir_ / "good.png", good);
  const std::string bytes = read_text(dir_ / "good.png");
  write_text(dir_ / "truncated.png", bytes.substr(0, bytes.size() / 2));
  write_text(dir_ / "garbage.png", "this is not a png");
  write_text(dir_ / "empty.png", "");
  for (const char* name : {"truncated.png", "garbage.png", "empty.png"}) {
    RgbdFrame f;
    f.intensity_path = (dir_ / name).string();
    const std::string message = error_message<IoError>([&] { load_frame_images(f); });
    EXPECT_NE(message.find(name), std::string::npos) << message;
    EXPECT_TRUE(message.find("cannot decode") != std::string::npos || message.find("empty") != std::string::npos)
        << message;
  }
}

TEST_F(ImageIoTest, DepthMustBe16BitSingleChannel) {
  RgbdFrame f;
  f.depth_path = imwrite(dir_ / "depth8.png", cv::Mat(3, 3, CV_8UC1, cv::Scalar(100)));
  std::string message = error_message<IoError>([&] { load_frame_images(f); });
  EXPECT_NE(message.find("16-bit single-channel PNG, found 8-bit 1-channel"), std::string::npos) << message;
  f.depth_path = imwrite(dir_ / "depth3.png", cv::Mat(3, 3, CV_16UC3, cv::Scalar(1000, 1000, 1000)));
  message = error_message<IoError>([&] { load_frame_images(f); });
  EXPECT_NE(message.find("found 16-bit 3-channel"), std::string::npos) << message;
}

TEST_F(ImageIoTest, LabelsMustBe8BitSingleChannel) {
  RgbdFrame f;
  f.labels_path = imwrite(dir_ / "labels.png", cv::Mat(3, 3, CV_8UC3, cv::Scalar(1, 2, 3)));
  const std::string message = error_message<IoError>([&] { load_frame_images(f); });
  EXPECT_NE(message.find("8-bit single-channel"), std::string::npos) << message;
}

TEST_F(ImageIoTest, SixteenBitIntensityIsRejected) {
  RgbdFrame f;
  f.intensity_path = imwrite(dir_ / "i16.png", cv::Mat(3, 3, CV_16UC1, cv::Scalar(1000)));
  const std::string message = error_message<IoError>([&] { load_frame_images(f); });
  EXPECT_NE(message.find("8 bits per channel"), std::string::npos) << message;
}

TEST_F(ImageIoTest, DepthInMetresInsteadOfMillimetresIsCaught) {
  cv::Mat metres(6, 8, CV_16UC1, cv::Scalar(0));
  for (int y = 0; y < 6; ++y)
    for (int x = 2; x < 8; ++x) metres.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(1 + (x + y) % 20);
  metres.at<std::uint16_t>(5, 7) = 20;  // a 20 m wall, written as 20 "mm"
  RgbdFrame f;
  f.depth_path = imwrite(dir_ / "metres.png", metres);
  const std::string message = error_message<IoError>([&] { load_frame_images(f); });
  EXPECT_NE(message.find("metres.png"), std::string::npos) << message;
  EXPECT_NE(message.find("looks like depth in metres stored as integers, not millimetres"), std::string::npos)
      << message;
  EXPECT_NE(message.find("largest 20 units"), std::string::npos) << message;

  // A frame with no valid pixel says nothing about units; a real near frame passes.
  f.depth_path = imwrite(dir_ / "blank.png", cv::Mat(6, 8, CV_16UC1, cv::Scalar(0)));
  EXPECT_NO_THROW(load_frame_images(f));
  metres.at<std::uint16_t>(0, 0) = 300;  // one pixel at 30 cm
  f.depth_path = imwrite(dir_ / "near.png", metres);
  EXPECT_NO_THROW(load_frame_images(f));
}

TEST_F(ImageIoTest, DepthToPngUnits) {
  ImageF32 d(3, 1, 1);
  d.at(0, 0) = 0;
  d.at(1, 0) = 1.2344f;
  d.at(2, 0) = 65.535f;
  const ImageU16 mm = depth_to_png_units(d, 0.001, "out.png");
  EXPECT_EQ(mm.at(0, 0), 0);
  EXPECT_EQ(mm.at(1, 0), 1234);
  EXPECT_EQ(mm.at(2, 0), 65535);
  d.at(2, 0) = 65.6f;
  std::string message = error_message<IoError>([&] { depth_to_png_units(d, 0.001, "out.png"); });
  EXPECT_NE(message.find("out.png: pixel (2, 0): depth 65.6"), std::string::npos) << message;
  EXPECT_NE(message.find("exceeds the 16-bit range"), std::string::npos) << message;
  d.at(2, 0) = -1;
  message = error_message<IoError>([&] { depth_to_png_units(d, 0.001, "out.png"); });
  EXPECT_NE(message.find("only finite depth >= 0"), std::string::npos) << message;
}

TEST_F(ImageIoTest, ConvertDepthUnits) {
  ImageU16 tum(2, 1, 1);
  tum.at(0, 0) = 5001;   // 1.0002 m
  tum.at(1, 0) = 65535;  // 13.107 m
  const ImageU16 mm = convert_depth_units(tum, 1.0 / 5000, 0.001, "d.png");
  EXPECT_EQ(mm.at(0, 0), 1000);
  EXPECT_EQ(mm.at(1, 0), 13107);
  EXPECT_EQ(convert_depth_units(tum, 0.001, 0.001, "d.png"), tum);
  const std::string message = error_message<IoError>([&] { convert_depth_units(tum, 0.01, 0.001, "d.png"); });
  EXPECT_NE(message.find("exceeds the 16-bit range"), std::string::npos) << message;
}

TEST_F(ImageIoTest, LabelConfidenceQuantizesTo255Levels) {
  ImageF32 p(4, 1, 1);
  p.pixels = {0.0f, 0.2f, 0.5f, 1.0f};
  const ImageU8 units = confidence_to_png_units(p, "conf.png");
  EXPECT_EQ(units.pixels, (std::vector<std::uint8_t>{0, 51, 128, 255}));  // round(255 p), 127.5 up
  const std::string file = (dir_ / "conf.png").string();
  write_png(file, units);
  const ImageF32 back = read_confidence_png(file);
  ASSERT_EQ(back.width, 4);
  for (std::size_t i = 0; i < p.pixels.size(); ++i) EXPECT_NEAR(back.pixels[i], p.pixels[i], 0.5 / 255 + 1e-7);
  EXPECT_EQ(back.pixels[3], 1.0f);

  p.pixels[1] = -0.01f;
  EXPECT_NE(error_message<IoError>([&] { confidence_to_png_units(p, "conf.png"); }).find("pixel (1, 0)"),
            std::string::npos);
  p.pixels[1] = std::nanf("");
  EXPECT_NE(error_message<IoError>([&] { confidence_to_png_units(p, "conf.png"); }).find("not a probability"),
            std::string::npos);
  EXPECT_NE(error_message<IoError>([&] { read_confidence_png(imwrite(dir_ / "c16.png", cv::Mat(2, 2, CV_16UC1))); })
                .find("8-bit single-channel"),
            std::string::npos);
  EXPECT_NE(error_message<IoError>([&] { read_confidence_png(imwrite(dir_ / "c3.png", cv::Mat(2, 2, CV_8UC3))); })
                .find("8-bit single-channel"),
            std::string::npos);
}

TEST_F(ImageIoTest, WriterErrors) {
  const std::string message =
      error_message<IoError>([&] { write_png((dir_ / "no" / "such" / "dir.png").string(), ImageU8(2, 2)); });
  EXPECT_NE(message.find("cannot open for writing"), std::string::npos) << message;
  EXPECT_THROW(write_png((dir_ / "two.png").string(), ImageU8(2, 2, 2)), IoError);
  EXPECT_THROW(write_png((dir_ / "empty.png").string(), ImageU16()), IoError);
}

}  // namespace
}  // namespace navaid::io
