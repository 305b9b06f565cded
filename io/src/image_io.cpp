#include "navaid/io/image_io.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

#include "navaid/core/errors.hpp"

namespace navaid::io {
namespace {

std::string describe(const cv::Mat& m) {
  const int depth = m.depth();
  const char* bits = depth == CV_8U ? "8-bit" : depth == CV_16U ? "16-bit" : depth == CV_32F ? "32-bit float"
                                                                                              : "non-standard";
  return std::string(bits) + " " + std::to_string(m.channels()) + "-channel";
}

// Reading the bytes ourselves separates "cannot read the file" from "cannot decode it".
cv::Mat decode_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path, "image file does not exist");
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path, "is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open image file for reading");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(path, "read error");
  if (bytes.empty()) throw IoError(path, "image file is empty");
  cv::Mat image;
  try {
    image = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw IoError(path, std::string("cannot decode image: ") + e.what());
  }
  if (image.empty()) throw IoError(path, "cannot decode image (corrupt, truncated or not an image)");
  return image;
}

template <typename T>
Image<T> to_image(const cv::Mat& m) {
  Image<T> out(m.cols, m.rows, m.channels());
  const std::size_t row_values = static_cast<std::size_t>(m.cols) * m.channels();
  for (int y = 0; y < m.rows; ++y) {
    const T* src = m.ptr<T>(y);
    std::copy(src, src + row_values, out.pixels.begin() + static_cast<std::ptrdiff_t>(y * row_values));
  }
  return out;
}

ImageU16 u16_single_channel(const cv::Mat& m, const std::string& path) {
  if (m.depth() != CV_16U || m.channels() != 1)
    throw IoError(path, "depth image must be a 16-bit single-channel PNG, found " + describe(m));
  return to_image<std::uint16_t>(m);
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(path, "cannot open for writing (does the folder exist?)");
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw IoError(path, "write error");
}

void encode_png(const std::string& path, const cv::Mat& m, int compression) {
  if (compression < 0 || compression > 9) throw IoError(path, "PNG compression level must be 0-9");
  std::vector<unsigned char> bytes;
  try {
    if (!cv::imencode(".png", m, bytes, {cv::IMWRITE_PNG_COMPRESSION, compression}))
      throw IoError(path, "PNG encoding failed");
  } catch (const cv::Exception& e) {
    throw IoError(path, std::string("PNG encoding failed: ") + e.what());
  }
  write_bytes(path, bytes);
}

std::string format_m(double metres) {
  std::ostringstream s;
  s << metres << " m";
  return s.str();
}

}  // namespace

ImageU8 read_intensity_image(const std::string& path) {
  const cv::Mat m = decode_file(path);
  if (m.depth() != CV_8U)
    throw IoError(path, "intensity image must have 8 bits per channel, found " + describe(m));
  if (m.channels() == 1) return to_image<std::uint8_t>(m);
  if (m.channels() != 3 && m.channels() != 4)
    throw IoError(path, "intensity image must be grey, RGB or RGBA, found " + describe(m));
  // OpenCV decodes to BGR(A); navaid images are RGB.
  ImageU8 out(m.cols, m.rows, 3);
  const int step = m.channels();
  for (int y = 0; y < m.rows; ++y) {
    const std::uint8_t* src = m.ptr<std::uint8_t>(y);
    for (int x = 0; x < m.cols; ++x) {
      out.at(x, y, 0) = src[x * step + 2];
      out.at(x, y, 1) = src[x * step + 1];
      out.at(x, y, 2) = src[x * step + 0];
    }
  }
  return out;
}

ImageU8 read_label_image(const std::string& path) {
  const cv::Mat m = decode_file(path);
  if (m.depth() != CV_8U || m.channels() != 1)
    throw IoError(path, "label image must be an 8-bit single-channel PNG of class ids, found " + describe(m));
  return to_image<std::uint8_t>(m);
}

ImageU8 read_confidence_png_raw(const std::string& path) {
  const cv::Mat m = decode_file(path);
  if (m.depth() != CV_8U || m.channels() != 1)
    throw IoError(path, "label confidence image must be an 8-bit single-channel PNG (round(255 p)), found " +
                            describe(m));
  return to_image<std::uint8_t>(m);
}

ImageF32 read_confidence_png(const std::string& path) {
  const ImageU8 raw = read_confidence_png_raw(path);
  ImageF32 p(raw.width, raw.height, 1);
  for (std::size_t i = 0; i < raw.pixels.size(); ++i) p.pixels[i] = static_cast<float>(raw.pixels[i] / 255.0);
  return p;
}

ImageU8 confidence_to_png_units(const ImageF32& probability, const std::string& path) {
  if (probability.channels != 1) throw IoError(path, "label confidence must have one channel");
  ImageU8 out(probability.width, probability.height, 1);
  for (int y = 0; y < probability.height; ++y) {
    for (int x = 0; x < probability.width; ++x) {
      const double p = probability.at(x, y);
      if (!(p >= 0 && p <= 1))  // also catches NaN
        throw IoError(path, "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): label confidence " +
                                std::to_string(p) + " is not a probability in [0, 1]");
      out.at(x, y) = static_cast<std::uint8_t>(std::lround(255.0 * p));
    }
  }
  return out;
}

void check_depth_units(const ImageU16& raw, double scale_m, const std::string& path) {
  std::uint16_t largest = 0;
  for (const std::uint16_t v : raw.pixels) largest = std::max(largest, v);
  if (largest == 0) return;  // no valid pixel (lens covered, all out of range): nothing to judge
  const double max_depth_m = largest * scale_m;
  if (max_depth_m >= kMinPlausibleMaxDepthM) return;
  throw IoError(path, "every valid depth value is below " + format_m(kMinPlausibleMaxDepthM) + " (largest " +
                          std::to_string(largest) + " units x " + format_m(scale_m) + " per unit = " +
                          format_m(max_depth_m) +
                          "): this looks like depth in metres stored as integers, not millimetres "
                          "(or the wrong depth scale for this data set)");
}

ImageU16 read_depth_png_raw(const std::string& path, double scale_m) {
  if (!(scale_m > 0) || !std::isfinite(scale_m)) throw IoError(path, "depth scale must be positive and finite");
  ImageU16 raw = u16_single_channel(decode_file(path), path);
  check_depth_units(raw, scale_m, path);
  return raw;
}

ImageF32 read_depth_png(const std::string& path, double scale_m) {
  const ImageU16 raw = read_depth_png_raw(path, scale_m);
  ImageF32 depth(raw.width, raw.height, 1);
  for (std::size_t i = 0; i < raw.pixels.size(); ++i)
    depth.pixels[i] = static_cast<float>(raw.pixels[i] * scale_m);
  return depth;
}

ImageU16 depth_to_png_units(const ImageF32& depth_m, double scale_m, const std::string& path) {
  if (depth_m.channels != 1) throw IoError(path, "depth image must have one channel");
  if (!(scale_m > 0) || !std::isfinite(scale_m)) throw IoError(path, "depth scale must be positive and finite");
  ImageU16 out(depth_m.width, depth_m.height, 1);
  constexpr double kMaxUnits = std::numeric_limits<std::uint16_t>::max();
  for (int y = 0; y < depth_m.height; ++y) {
    for (int x = 0; x < depth_m.width; ++x) {
      const double d = depth_m.at(x, y);
      const auto where = [&] { return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")"; };
      if (!std::isfinite(d) || d < 0)
        throw IoError(path, where() + ": depth " + std::to_string(d) +
                                " cannot be stored (only finite depth >= 0 m; use 0 for invalid)");
      const double units = std::round(d / scale_m);
      if (units > kMaxUnits)
        throw IoError(path, where() + ": depth " + format_m(d) + " exceeds the 16-bit range at " + format_m(scale_m) +
                                " per unit (max " + format_m(kMaxUnits * scale_m) + ")");
      out.at(x, y) = static_cast<std::uint16_t>(units);
    }
  }
  return out;
}

ImageU16 convert_depth_units(const ImageU16& raw, double from_scale_m, double to_scale_m, const std::string& path) {
  if (from_scale_m == to_scale_m) return raw;
  const double ratio = from_scale_m / to_scale_m;
  constexpr double kMaxUnits = std::numeric_limits<std::uint16_t>::max();
  ImageU16 out(raw.width, raw.height, raw.channels);
  for (std::size_t i = 0; i < raw.pixels.size(); ++i) {
    const double units = std::round(raw.pixels[i] * ratio);
    if (units > kMaxUnits)
      throw IoError(path, "depth " + format_m(raw.pixels[i] * from_scale_m) + " exceeds the 16-bit range at " +
                              format_m(to_scale_m) + " per unit (max " + format_m(kMaxUnits * to_scale_m) + ")");
    out.pixels[i] = static_cast<std::uint16_t>(units);
  }
  return out;
}

void write_png(const std::string& path, const ImageU8& image, int compression) {
  if (image.empty()) throw IoError(path, "cannot write an empty image");
  if (image.channels == 1) {
    const cv::Mat m(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.data()));
    encode_png(path, m, compression);
    return;
  }
  if (image.channels != 3) throw IoError(path, "8-bit PNGs are written from 1- or 3-channel images");
  cv::Mat bgr(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y) {
    std::uint8_t* dst = bgr.ptr<std::uint8_t>(y);
    for (int x = 0; x < image.width; ++x) {
      dst[3 * x + 0] = image.at(x, y, 2);
      dst[3 * x + 1] = image.at(x, y, 1);
      dst[3 * x + 2] = image.at(x, y, 0);
    }
  }
  encode_png(path, bgr, compression);
}

void write_png(const std::string& path, const ImageU16& image, int compression) {
  if (image.empty()) throw IoError(path, "cannot write an empty image");
  if (image.channels != 1) throw IoError(path, "16-bit PNGs are written from 1-channel images");
  const cv::Mat m(image.height, image.width, CV_16UC1, const_cast<std::uint16_t*>(image.data()));
  encode_png(path, m, compression);
}

void load_frame_images(RgbdFrame& frame) {
  if (!frame.intensity_path.empty()) frame.intensity = read_intensity_image(frame.intensity_path);
  if (!frame.depth_path.empty()) frame.depth = read_depth_png(frame.depth_path, frame.depth_png_scale_m);
  if (!frame.labels_path.empty()) frame.labels = read_label_image(frame.labels_path);
  if (!frame.confidence_path.empty()) {
    ImageF32 confidence = read_confidence_png(frame.confidence_path);
    if (frame.labels && (confidence.width != frame.labels->width || confidence.height != frame.labels->height))
      throw IoError(frame.confidence_path, "label confidence is " + std::to_string(confidence.width) + "x" +
                                               std::to_string(confidence.height) + " but the labels are " +
                                               std::to_string(frame.labels->width) + "x" +
                                               std::to_string(frame.labels->height));
    frame.label_confidence = std::move(confidence);
  }
}

void release_frame_images(RgbdFrame& frame) {
  frame.intensity = ImageU8();
  frame.depth = ImageF32();
  frame.labels.reset();
  frame.label_confidence.reset();
  frame.class_probabilities.reset();
}

ImageU8 to_gray(const ImageU8& image, const std::string& file) {
  if (image.channels == 1) return image;
  if (image.channels != 3) throw IoError(file, "expected a grey or RGB image, found " + std::to_string(image.channels) + " channels");
  ImageU8 g(image.width, image.height, 1);
  for (std::size_t i = 0; i < g.pixels.size(); ++i) {
    const std::uint8_t* p = &image.pixels[3 * i];
    g.pixels[i] = static_cast<std::uint8_t>((299 * p[0] + 587 * p[1] + 114 * p[2] + 500) / 1000);
  }
  return g;
}

}  // namespace navaid::io
