#include "synth/dataset.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <thread>

#include "camera/camera_file.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "io/trajectory_file.h"
#include "synth/renderer.h"

namespace fs = std::filesystem;

namespace plslam::synth {

namespace {

const Logger kLog("synth");

void writePng(const std::string& path, const cv::Mat& image, int compression) {
  std::vector<uchar> buf;
  // RLE suits these images best (noisy colour and depth, mostly-zero masks): smaller and faster than the default.
  if (!cv::imencode(".png", image, buf,
                    {cv::IMWRITE_PNG_COMPRESSION, compression, cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_RLE}))
    throw IoError(path + ": cannot encode PNG");
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
  out.close();
  if (!out) throw IoError(path + ": cannot write");
}

void makeDir(const fs::path& p) {
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec || !fs::is_directory(p)) throw IoError(p.string() + ": cannot create folder (" + ec.message() + ")");
}

std::string indexFile(const std::string& what, const std::vector<std::pair<std::string, std::string>>& rows) {
  std::ostringstream os;
  os << "# " << what << "\n# file: 'plslam synth'\n# timestamp filename\n";
  for (const auto& [stamp, file] : rows) os << stamp << " " << file << "\n";
  return os.str();
}

cv::Vec3b instanceColour(int id) {
  static const cv::Vec3b kColours[] = {{60, 60, 255}, {255, 120, 40}, {40, 220, 60}, {230, 60, 230}, {0, 220, 255}, {255, 255, 0}};
  return kColours[(id - 1) % 6];
}

/// Renders and writes every frame's images, on options.threads threads; the first failure
/// stops the others and is rethrown. Returns each frame's exposure row (fast scene).
std::vector<std::string> renderFrames(const Scene& scene, const fs::path& root, const std::vector<std::string>& stamps,
                                      const std::vector<std::string>& depth_stamps, const DatasetOptions& options) {
  const int n = scene.frameCount();
  const double scale = scene.camera().depth_scale;
  std::vector<std::string> exposure_rows(n);  // fast scene: what the colour of each frame went through
  std::atomic<int> next{0}, done{0};
  std::mutex mutex;
  std::exception_ptr failure;
  auto worker = [&]() {
    try {
      for (int i = next++; i < n; i = next++) {
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (failure) return;
        }
        const RenderedFrame f = render(scene, i);
        exposure_rows[i] = str(stamps[i], " ", f.gain, " ", f.subframes);
        writePng((root / "rgb" / (stamps[i] + ".png")).string(), f.bgr, options.png_compression);
        writePng((root / "depth" / (depth_stamps[i] + ".png")).string(), metresToDepth(f.depth_m, scale),
                 options.png_compression);
        if (options.write_masks)
          writePng((root / "masks" / (stamps[i] + ".png")).string(), f.instance_ids, options.png_compression);
        const int d = ++done;
        if (options.progress) {
          std::lock_guard<std::mutex> lock(mutex);
          options.progress(d, n);
        }
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!failure) failure = std::current_exception();
    }
  };
  const int threads = std::clamp(options.threads, 1, 64);
  if (threads == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  if (failure) std::rethrow_exception(failure);
  return exposure_rows;
}

/// masks/instances.txt and masks.txt.
void writeMaskFiles(const Scene& scene, const fs::path& root,
                    const std::vector<std::pair<std::string, std::string>>& mask_rows) {
  std::ostringstream inst;
  inst << "# instance_id class_id class_name (COCO class ids; 0 in a mask = static background)\n";
  for (const auto& m : scene.movingObjects()) inst << m.instance_id << " " << m.class_id << " " << m.class_name << "\n";
  writeFileAtomically((root / "masks" / "instances.txt").string(), inst.str());
  writeFileAtomically((root / "masks.txt").string(), indexFile("instance masks (16-bit ids)", mask_rows));
}

/// exposure.txt of the fast scene.
void writeExposureFile(const Scene& scene, const fs::path& root, const std::vector<std::string>& exposure_rows) {
  std::ostringstream os;
  os << "# exposure gain and motion-blur sub-frames per colour image (exposure "
     << nsToSeconds(scene.exposureNs()) * 1e3 << " ms centred on the stamp; 1 sub-frame = sharp)\n"
     << "# timestamp gain subframes\n";
  for (const std::string& row : exposure_rows) os << row << "\n";
  writeFileAtomically((root / "exposure.txt").string(), os.str());
}

}  // namespace

void writeDataset(const Scene& scene, const std::string& dir, const DatasetOptions& options) {
  if (options.png_compression < 0 || options.png_compression > 9)
    throw ConfigError(str("synthetic dataset: png_compression must be 0..9, got ", options.png_compression));
  const fs::path root(dir);
  makeDir(root / "rgb");
  makeDir(root / "depth");
  if (options.write_masks) makeDir(root / "masks");
  const int n = scene.frameCount();
  std::vector<std::string> stamps(n), depth_stamps(n);
  for (int i = 0; i < n; ++i) {
    stamps[i] = formatSecondsStamp(scene.frameTime(i));
    depth_stamps[i] = formatSecondsStamp(scene.frameTime(i) + options.depth_offset_ns);
  }
  const std::vector<std::string> exposure_rows = renderFrames(scene, root, stamps, depth_stamps, options);

  std::vector<std::pair<std::string, std::string>> rgb_rows, depth_rows, mask_rows;
  for (int i = 0; i < n; ++i) {
    rgb_rows.push_back({stamps[i], "rgb/" + stamps[i] + ".png"});
    depth_rows.push_back({depth_stamps[i], "depth/" + depth_stamps[i] + ".png"});
    mask_rows.push_back({stamps[i], "masks/" + stamps[i] + ".png"});
  }
  saveCameraFile((root / "camera.xml").string(), scene.camera(), "plslam synthetic scene camera");
  writeFileAtomically((root / "scene.txt").string(), scene.describe());
  writeTumTrajectory((root / "groundtruth.txt").string(), scene.groundTruth(),
                     str("ground truth of the synthetic '", sceneKindName(scene.kind()), "' scene, seed ",
                         scene.options().seed, " (T_w_c)"));
  if (options.write_masks) writeMaskFiles(scene, root, mask_rows);
  if (scene.kind() == SceneKind::kFast) writeExposureFile(scene, root, exposure_rows);
  writeFileAtomically((root / "depth.txt").string(), indexFile("depth maps", depth_rows));
  writeFileAtomically((root / "rgb.txt").string(), indexFile("color images", rgb_rows));
  kLog.info(str("wrote ", n, " frames of the '", sceneKindName(scene.kind()), "' scene to ", dir));
}

cv::Mat colourDepth(const cv::Mat& depth_m, double max_depth_m) {
  cv::Mat grey(depth_m.size(), CV_8UC1), invalid(depth_m.size(), CV_8UC1);
  for (int y = 0; y < depth_m.rows; ++y)
    for (int x = 0; x < depth_m.cols; ++x) {
      const float d = depth_m.at<float>(y, x);
      invalid.at<uchar>(y, x) = std::isfinite(d) ? 0 : 255;
      grey.at<uchar>(y, x) = std::isfinite(d) ? cv::saturate_cast<uchar>(255.0 * d / max_depth_m) : 0;
    }
  cv::Mat out;
  cv::applyColorMap(grey, out, cv::COLORMAP_JET);
  out.setTo(cv::Scalar::all(0), invalid);
  return out;
}

cv::Mat overlayInstances(const cv::Mat& bgr, const cv::Mat& instance_ids) {
  cv::Mat out = bgr.clone();
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x) {
      const int id = instance_ids.at<uint16_t>(y, x);
      if (id == 0) continue;
      cv::Vec3b& p = out.at<cv::Vec3b>(y, x);
      const cv::Vec3b c = instanceColour(id);
      for (int k = 0; k < 3; ++k) p[k] = static_cast<uchar>((p[k] + c[k]) / 2);
    }
  return out;
}

std::vector<int> previewFrames(const Scene& scene) {
  const int n = scene.frameCount();
  std::vector<int> frames;
  for (int k = 0; k < 3; ++k) frames.push_back(std::min(n - 1, (2 * k + 1) * n / 6));
  if (scene.movingObjects().empty() || n < 3) return frames;
  // Pick, in each third, the frame where the moving objects cover most of a small render.
  SceneOptions small = scene.options();
  small.width = 80;
  small.height = 60;
  small.aa_samples = 1;
  small.noise.enabled = false;
  const Scene probe = makeScene(scene.kind(), small);
  std::vector<int> cover(n);
  for (int i = 0; i < n; ++i) cover[i] = cv::countNonZero(render(probe, i).instance_ids);
  for (int k = 0; k < 3; ++k) {
    // The middle 80% of each third, so that the three frames are apart.
    const int b0 = k * n / 3, e0 = std::max(b0 + 1, (k + 1) * n / 3), margin = (e0 - b0) / 10;
    const int b = b0 + margin, e = e0 - margin;
    frames[k] = static_cast<int>(std::max_element(cover.begin() + b, cover.begin() + e) - cover.begin());
  }
  return frames;
}

cv::Mat makePreview(const Scene& scene, std::vector<int> frames) {
  if (frames.empty()) frames = previewFrames(scene);
  const int w = scene.camera().width / 2, h = scene.camera().height / 2;
  cv::Mat sheet(h * static_cast<int>(frames.size()), w * 3, CV_8UC3, cv::Scalar::all(0));
  for (size_t r = 0; r < frames.size(); ++r) {
    const RenderedFrame f = render(scene, frames[r]);
    const cv::Mat tiles[3] = {f.bgr, colourDepth(f.depth_m), overlayInstances(f.bgr, f.instance_ids)};
    const char* labels[3] = {"rgb", "depth 0-6 m", "instance masks"};
    for (int c = 0; c < 3; ++c) {
      cv::Mat cell = sheet(cv::Rect(c * w, static_cast<int>(r) * h, w, h));
      cv::resize(tiles[c], cell, cell.size(), 0, 0, cv::INTER_AREA);
      const std::string text = str(sceneKindName(scene.kind()), " #", frames[r], " ", labels[c]);
      cv::putText(cell, text, {6, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar::all(0), 3, cv::LINE_AA);
      cv::putText(cell, text, {6, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar::all(255), 1, cv::LINE_AA);
    }
  }
  return sheet;
}

void writePreview(const Scene& scene, const std::string& path, const std::vector<int>& frames) {
  const cv::Mat sheet = makePreview(scene, frames);
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) makeDir(parent);
  writePng(path, sheet, 6);
}

}  // namespace plslam::synth
