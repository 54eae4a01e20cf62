#include "core/allocator.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

// The sanitizers bring their own allocator, which ignores mallopt.
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)

namespace plslam {
namespace {

long minorPageFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// The buffers of one LSD call on a 640 x 480 frame at half scale (double images at full and
// half size, its list of pixels), each written once and freed: what the line thread does.
constexpr size_t kFrameBuffers[] = {640 * 480 * 8, 320 * 240 * 8, 320 * 240 * 8, 320 * 240 * 8, 320 * 240 * 16};

size_t bytesPerFrame() {
  size_t total = 0;
  for (size_t s : kFrameBuffers) total += s;
  return total;
}

void oneFramesBuffers() {
  std::vector<char*> buffers;
  for (size_t size : kFrameBuffers) {
    auto* p = static_cast<char*>(std::malloc(size));
    ASSERT_NE(p, nullptr);
    std::memset(p, 1, size);
    buffers.push_back(p);
  }
  for (char* p : buffers) std::free(p);
}

TEST(Allocator, AWorkerThreadsFreedFrameBuffersAreNotFaultedInAgain) {
  ASSERT_TRUE(keepFreedMemoryForReuse());
  // Each frame on a new thread, as std::async runs the line extraction. Without the setting,
  // glibc trims the thread arena's top on every free and each frame faults in all its pages
  // again (about 1300 of 4 KB here).
  std::thread([] { oneFramesBuffers(); }).join();
  const long before = minorPageFaults();
  constexpr int kFrames = 5;
  for (int i = 0; i < kFrames; ++i) std::thread([] { oneFramesBuffers(); }).join();
  const long pages_touched = kFrames * static_cast<long>(bytesPerFrame() / 4096);
  EXPECT_LT(minorPageFaults() - before, pages_touched / 10);
}

}  // namespace
}  // namespace plslam

#endif
