// The fuzz targets: one function per parser of outside input. Each takes the bytes of one
// input and must return normally or throw plslam::Error (the typed, named refusal); any
// other exception, a crash or a sanitizer report is a finding.
//
// The same functions run under libFuzzer (fuzz_main.cpp, clang, `fuzz` preset) and, in
// the ordinary test suite, over every committed input of fuzz/corpus/<target>/
// (tests/reliability/test_fuzz_corpus.cpp), so a crash once found stays fixed.
#pragma once

#include <string>
#include <vector>

namespace plslam::fuzz {

struct Target {
  const char* name;                         ///< also the folder under fuzz/corpus/
  void (*run)(const std::string& bytes);
};

/// The run configuration target (fuzz_config.cpp; listed when built with PLSLAM_FUZZ_WITH_CONFIG).
void config(const std::string& bytes);

/// Every target (the map file target only when src/mapfile is built).
const std::vector<Target>& targets();
/// The target called `name`, or nullptr.
const Target* findTarget(const std::string& name);

/// Runs target `name` on `bytes`, swallowing plslam::Error (an accepted refusal).
/// Returns false when the input was refused with a plslam::Error.
bool runOne(const Target& target, const std::string& bytes);

}  // namespace plslam::fuzz
