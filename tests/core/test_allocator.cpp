#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "navaid/core/allocator.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

// AddressSanitizer brings its own malloc: glibc's settings do not apply there.
#if defined(__SANITIZE_ADDRESS__)
#define NAVAID_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NAVAID_ASAN 1
#endif
#endif

namespace {

#if defined(__GLIBC__) && !defined(NAVAID_ASAN)
// A frame-sized block (a 640x480 float image) comes from the heap, not from a fresh mapping, and
// freeing it keeps the memory in the process.
TEST(KeepFreedMemory, FrameSizedBlocksStayInTheHeap) {
  ASSERT_TRUE(navaid::keep_freed_memory());
  constexpr std::size_t kBytes = 640 * 480 * sizeof(float);
  const struct mallinfo2 before = mallinfo2();
  void* block = std::malloc(kBytes);
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBytes);  // touched, as an image is
  const struct mallinfo2 held = mallinfo2();
  EXPECT_EQ(held.hblkhd, before.hblkhd) << "the block was mmapped";
  std::free(block);
  const struct mallinfo2 after = mallinfo2();
  EXPECT_GE(after.arena, held.arena) << "the heap was trimmed";
  EXPECT_GE(after.fordblks, kBytes) << "the freed block is not kept for reuse";
}
#elif defined(NAVAID_ASAN)
TEST(KeepFreedMemory, ReportsThatTheSettingIsUnavailableUnderAddressSanitizer) {
  EXPECT_FALSE(navaid::keep_freed_memory());
}
#else
TEST(KeepFreedMemory, ReportsThatTheSettingIsUnavailable) { EXPECT_FALSE(navaid::keep_freed_memory()); }
#endif

}  // namespace
