#pragma once
// Process-wide heap setting for steady per-frame work (docs/estimator.md, "Speed": freed memory).

namespace navaid {

/// Keeps freed heap memory in the process for the next frame instead of returning it to the
/// kernel: blocks below 32 MiB come from the heap (not a fresh mmap each time) and up to 512 MiB
/// of free heap top stays mapped. Every frame allocates and frees the same megabyte-sized images,
/// pyramids and solver matrices; handed back each time, each new one page-faults afresh, which on
/// a virtual machine cost more than the tracking itself (rendered lab-walk-1: front end mean 17 ->
/// 6 ms). Call once at program start, before threads start. Returns false where the C library has
/// no such settings (then nothing changes).
bool keep_freed_memory();

}  // namespace navaid
