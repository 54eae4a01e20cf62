// Every committed input of fuzz/corpus/<target>/ (seeds and the inputs that once crashed a
// parser) through the same target functions the fuzzers run, in the ordinary build: a
// fixed crash stays fixed even where clang and libFuzzer are absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "core/log.h"
#include "fuzz_targets.h"
#include "support/test_support.h"

namespace fs = std::filesystem;
using namespace plslam;

TEST(FuzzCorpus, EveryTargetHasSeedsAndEveryInputIsParsedOrRefusedWithATypedError) {
  setLogLevel(LogLevel::kOff);
  const fs::path corpus = fs::path(test::sourceDir()) / "fuzz" / "corpus";
  ASSERT_TRUE(fs::is_directory(corpus)) << corpus;
  for (const fuzz::Target& t : fuzz::targets()) {
    const fs::path dir = corpus / t.name;
    ASSERT_TRUE(fs::is_directory(dir)) << "no seed corpus for fuzz target " << t.name;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    EXPECT_FALSE(files.empty()) << dir;
    int accepted = 0;
    for (const fs::path& f : files) {
      SCOPED_TRACE(f.string());
      // Anything but a plslam::Error escaping (or a crash) fails the test.
      accepted += fuzz::runOne(t, test::readFile(f.string()));
    }
    // Seeds are meant to be mostly valid, so the fuzzers start deep inside the parsers.
    EXPECT_GT(accepted, 0) << "no input of " << dir << " is accepted";
  }
}

TEST(FuzzCorpus, TruncationsOfEverySeedAreParsedOrRefused) {
  setLogLevel(LogLevel::kOff);
  const fs::path corpus = fs::path(test::sourceDir()) / "fuzz" / "corpus";
  for (const fuzz::Target& t : fuzz::targets()) {
    if (!fs::is_directory(corpus / t.name)) continue;
    for (const auto& e : fs::directory_iterator(corpus / t.name)) {
      const std::string bytes = test::readFile(e.path().string());
      SCOPED_TRACE(e.path().string());
      // A handful of cut points per seed, plus one flipped byte: cheap, deterministic.
      for (size_t k = 1; k <= 8; ++k) {
        const size_t n = bytes.size() * k / 9;
        fuzz::runOne(t, bytes.substr(0, n));
        std::string flipped = bytes;
        if (!flipped.empty()) flipped[n % flipped.size()] ^= static_cast<char>(0x5a);
        fuzz::runOne(t, flipped);
      }
    }
  }
}

// ------------------------------------------------------------ fuzzing findings, fixed
// Each crash the fuzzers found: its input is in fuzz/corpus/<target>/crash-*, replayed
// above; these tests state the fixed behaviour directly.

#include "core/time.h"
#include "io/trajectory_file.h"

// fuzz_tum_list, crash-stamp-int64-overflow: a 11-digit seconds stamp overflowed int64
// nanoseconds in parseSecondsStamp (UBSan: signed multiplication overflow).
TEST(FuzzFindings, StampsBeyondInt64NanosecondsAreNotStamps) {
  TimeNs t = 0;
  EXPECT_TRUE(parseSecondsStamp("9000000000.999999", &t));
  EXPECT_EQ(t, 9'000'000'000'999'999'000LL);
  EXPECT_FALSE(parseSecondsStamp("9000000001", &t));
  EXPECT_FALSE(parseSecondsStamp("13050311020.175304", &t));
  EXPECT_FALSE(parseSecondsStamp("99999999999999999999", &t));
}

// fuzz_trajectory, crash-exponent-stamp-out-of-range: "3e10" (not a plain decimal) went
// through secondsToNs and overflowed the double-to-int64 conversion (UBSan).
TEST(FuzzFindings, TrajectoryLineWithAnOutOfRangeExponentStampIsSkipped) {
  TrajectoryReadReport report;
  const Trajectory t = parseTumTrajectory("3e10 1 2 3 0 0 0 1\n-4e12 1 2 3 0 0 0 1\n3e0 1 2 3 0 0 0 1\n", "t.txt", &report);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].t_ns, 3 * kNsPerSecond);
  EXPECT_EQ(report.skipped_malformed, 2);
}
