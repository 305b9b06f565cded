#include "navaid/simulation/render_cache.hpp"

#include <gtest/gtest.h>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

RenderedFrame frame(double unit) {
  RenderedFrame f;
  f.depth = ImageF32(8, 6, 1, 0.0f);
  f.labels = ImageU8(8, 6, 1, 1);
  f.intensity = ImageU8(8, 6, 1, 0);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      // Already quantized, as the simulator stores it; some invalid pixels.
      f.depth.at(x, y) = (x + y) % 5 == 0 ? 0.0f : static_cast<float>((4000 + 123 * x + 7 * y) * unit);
      f.labels.at(x, y) = static_cast<std::uint8_t>((x * y) % 25);
      f.intensity.at(x, y) = static_cast<std::uint8_t>(30 * x + y);
    }
  return f;
}

TEST(RenderCache, DepthUnitIsTheFinestThatHoldsTheRange) {
  EXPECT_DOUBLE_EQ(cache_depth_unit_m(6.0), 1e-4);
  EXPECT_DOUBLE_EQ(cache_depth_unit_m(7.2), 2e-4);
  EXPECT_DOUBLE_EQ(cache_depth_unit_m(30.0), 5e-4);
  EXPECT_DOUBLE_EQ(cache_depth_unit_m(65.0), 1e-3);
  EXPECT_THROW(cache_depth_unit_m(70.0), ConfigError);
}

TEST(RenderCache, StoresAndLoadsFramesExactly) {
  testing::ScratchDir dir("render_cache");
  const double unit = 1e-4;
  const RenderCache cache(dir.path(), "key A", unit);
  EXPECT_FALSE(cache.has(3));
  const RenderedFrame f = frame(unit);
  cache.store(3, f);
  EXPECT_TRUE(cache.has(3));
  EXPECT_FALSE(cache.has(4));
  const RenderedFrame back = cache.load(3);
  EXPECT_EQ(back.depth, f.depth);
  EXPECT_EQ(back.labels, f.labels);
  EXPECT_EQ(back.intensity, f.intensity);
  // Re-opening with the same key finds the frame; another key gets another folder.
  EXPECT_TRUE(RenderCache(dir.path(), "key A", unit).has(3));
  const RenderCache other(dir.path(), "key B", unit);
  EXPECT_NE(other.folder(), cache.folder());
  EXPECT_FALSE(other.has(3));
}

TEST(RenderCache, DetectsAnEntryOfAnotherKey) {
  testing::ScratchDir dir("render_cache_collision");
  const RenderCache cache(dir.path(), "key A", 1e-4);
  testing::write_text(cache.folder() / "key.txt", "something else");
  const std::string msg = testing::error_message<IoError>([&] { RenderCache(dir.path(), "key A", 1e-4); });
  EXPECT_NE(msg.find("another key"), std::string::npos) << msg;
}

TEST(RenderCache, HashIsStable) {
  // FNV-1a 64 reference values: the cache layout must not change between builds or platforms.
  EXPECT_EQ(stable_hash_hex(""), "cbf29ce484222325");
  EXPECT_EQ(stable_hash_hex("a"), "af63dc4c8601ec8c");
}

}  // namespace
}  // namespace navaid::simulation
