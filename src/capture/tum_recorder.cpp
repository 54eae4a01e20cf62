#include "capture/tum_recorder.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "camera/camera_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/time.h"

namespace plslam {

namespace fs = std::filesystem;

namespace {

const Logger kLog("capture");

std::FILE* openList(const std::string& path, const char* header) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw IoError("recorder: cannot create " + path);
  std::fputs(header, f);
  std::fflush(f);
  return f;
}

}  // namespace

TumRecorder::TumRecorder(std::string dir, PinholeCamera camera, RecorderOptions options)
    : dir_(std::move(dir)), camera_(std::move(camera)), options_(options) {
  std::error_code ec;
  fs::create_directories(fs::path(dir_) / "rgb", ec);
  if (!ec) fs::create_directories(fs::path(dir_) / "depth", ec);
  if (ec) throw IoError("recorder: cannot create " + dir_ + ": " + ec.message());
  if (fs::exists(fs::path(dir_) / "rgb.txt")) throw IoError("recorder: " + dir_ + " already holds a recording (rgb.txt)");
  saveCameraFile(dir_ + "/camera.xml", camera_, "recorded by plslam");
  rgb_list_ = openList(dir_ + "/rgb.txt", "# color images\n# recorded by plslam\n# timestamp filename\n");
  depth_list_ = openList(dir_ + "/depth.txt", "# depth maps\n# recorded by plslam\n# timestamp filename\n");
  if (options_.background) {
    queue_ = std::make_unique<BoundedQueue<RgbdFrame>>(options_.queue, QueuePolicy::kBlock);
    writer_ = std::thread([this] {
      while (auto frame = queue_->pop()) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          if (failure_) continue;  // drain without writing after a failure
        }
        try {
          write(*frame);
        } catch (...) {
          std::lock_guard<std::mutex> lock(mutex_);
          failure_ = std::current_exception();
        }
      }
    });
  }
}

TumRecorder::~TumRecorder() {
  try {
    close();
  } catch (const std::exception& e) {
    kLog.error(str("recorder: ", e.what()));
  }
}

void TumRecorder::rethrowFailure() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (failure_) {
    std::exception_ptr f = failure_;
    failure_ = nullptr;
    std::rethrow_exception(f);
  }
}

void TumRecorder::add(const RgbdFrame& frame) {
  if (closed_) throw IoError("recorder: add() after close(): " + dir_);
  checkImageSize(camera_, frame.bgr.cols, frame.bgr.rows, "recorded colour frame " + frame.name);
  checkImageSize(camera_, frame.depth_m.cols, frame.depth_m.rows, "recorded depth frame " + frame.name);
  rethrowFailure();
  if (queue_) {
    queue_->push(deepCopy(frame));  // the grabber may reuse its buffers
  } else {
    write(frame);
  }
}

void TumRecorder::write(const RgbdFrame& frame) {
  const std::string stamp = formatSecondsStamp(frame.t_ns);
  const std::string rgb = "rgb/" + stamp + ".png", depth = "depth/" + stamp + ".png";
  const std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, options_.png_compression};
  if (!cv::imwrite(dir_ + "/" + rgb, frame.bgr, params)) throw IoError("recorder: cannot write " + dir_ + "/" + rgb);
  if (!cv::imwrite(dir_ + "/" + depth, metresToDepth(frame.depth_m, camera_.depth_scale), params))
    throw IoError("recorder: cannot write " + dir_ + "/" + depth);
  // Depth first: a list line always names files that exist, and rgb.txt never runs ahead.
  if (std::fprintf(depth_list_, "%s %s\n", stamp.c_str(), depth.c_str()) < 0 || std::fflush(depth_list_) != 0 ||
      std::fprintf(rgb_list_, "%s %s\n", stamp.c_str(), rgb.c_str()) < 0 || std::fflush(rgb_list_) != 0)
    throw IoError("recorder: cannot append to the lists of " + dir_);
  std::lock_guard<std::mutex> lock(mutex_);
  ++written_;
}

void TumRecorder::close() {
  if (closed_) return;
  closed_ = true;
  if (queue_) {
    queue_->close();
    if (writer_.joinable()) writer_.join();
  }
  if (rgb_list_) std::fclose(rgb_list_);
  if (depth_list_) std::fclose(depth_list_);
  rgb_list_ = depth_list_ = nullptr;
  rethrowFailure();
  kLog.info(str("recorded ", written(), " frames into ", dir_));
}

int TumRecorder::written() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return written_;
}

}  // namespace plslam
