#pragma once
// A plain owning image: row-major, interleaved channels. Kept free of OpenCV so that core stays
// light; rooms that use OpenCV wrap the buffer without copying (cv::Mat(h, w, type, data())).
#include <cassert>
#include <cstdint>
#include <vector>

namespace navaid {

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<T> pixels;

  Image() = default;
  Image(int w, int h, int c = 1, T fill = T{})
      : width(w), height(h), channels(c), pixels(static_cast<std::size_t>(w) * h * c, fill) {}

  bool empty() const { return pixels.empty(); }
  T* data() { return pixels.data(); }
  const T* data() const { return pixels.data(); }
  std::size_t index(int x, int y, int c = 0) const {
    assert(x >= 0 && x < width && y >= 0 && y < height && c >= 0 && c < channels);
    return (static_cast<std::size_t>(y) * width + x) * channels + c;
  }
  T& at(int x, int y, int c = 0) { return pixels[index(x, y, c)]; }
  const T& at(int x, int y, int c = 0) const { return pixels[index(x, y, c)]; }
  bool operator==(const Image& o) const {
    return width == o.width && height == o.height && channels == o.channels && pixels == o.pixels;
  }
};

using ImageU8 = Image<std::uint8_t>;
using ImageU16 = Image<std::uint16_t>;
using ImageF32 = Image<float>;

}  // namespace navaid
