// Helpers shared by the tests: where ../shared is, scratch folders, and the skip macro.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace plslam::test {

/// The shared/ folder (env PLSLAM_SHARED_DIR, else the configured default); empty when absent.
std::string sharedDir();
/// The source tree root (for calib/ files).
std::string sourceDir();
/// The build tree root (for the plslam executable).
std::string binaryDir();
/// A fresh, empty folder under the system temp folder, unique to this test.
std::string scratchDir(const std::string& tag);

}  // namespace plslam::test

/// Skips the current test visibly when shared/ (or a file under it) is not there.
#define PLSLAM_REQUIRE_SHARED(relative_path)                                                       \
  do {                                                                                            \
    if (::plslam::test::sharedDir().empty())                                                      \
      GTEST_SKIP() << "shared/ data folder not found (set PLSLAM_SHARED_DIR): skipped";           \
    if (!std::string(relative_path).empty() &&                                                    \
        !::plslam::test::pathExists(::plslam::test::sharedDir() + "/" + (relative_path)))         \
      GTEST_SKIP() << "shared/" << (relative_path) << " not found: skipped";                     \
  } while (0)

namespace plslam::test {
bool pathExists(const std::string& path);
}
