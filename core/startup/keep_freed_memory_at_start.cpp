// Linked (as an object) into the test and benchmark programs: they run with the heap setting of
// the navaid CLI (navaid/core/allocator.hpp), so that their times are what `navaid run` sees.
#include "navaid/core/allocator.hpp"

namespace {
const bool kFreedMemoryKept = navaid::keep_freed_memory();
}  // namespace
