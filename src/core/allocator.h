// How the process's allocator treats memory that a frame frees.
#pragma once

namespace plslam {

/// Makes the C allocator keep freed memory for the next frame instead of handing it back
/// to the kernel. Call once at the start of a program, before its threads start.
///
/// Why: glibc gives the top of a thread's arena back to the kernel on every free, so each
/// frame's large buffers (OpenCV's LSD allocates about 5 MB a call on the line thread) are
/// page-faulted in afresh, page by page. On this project's 2-core machines that doubled LSD's
/// time on some runs (docs/RESULTS.md, "Freed memory kept for the next frame"). The cost is
/// that the process keeps up to 64 MB per arena that it no longer uses.
///
/// Does nothing where the C library is not glibc. Returns whether the settings were taken.
bool keepFreedMemoryForReuse();

}  // namespace plslam
