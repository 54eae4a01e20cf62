// Helpers shared by the tests: where ../shared is, scratch folders, and the skip macro.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

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

/// The outcome of running a shell command.
struct CommandResult {
  int status = -1;     ///< exit code; -1 when it did not exit normally
  std::string output;  ///< stdout and stderr together
};
/// Runs `command` through the shell, capturing stdout (and stderr with `with_stderr`).
CommandResult runCommand(const std::string& command, bool with_stderr = true);
/// Runs the built `plslam` with `arguments`.
CommandResult runPlslam(const std::string& arguments, bool with_stderr = true);
/// Starts `plslam run --dataset DATA --calib DATA/camera.xml --out OUT --quiet EXTRA...` as a
/// child process and returns its pid, for tests that signal it; the caller waits for it.
int startPlslamRun(const std::string& data, const std::string& out, const std::vector<std::string>& extra = {});
/// The whole content of a file ("" when it cannot be read).
std::string readFile(const std::string& path);
/// `text` parsed as JSON; a test failure naming `what` (and null) when it is not JSON.
nlohmann::json parseJson(const std::string& text, const std::string& what = "text");
/// The JSON file at `path` (see parseJson).
nlohmann::json readJson(const std::string& path);
}  // namespace plslam::test
