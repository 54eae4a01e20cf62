#include "support/test_support.h"

#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

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

CommandResult runCommand(const std::string& command, bool with_stderr) {
  CommandResult r;
  FILE* p = popen((with_stderr ? command + " 2>&1" : command).c_str(), "r");
  if (!p) return r;
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof(buf), p)) > 0;) r.output.append(buf, n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

CommandResult runPlslam(const std::string& arguments, bool with_stderr) {
  return runCommand(binaryDir() + "/plslam " + arguments, with_stderr);
}

int startPlslamRun(const std::string& data, const std::string& out, const std::vector<std::string>& extra) {
  std::vector<std::string> args = {binaryDir() + "/plslam", "run", "--dataset", data, "--calib", data + "/camera.xml",
                                   "--out", out, "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  const pid_t pid = fork();
  if (pid != 0) return pid;  // the parent, or -1
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(argv[0], argv.data());
  _exit(127);
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

nlohmann::json parseJson(const std::string& text, const std::string& what) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    ADD_FAILURE() << what << " is not JSON (" << e.what() << "):\n" << text;
    return nullptr;
  }
}

nlohmann::json readJson(const std::string& path) { return parseJson(readFile(path), path); }

}  // namespace plslam::test
