#include "synthetic_cache.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <thread>

#include "synth/dataset.h"

namespace plslam::test {

std::string syntheticSequence(synth::SceneKind kind, int frames) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "plslam_tests" /
                       (std::string("synth_") + synth::sceneKindName(kind) + "_" + std::to_string(frames));
  fs::create_directories(dir.parent_path());
  const std::string lock_path = dir.string() + ".lock";
  const int fd = ::open(lock_path.c_str(), O_CREAT | O_RDWR, 0644);
  if (fd >= 0) ::flock(fd, LOCK_EX);
  // rgb.txt is written last (atomically), so its presence means the folder is complete.
  if (!fs::exists(dir / "rgb.txt")) {
    synth::SceneOptions options;
    options.frames = frames;
    synth::DatasetOptions write;
    write.threads = 2;
    synth::writeDataset(synth::makeScene(kind, options), dir.string(), write);
  }
  if (fd >= 0) {
    ::flock(fd, LOCK_UN);
    ::close(fd);
  }
  return dir.string();
}

RenderedSequence renderSequence(synth::SceneKind kind, const synth::SceneOptions& options) {
  RenderedSequence s{synth::makeScene(kind, options), {}};
  s.frames.resize(options.frames);
  std::vector<std::thread> workers;
  for (int t = 0; t < 2; ++t)
    workers.emplace_back([&s, t, n = options.frames] {
      for (int i = t; i < n; i += 2) s.frames[i] = synth::render(s.scene, i);
    });
  for (auto& w : workers) w.join();
  return s;
}

}  // namespace plslam::test
