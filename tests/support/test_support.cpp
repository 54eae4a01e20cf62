#include "support/test_support.h"

#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace plslam::test {

bool pathExists(const std::string& path) { return fs::exists(path); }

std::string sharedDir() {
  const char* env = std::getenv("PLSLAM_SHARED_DIR");
  const std::string dir = env && *env ? env : PLSLAM_DEFAULT_SHARED_DIR;
  return fs::is_directory(dir) ? fs::canonical(dir).string() : std::string();
}

std::string sourceDir() { return PLSLAM_SOURCE_DIR; }
std::string binaryDir() { return PLSLAM_BINARY_DIR; }

std::string scratchDir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = tag;
  if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  const fs::path dir = fs::temp_directory_path() / "plslam_tests" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

}  // namespace plslam::test
