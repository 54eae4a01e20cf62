// plslam calib: camera calibration tools (src/calibration).
//   render      synthetic target images with a known camera, to try the others
//   intrinsics  intrinsics + distortion from views of a chessboard or an AprilTag grid
//   depth       depth scale and offset against the board's plane
//   base        camera-to-base transform of a robot from views of a tag at a known pose
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "args.h"
#include "calibration/base_transform.h"
#include "calibration/depth_check.h"
#include "calibration/detect.h"
#include "calibration/intrinsics.h"
#include "calibration/render.h"
#include "calibration/target.h"
#include "camera/camera_file.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"

namespace fs = std::filesystem;

namespace plslam::cli {

namespace {

using namespace plslam::calib;

constexpr const char* kTargetHelp =
    "chessboard:COLSxROWS:SQUARE_M (inner corners), aprilgrid:COLSxROWS:TAG_M:SPACING_M[:FIRST_ID] (tag36h11) "
    "or tag:ID:SIZE_M";

/// The camera `calib render` uses when none is given: 640x480 with visible distortion.
PinholeCamera exampleCamera() {
  PinholeCamera c;
  c.name = "example_truth";
  c.width = 640;
  c.height = 480;
  c.fx = 520.0;
  c.fy = 515.0;
  c.cx = 322.5;
  c.cy = 243.0;
  c.dist = {-0.12, 0.08, 0.0012, -0.0008, 0.0};
  c.depth_scale = 1000;
  return c;
}

/// Image files of a folder (png, jpg, jpeg, bmp, tif, tiff), sorted by name.
std::vector<fs::path> imageFiles(const std::string& dir, const std::string& what) {
  if (!fs::is_directory(dir)) throw IoError(what + " '" + dir + "' is not a folder");
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tif" || ext == ".tiff"))
      out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  if (out.empty()) throw IoError(what + " '" + dir + "' holds no image (png, jpg, bmp, tif)");
  return out;
}

void writeImage(const std::string& path, const cv::Mat& img) {
  if (!cv::imwrite(path, img)) throw IoError(path + ": cannot write image");
}

std::string poseLine(const std::string& name, const SE3& T) {
  const Eigen::Vector3d& t = T.translation();
  const Eigen::Quaterniond& q = T.quaternion();
  return str(name, " ", cv::format("%.9f %.9f %.9f %.9f %.9f %.9f %.9f", t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()), "\n");
}

/// Detects the target in every image of `dir`, printing one line per view.
std::vector<ViewResult> detectFolder(const std::vector<fs::path>& files, const TargetDetector& det, cv::Size& size) {
  std::vector<ViewResult> views;
  for (const fs::path& f : files) {
    const cv::Mat img = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    ViewResult v;
    if (img.empty()) {
      v.name = f.filename().string();
      v.status = ViewStatus::kUnreadable;
      v.reason = "cannot read the image";
    } else {
      if (size.area() == 0) size = img.size();
      if (img.size() != size)
        throw DataError(str(f.string(), ": image is ", img.cols, "x", img.rows, ", the first was ", size.width, "x", size.height));
      v = det.detect(img, f.filename().string());
    }
    views.push_back(std::move(v));
  }
  return views;
}

void printView(const ViewResult& v, const std::string& extra = "") {
  if (v.accepted()) {
    std::cout << "  " << v.name << ": accepted (" << v.reason << extra << ")\n";
  } else {
    std::cout << "  " << v.name << ": REJECTED: " << v.reason << "\n";
  }
}

double pct(double est, double truth) { return 100.0 * (est - truth) / truth; }

// ---------------------------------------------------------------------------------------

void declareRenderOptions(Args& args) {
  args.option("out", "output folder", "", true)
      .option("target", kTargetHelp, "aprilgrid:6x6:0.04:0.012")
      .option("camera", "camera file of the simulated camera [default: 640x480, fx 520, with distortion]")
      .option("views", "number of views", "15")
      .option("seed", "seed of the poses and the noise", "1")
      .option("blur", "Gaussian blur sigma, pixels", "0.5")
      .option("noise", "Gaussian intensity noise sigma, grey levels", "2")
      .option("supersampling", "sub-samples per pixel side (anti-aliasing)", "4")
      .flag("bad-views", "add two bad views: bad_blurred.png (rejected as too blurry) and bad_cut.png, the target half "
                         "out of view (a chessboard view is rejected; an aprilgrid view keeps its whole tags)")
      .flag("depth", "also write depth/ (16-bit PNG, the camera's depth scale) of the board's plane as a wall")
      .option("depth-scale-error", "simulated depth error: measured = SCALE * true + OFFSET", "1.0")
      .option("depth-offset", "OFFSET of the simulated depth error, metres", "0.0")
      .option("depth-noise", "depth noise sigma, metres", "0.002")
      .option("camera-to-base", "render the base-calibration scene instead: true camera pose in the base frame "
                                "x,y,z,roll,pitch,yaw (metres, degrees); needs --tag-pose")
      .option("tag-pose", "target centre pose in the base frame x,y,z,roll,pitch,yaw (metres, degrees)")
      .epilog(
          "Writes OUT/colour/view_NN.png, OUT/truth_camera.xml, OUT/truth_poses.txt (name, T_c_board as\n"
          "tx ty tz qx qy qz qw) and with --depth OUT/depth/view_NN.png; with --camera-to-base, views of the\n"
          "fixed tag (noise differs) and OUT/truth_camera_to_base.yaml. Examples:\n"
          "  plslam calib render --out /tmp/cal --target chessboard:9x6:0.03 --bad-views\n"
          "  plslam calib intrinsics --images /tmp/cal/colour --target chessboard:9x6:0.03 --out /tmp/cal/cam.xml \\\n"
          "      --truth /tmp/cal/truth_camera.xml\n"
          "  plslam calib render --out /tmp/base --target tag:0:0.12 --views 8 \\\n"
          "      --camera-to-base 0.09,0.01,0.18,-102,0,-90 --tag-pose 0.45,0.02,0.15,-90,0,-80");
}

/// The views' names and board poses: random poses around the target, or with --camera-to-base
/// the one pose of the base-calibration scene for every view (its truth file written).
std::vector<std::pair<std::string, SE3>> renderViewPoses(Args& args, const Target& target, const PinholeCamera& cam,
                                                         int n, uint32_t seed, const std::string& out) {
  std::vector<std::pair<std::string, SE3>> views;
  auto name = [](int i) { return cv::format("view_%02d.png", i); };
  if (args.has("camera-to-base")) {
    if (!args.has("tag-pose")) throw ConfigError("plslam calib render: --camera-to-base needs --tag-pose");
    CameraToBase truth;
    truth.T_b_c = parsePoseXyzRpyDeg(args.str("camera-to-base"), "--camera-to-base");
    const SE3 T_b_tag = parsePoseXyzRpyDeg(args.str("tag-pose"), "--tag-pose");
    const SE3 T_c_board = truth.T_b_c.inverse() * T_b_tag * target.boardFromTarget().inverse();
    if (!targetInView(target, cam, T_c_board, 2))
      throw ConfigError("plslam calib render: with these poses the target is not wholly in view of the camera");
    for (int i = 0; i < n; ++i) views.emplace_back(name(i), T_c_board);
    truth.views = n;
    saveCameraToBase(out + "/truth_camera_to_base.yaml", truth, "truth of plslam calib render");
  } else {
    const std::vector<SE3> poses = makeViewPoses(target, cam, n, seed);
    for (int i = 0; i < n; ++i) views.emplace_back(name(i), poses[i]);
  }
  return views;
}

/// bad_blurred.png (too blurry) and bad_cut.png (the target half out of view); their pose lines.
std::string renderBadViews(const Target& target, const PinholeCamera& cam, uint32_t seed, const RenderOptions& ro,
                           const std::string& out) {
  std::string pose_text;
  const SE3 pose = makeViewPoses(target, cam, 1, seed + 7777)[0];
  RenderOptions blurred = ro;
  blurred.blur_sigma = 4.0;
  writeImage(out + "/colour/bad_blurred.png", renderTarget(target, cam, pose, blurred));
  pose_text += poseLine("bad_blurred.png", pose);
  SE3 cut = pose;
  while (targetInView(target, cam, cut)) cut = SE3(Eigen::Quaterniond::Identity(), {0.01, 0, 0}) * cut;
  cut = SE3(Eigen::Quaterniond::Identity(), {0.5 * target.patternArea().width, 0, 0}) * cut;
  writeImage(out + "/colour/bad_cut.png", renderTarget(target, cam, cut, ro));
  pose_text += poseLine("bad_cut.png", cut);
  return pose_text;
}

int runRender(int argc, char** argv) {
  Args args("calib render", "Render synthetic target images seen by a known camera (to try plslam calib).");
  declareRenderOptions(args);
  if (!args.parse(argc, argv)) return 0;
  const Target target = Target::parse(args.str("target"));
  const PinholeCamera cam = args.has("camera") ? loadCameraFile(args.str("camera")) : exampleCamera();
  const int n = args.integer("views", 1, 1000);
  const uint32_t seed = static_cast<uint32_t>(args.integer("seed", 0, 1 << 30));
  const std::string out = args.str("out");
  fs::create_directories(out + "/colour");
  const bool depth = args.has("depth");
  if (depth) fs::create_directories(out + "/depth");

  RenderOptions ro;
  ro.blur_sigma = args.number("blur");
  ro.noise_sigma = args.number("noise");
  ro.supersampling = args.integer("supersampling", 1, 16);
  DepthRenderOptions dro;
  dro.scale = args.number("depth-scale-error");
  dro.offset = args.number("depth-offset");
  dro.noise_sigma = args.number("depth-noise");

  const std::vector<std::pair<std::string, SE3>> views = renderViewPoses(args, target, cam, n, seed, out);
  std::string pose_text = "# name tx ty tz qx qy qz qw: T_c_board, the board in the camera frame (metres)\n";
  for (size_t i = 0; i < views.size(); ++i) {
    RenderOptions o = ro;
    o.seed = seed * 1000 + static_cast<uint32_t>(i);
    writeImage(out + "/colour/" + views[i].first, renderTarget(target, cam, views[i].second, o));
    if (depth) {
      DepthRenderOptions d = dro;
      d.seed = o.seed;
      writeImage(out + "/depth/" + views[i].first, metresToDepth(renderPlaneDepth(cam, views[i].second, d), cam.depth_scale));
    }
    pose_text += poseLine(views[i].first, views[i].second);
  }
  if (args.has("bad-views")) pose_text += renderBadViews(target, cam, seed, ro, out);
  writeFileAtomically(out + "/truth_poses.txt", pose_text);
  saveCameraFile(out + "/truth_camera.xml", cam, "truth of plslam calib render");
  std::cout << "wrote " << views.size() << (args.has("bad-views") ? " + 2 bad" : "") << " views of " << target.spec()
            << " to " << out << "/colour" << (depth ? " (and depth/)" : "") << ", truth in " << out << "/truth_*\n";
  return 0;
}

// ---------------------------------------------------------------------------------------

int runIntrinsics(int argc, char** argv) {
  Args args("calib intrinsics", "Calibrate intrinsics and distortion from views of a target.");
  args.option("images", "folder of target views (png, jpg, bmp, tif; sorted by name)", "", true)
      .option("target", kTargetHelp, "", true)
      .option("out", "camera file to write (ViSP XML + plslam <rgbd>), e.g. calib/my_camera.xml", "", true)
      .option("model", "distortion coefficients: none, k1, k1k2, k1k2p1p2, k1k2p1p2k3", "k1k2p1p2k3")
      .option("name", "camera name in the file", "calibrated")
      .option("depth-scale", "depth image units per metre written to the file (D435i: 1000, TUM: 5000)", "1000")
      .option("min-views", "fewest accepted views", "5")
      .option("min-sharpness", "reject views less sharp than this (variance of the Laplacian)", "25")
      .option("min-tags", "aprilgrid: fewest tags per view", "4")
      .flag("sector-detector", "chessboard: also try OpenCV's findChessboardCornersSB on views the classic detector "
                               "misses (finds more blurred boards; seconds per failed view)")
      .option("truth", "camera file of the true camera (synthetic views): print the errors")
      .epilog(
          "Take 15-25 views: the whole target sharp, at several distances, tilted 20-45 degrees, and near\n"
          "every image corner. Example:\n"
          "  plslam calib intrinsics --images shots/ --target chessboard:9x6:0.025 --out calib/my_camera.xml");
  if (!args.parse(argc, argv)) return 0;
  const Target target = Target::parse(args.str("target"));
  DetectionOptions dopt;
  dopt.min_sharpness = args.number("min-sharpness");
  dopt.min_tags = args.integer("min-tags", 1, 1000);
  dopt.chessboard_sb_fallback = args.has("sector-detector");
  IntrinsicsOptions iopt;
  iopt.model = parseDistortionModel(args.str("model"));
  iopt.camera_name = args.str("name");
  iopt.depth_scale = args.number("depth-scale");
  iopt.min_views = args.integer("min-views", 3, 10000);
  const std::vector<fs::path> files = imageFiles(args.str("images"), "--images");
  TargetDetector det(target, dopt);
  cv::Size size;
  std::cout << "detecting " << target.spec() << " in " << files.size() << " images of " << args.str("images") << "\n";
  std::vector<ViewResult> views = detectFolder(files, det, size);
  const IntrinsicsResult r = calibrateIntrinsics(std::move(views), size, iopt);
  std::cout << "views:\n";
  for (size_t i = 0; i < r.views.size(); ++i)
    printView(r.views[i], std::isnan(r.view_rms_px[i]) ? "" : cv::format(", RMS %.3f px", r.view_rms_px[i]));
  const PinholeCamera& c = r.camera;
  std::cout << cv::format("result: %d of %zu views used, reprojection RMS %.3f px, image coverage %.0f %%, %d tilted views\n",
                          r.views_used, r.views.size(), r.rms_px, 100 * r.coverage, r.tilted_views)
            << cv::format("  fx %.3f +- %.3f  fy %.3f +- %.3f  cx %.3f +- %.3f  cy %.3f +- %.3f\n", c.fx, r.std_dev[0], c.fy,
                          r.std_dev[1], c.cx, r.std_dev[2], c.cy, r.std_dev[3])
            << cv::format("  distortion (%s): k1 %.5f k2 %.5f p1 %.6f p2 %.6f k3 %.5f\n", distortionModelName(r.model),
                          c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4]);
  if (args.has("truth")) {
    const PinholeCamera t = loadCameraFile(args.str("truth"));
    std::cout << cv::format("  vs truth: fx %+.3f %%  fy %+.3f %%  cx %+.3f %%  cy %+.3f %%  dk1 %+.5f dk2 %+.5f dp1 %+.6f dp2 %+.6f dk3 %+.5f\n",
                            pct(c.fx, t.fx), pct(c.fy, t.fy), pct(c.cx, t.cx), pct(c.cy, t.cy), c.dist[0] - t.dist[0],
                            c.dist[1] - t.dist[1], c.dist[2] - t.dist[2], c.dist[3] - t.dist[3], c.dist[4] - t.dist[4]);
  }
  for (const std::string& g : r.guidance) std::cout << "hint: " << g << "\n";
  saveCalibration(args.str("out"), r, target);
  std::cout << "wrote " << args.str("out") << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------

int runDepth(int argc, char** argv) {
  Args args("calib depth", "Fit the depth error (measured = scale * true + offset) against the board's plane.");
  args.option("colour", "folder of colour views of the board", "", true)
      .option("depth", "folder of depth images registered to them (16-bit PNG, same file names)", "", true)
      .option("camera", "calibrated camera file (plslam calib intrinsics)", "", true)
      .option("target", kTargetHelp, "", true)
      .option("depth-scale", "depth image units per metre [default: the camera file's]")
      .option("stride", "use every N-th pixel", "2")
      .epilog(
          "Hold the board flat (or on a wall) at several distances, 0.4 m to 2 m, some views tilted.\n"
          "Example:\n"
          "  plslam calib depth --colour shots/colour --depth shots/depth --camera calib/my_camera.xml \\\n"
          "      --target aprilgrid:6x6:0.04:0.012");
  if (!args.parse(argc, argv)) return 0;
  const Target target = Target::parse(args.str("target"));
  const PinholeCamera cam = loadCameraFile(args.str("camera"));
  const double depth_scale = args.has("depth-scale") ? args.number("depth-scale") : cam.depth_scale;
  if (!(depth_scale > 0)) throw ConfigError("plslam calib depth: --depth-scale must be positive");
  TargetDetector det(target);
  std::vector<DepthView> views;
  std::cout << "views:\n";
  for (const fs::path& f : imageFiles(args.str("colour"), "--colour")) {
    const cv::Mat img = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    ViewResult v = img.empty() ? ViewResult{} : det.detect(img, f.filename().string());
    v.name = f.filename().string();
    if (img.empty()) {
      v.status = ViewStatus::kUnreadable;
      v.reason = "cannot read the image";
    }
    const fs::path dpath = fs::path(args.str("depth")) / f.filename();
    const cv::Mat raw = v.accepted() ? cv::imread(dpath.string(), cv::IMREAD_ANYDEPTH) : cv::Mat();
    if (v.accepted() && (raw.empty() || raw.type() != CV_16UC1)) {
      v.status = ViewStatus::kNoDepth;
      v.reason = dpath.string() + " is missing or not a 16-bit depth PNG";
    }
    if (v.accepted()) {
      checkImageSize(cam, img.cols, img.rows, f.string());
      checkImageSize(cam, raw.cols, raw.rows, dpath.string());
      double rms = 0;
      const SE3 T = estimateBoardPose(v.observation, cam, &rms);
      views.push_back({v.name, depthToMetres(raw, depth_scale), T});
      printView(v, cv::format(", board at %.2f m, PnP RMS %.2f px", T.translation().norm(), rms));
    } else {
      printView(v);
    }
  }
  const DepthFit fit = fitDepthScaleOffset(views, cam, target);
  for (const std::string& note : fit.view_notes) std::cout << "  depth " << note << "\n";
  std::cout << cv::format("result: measured = %.5f * true %+.5f m, residual RMS %.4f m over %d pixels of %d views, "
                          "true depth %.2f-%.2f m\n",
                          fit.scale, fit.offset, fit.rms_m, fit.pixels, fit.views, fit.min_true_m, fit.max_true_m);
  std::cout << cv::format("  to correct: true = (measured %+.5f) / %.5f; at 1 m the error is %+.1f mm\n", -fit.offset,
                          fit.scale, 1000 * (fit.scale - 1 + fit.offset));
  std::cout << cv::format("  to apply it (run, live, the ROS node): a configuration with\n"
                          "    calibration:\n      depth_scale: %.5f\n      depth_offset_m: %.5f\n",
                          fit.scale, fit.offset);
  for (const std::string& g : fit.guidance) std::cout << "hint: " << g << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------

int runBase(int argc, char** argv) {
  Args args("calib base", "Camera-to-base transform of a robot from views of a tag at a known pose in the base frame.");
  args.option("images", "folder of views of the tag taken by the robot's camera", "", true)
      .option("camera", "calibrated camera file (plslam calib intrinsics)", "", true)
      .option("target", "the tag (tag:ID:SIZE_M) or any target", "", true)
      .option("tag-pose", "pose of the target centre in the base frame: x,y,z,roll,pitch,yaw (metres, degrees; "
                          "R = Rz(yaw) Ry(pitch) Rx(roll); target axes x right, y down, z into it)", "", true)
      .option("out", "camera-to-base file to write (YAML, format in src/calibration/base_transform.h)", "", true)
      .option("truth", "true camera-to-base file (synthetic views): print the error")
      .epilog(
          "An upright tag facing the robot, 40 cm ahead and 15 cm up: --tag-pose 0.40,0,0.15,-90,0,-90.\n"
          "Example:\n"
          "  plslam calib base --images shots/ --camera calib/my_camera.xml --target tag:0:0.12 \\\n"
          "      --tag-pose 0.40,0,0.15,-90,0,-90 --out calib/camera_to_base.yaml");
  if (!args.parse(argc, argv)) return 0;
  const Target target = Target::parse(args.str("target"));
  const PinholeCamera cam = loadCameraFile(args.str("camera"));
  const SE3 T_b_target = parsePoseXyzRpyDeg(args.str("tag-pose"), "--tag-pose");
  DetectionOptions dopt;
  dopt.min_tags = 1;
  dopt.min_area_fraction = 0.002;  // one tag may be small in the image
  TargetDetector det(target, dopt);
  cv::Size size;
  const std::vector<ViewResult> views = detectFolder(imageFiles(args.str("images"), "--images"), det, size);
  checkImageSize(cam, size.width, size.height, args.str("images"));
  std::vector<SE3> T_c_target;
  std::cout << "views:\n";
  for (const ViewResult& v : views) {
    if (!v.accepted()) {
      printView(v);
      continue;
    }
    double rms = 0;
    const SE3 T = estimateBoardPose(v.observation, cam, &rms) * target.boardFromTarget();
    T_c_target.push_back(T);
    printView(v, cv::format(", target at %.3f m, PnP RMS %.2f px", T.translation().norm(), rms));
  }
  const CameraToBase c = cameraToBase(T_c_target, T_b_target);
  const Eigen::Vector3d t = c.T_b_c.translation(), rpy = rpyFromRotation(c.T_b_c.rotation()) * 180 / M_PI;
  std::cout << cv::format("result: T_b_c translation %.4f %.4f %.4f m, rpy %.3f %.3f %.3f deg, from %d views "
                          "(spread %.2f mm, %.3f deg)\n",
                          t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z(), c.views, 1000 * c.spread_t_m, c.spread_r_deg);
  if (args.has("truth")) {
    const SE3 truth = loadCameraToBase(args.str("truth"));
    std::cout << cv::format("  vs truth: translation error %.2f mm, rotation error %.3f deg\n",
                            1000 * (t - truth.translation()).norm(), (truth.inverse() * c.T_b_c).angle() * 180 / M_PI);
  }
  if (c.spread_t_m > 0.005 || c.spread_r_deg > 0.5)
    std::cout << "hint: the views disagree: is the tag fixed, flat and its size right? Keep the robot still.\n";
  saveCameraToBase(args.str("out"), c,
                   str("plslam calib base: target ", target.spec(), ", tag pose ", args.str("tag-pose"), ", ", c.views, " views"));
  std::cout << "wrote " << args.str("out") << " (use it: plslam run/live/servo --base " << args.str("out")
            << ", or the ROS node's _camera_to_base)\n";
  return 0;
}

int runCalib(int argc, char** argv) {
  const std::map<std::string, int (*)(int, char**)> subs = {
      {"render", runRender}, {"intrinsics", runIntrinsics}, {"depth", runDepth}, {"base", runBase}};
  const std::string usage =
      "usage: plslam calib <render|intrinsics|depth|base> [options]   (plslam calib <sub> --help)\n"
      "  render      synthetic target images with a known camera, to try the others\n"
      "  intrinsics  intrinsics + distortion from views of a chessboard or an AprilTag grid -> camera XML\n"
      "  depth       depth scale and offset against the board's plane\n"
      "  base        camera-to-base transform of a robot from views of a tag at a known pose\n";
  if (argc < 1 || std::string(argv[0]) == "--help" || std::string(argv[0]) == "-h") {
    (argc < 1 ? std::cerr : std::cout) << usage;
    return argc < 1 ? 2 : 0;
  }
  const auto it = subs.find(argv[0]);
  if (it == subs.end()) throw ConfigError(str("plslam calib: unknown subcommand '", argv[0], "'\n", usage));
  return it->second(argc - 1, argv + 1);
}

}  // namespace

Command makeCalibCommand() {
  return {"calib", "calibrate a camera: intrinsics, depth scale/offset, camera-to-base (render: synthetic views)", runCalib};
}

}  // namespace plslam::cli
