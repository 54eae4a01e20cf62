// libFuzzer entry point; PLSLAM_FUZZ_TARGET names the target in fuzz_targets.cpp.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/log.h"
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  plslam::setLogLevel(plslam::LogLevel::kOff);  // the parsers' warnings would drown the fuzzer's output
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const plslam::fuzz::Target* target = plslam::fuzz::findTarget(PLSLAM_FUZZ_TARGET);
  if (!target) std::abort();
  plslam::fuzz::runOne(*target, std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
