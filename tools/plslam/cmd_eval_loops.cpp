// plslam eval loops: precision-recall of place recognition against ground-truth loops.
//
// Every frame (or every --every-th) is described by its ORB and LBD bags of words (and its
// segmented instances with --segmenter). Ground truth: two frames show the same place when
// their camera positions are within --distance and their optical axes within --angle, and
// they are at least --min-gap seconds apart. Each query frame proposes its best-scoring
// earlier frame (at least --min-gap back), with the loop closer's score: the similarity
// normalised by the best similarity to the frames of the last second before the query (the
// stand-in for covisible keyframes). Sweeping a threshold on that score gives precision
// (correct proposals / proposals) and recall (correct proposals / queries that have a true
// match), for four variants: ORB only, LBD only, ORB+LBD, ORB+LBD+semantic.
//
// With --mask-dynamic the semantic variant keeps what a run with the same segmenter keeps:
// the features on potentially dynamic instances (persons...), grown by the dynamic mask's
// dilation, are dropped before its bags of words and its geometric verification, as the
// run's dynamic rejection drops a walker's, and those instances count as dynamic in the
// instance agreement. (A run decides per instance with the geometric check too: a still
// person is kept there; here the class prior alone decides.)
//
// The operating point is the loop closer's threshold (--threshold, default its
// loop.min_normalised_score). There each variant's appearance-only precision and recall are
// reported, and the full variant's proposals are also put through the loop closer's
// geometric verification (3D-3D RANSAC with depth, then with the lines fitted to depth),
// which is what decides in a run (its two-keyframe consistency check is not applied here).
// After verification a loop is false when its relative pose is wrong (--pose-tolerance-*):
// an accepted view just beyond the ground-truth radius, with the right pose, is an overlap
// and helps a correction.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "progress_line.h"
#include "camera/camera_file.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "core/log.h"
#include "dynamic/dynamic_mask.h"
#include "dynamic/segmenter.h"
#include "dynamic/semantic_labels.h"
#include "eval/precision_recall.h"
#include "frontend/feature_extraction.h"
#include "io/dataset.h"
#include "loop/loop_closer.h"
#include "mapping/line_reconstruction.h"
#include "run_session.h"

namespace plslam::cli {

namespace {

/// Features, lines fitted to depth (points use their keypoint depth) and bags of words.
struct FrameDescription {
  FrameFeatures features;
  FeatureGeometry geometry;
  KeyframeBow bow;
};

struct FrameInfo {
  TimeNs t_ns = 0;
  SE3 T_w_c;
  FrameDescription all;  ///< every feature
  /// Without the features on potentially dynamic instances (the semantic variant's); empty
  /// when no such instance is in view or without --mask-dynamic, and then `all` stands for it.
  std::optional<FrameDescription> off_dynamic;
  std::vector<KeyframeInstance> instances;

  const FrameDescription& semantic() const { return off_dynamic ? *off_dynamic : all; }
};

FrameDescription describeFrame(const RgbdFrame& frame, const cv::Mat& mask, const PinholeCamera& camera,
                               const VocabularySet& vocab) {
  FeatureOptions fo;
  fo.parallel = false;
  FrameDescription d;
  d.features = extractFeatures(frame, mask, camera, fo);
  // The loop closer verifies with map lines; here each line is fitted to this frame's depth.
  d.geometry.lines = segmentsFittedToDepth(d.features.lines, frame.depth_m, camera);
  d.bow = describeBow(vocab, d.features);
  return d;
}

/// CV_8U, 0 on the pixels of potentially dynamic instances grown by the dynamic mask's
/// dilation, 255 elsewhere; empty when there are none. Marks those instances dynamic.
cv::Mat potentiallyDynamicMask(const Segmentation& s, std::vector<InstanceDecision>* decisions) {
  cv::Mat dynamic_pixels = cv::Mat::zeros(s.instance_ids.size(), CV_8U);
  bool any = false;
  for (const Instance& in : s.instances) {
    InstanceDecision d;
    d.instance_id = in.id;
    d.class_id = in.class_id;
    d.class_name = in.class_name;
    d.dynamic = in.potentially_dynamic;
    decisions->push_back(d);
    if (!in.potentially_dynamic) continue;
    dynamic_pixels.setTo(255, s.instance_ids == in.id);
    any = true;
  }
  if (!any) return {};
  const int r = DynamicMaskOptions{}.dilate_px;
  cv::dilate(dynamic_pixels, dynamic_pixels, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  cv::Mat keep;
  cv::bitwise_not(dynamic_pixels, keep);
  return keep;
}

struct Curve {
  std::string name;
  std::vector<ScoredProposal> proposals;
  PrCurve pr;
  PrPoint at_threshold;  ///< appearance only
};

const SE3* groundTruthAt(const Trajectory& gt, TimeNs t, TimeNs max_diff) {
  const StampedPose* best = nullptr;
  for (const StampedPose& p : gt)
    if (std::llabs(p.t_ns - t) <= max_diff && (!best || std::llabs(p.t_ns - t) < std::llabs(best->t_ns - t))) best = &p;
  return best ? &best->T_w_c : nullptr;
}

void drawCurves(const std::string& path, const std::vector<Curve>& curves, const PrPoint& verified,
                const std::string& title) {
  const int W = 720, H = 560, L = 70, R = 20, T = 40, B = 60;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  auto px = [&](double recall, double precision) {
    return cv::Point(L + static_cast<int>(recall * (W - L - R)), H - B - static_cast<int>(precision * (H - T - B)));
  };
  for (int k = 0; k <= 10; ++k) {
    const double v = k / 10.0;
    cv::line(img, px(v, 0), px(v, 1), cv::Scalar(230, 230, 230));
    cv::line(img, px(0, v), px(1, v), cv::Scalar(230, 230, 230));
    char buf[16];
    std::snprintf(buf, sizeof(buf), "%.1f", v);
    cv::putText(img, buf, px(v, 0) + cv::Point(-10, 20), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
    cv::putText(img, buf, px(0, v) + cv::Point(-35, 5), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  }
  cv::rectangle(img, px(0, 1), px(1, 0), cv::Scalar(60, 60, 60));
  cv::putText(img, "recall", cv::Point(W / 2 - 20, H - 15), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  cv::putText(img, "precision", cv::Point(5, T - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  cv::putText(img, title, cv::Point(L + 60, T - 15), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  const cv::Scalar colours[] = {cv::Scalar(200, 80, 0), cv::Scalar(0, 140, 0), cv::Scalar(0, 0, 220), cv::Scalar(160, 0, 160)};
  for (size_t c = 0; c < curves.size(); ++c) {
    std::vector<cv::Point> poly;
    for (const PrPoint& p : curves[c].pr.points) poly.push_back(px(p.recall, p.precision));
    if (poly.size() > 1) cv::polylines(img, poly, false, colours[c % 4], 2, cv::LINE_AA);
    // The operating threshold on each curve.
    cv::circle(img, px(curves[c].at_threshold.recall, curves[c].at_threshold.precision), 5, colours[c % 4], 1, cv::LINE_AA);
    char buf[128];
    std::snprintf(buf, sizeof(buf), "%s (recall@P1 %.2f)", curves[c].name.c_str(), curves[c].pr.recall_at_precision_1);
    const cv::Point at(L + 15, H - B - 20 - 20 * static_cast<int>(curves.size() - 1 - c));
    cv::line(img, at + cv::Point(0, -4), at + cv::Point(25, -4), colours[c % 4], 2, cv::LINE_AA);
    cv::putText(img, buf, at + cv::Point(32, 0), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  }
  // The full variant after geometric verification: the run's operating point.
  const cv::Point v = px(verified.recall, verified.precision);
  cv::drawMarker(img, v, cv::Scalar(0, 0, 0), cv::MARKER_STAR, 14, 2, cv::LINE_AA);
  char buf[128];
  std::snprintf(buf, sizeof(buf), "* verified at threshold %.2f: P %.2f R %.2f", verified.threshold, verified.precision,
                verified.recall);
  cv::putText(img, buf, cv::Point(L + 15, H - B - 20 - 20 * static_cast<int>(curves.size())), cv::FONT_HERSHEY_SIMPLEX,
              0.45, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  std::vector<uchar> png;
  if (!cv::imencode(".png", img, png)) throw IoError(path + ": cannot encode the plot");
  writeFileAtomically(path, std::string(png.begin(), png.end()));
}

void declareEvalLoopsOptions(Args& args) {
  args.option("dataset", "RGB-D folder in the TUM layout with groundtruth.txt", "", true)
      .option("calib", "camera file (ViSP XML); default: <dataset>/camera.xml")
      .option("out", "output folder: pr.csv, pr.png, summary.json", "", true)
      .option("distance", "same place: camera positions within this distance, metres", "0.3")
      .option("angle", "same place: optical axes within this angle, degrees", "20")
      .option("min-gap", "pairs closer in time than this are not loops, seconds", "3")
      .option("every", "use every N-th frame", "1")
      .option("threshold", "operating threshold on the normalised score (default: the loop closer's)")
      .option("pose-tolerance-m", "a verified loop is false when its relative pose is off by more than this, metres", "0.1")
      .option("pose-tolerance-deg", "... or by more than this, degrees", "3")
      .option("vocab", "vocabulary file (default: the shipped one)")
      .option("segmenter", "instances for the semantic variant: none, replay (masks of the folder) or a YOLOv8-seg .onnx",
              "none")
      .flag("mask-dynamic", "semantic variant: drop the features on potentially dynamic instances (persons...) before "
                            "its bags of words and verification, as a run's dynamic rejection does")
      .epilog("example: plslam eval loops --dataset /tmp/loop --out /tmp/loop_pr");
}

struct EvalLoopsSettings {
  double distance = 0, angle_deg = 0, gap_s = 0, pose_tol_m = 0, pose_tol_deg = 0;
  int every = 1;
  std::string dir, out;
  bool mask_dynamic = false;
};

/// The parsed options, checked before the long pass over the frames.
EvalLoopsSettings readEvalLoopsSettings(Args& args) {
  EvalLoopsSettings c;
  c.distance = args.number("distance"), c.angle_deg = args.number("angle"), c.gap_s = args.number("min-gap");
  c.pose_tol_m = args.number("pose-tolerance-m"), c.pose_tol_deg = args.number("pose-tolerance-deg");
  for (const auto& [name, value] : {std::pair<const char*, double>{"distance", c.distance}, {"angle", c.angle_deg},
                                    {"pose-tolerance-m", c.pose_tol_m}, {"pose-tolerance-deg", c.pose_tol_deg}})
    if (!(value > 0)) throw ConfigError(str("plslam eval loops: --", name, " must be positive, got ", value));
  c.every = args.integer("every", 1, 10000);
  c.dir = args.str("dataset"), c.out = args.str("out");
  c.mask_dynamic = args.has("mask-dynamic");
  if (c.mask_dynamic && args.str("segmenter") == "none") throw ConfigError("plslam eval loops: --mask-dynamic needs --segmenter");
  return c;
}

SegmenterOptions evalSegmenterOptions(const std::string& seg, const TumDataset& dataset) {
  SegmenterOptions so;
  if (seg == "none" || seg == "replay") so.kind = parseSegmenterKind(seg);
  else so.kind = SegmenterKind::kYolo, so.yolo.model_path = seg;
  so.replay_labels = replayLabels(dataset);
  return so;
}

/// Every --every-th frame with a ground-truth pose, described (and segmented when a segmenter is given).
std::vector<FrameInfo> describeFrames(TumDataset& dataset, const PinholeCamera& camera, const VocabularySet& vocab,
                                      SegmenterKind kind, Segmenter* segmenter, const EvalLoopsSettings& c) {
  std::vector<FrameInfo> frames;
  RgbdFrame frame;
  ProgressLine line("eval loops");
  for (size_t i = 0; i < dataset.size(); i += c.every) {
    if (dataset.load(i, &frame) != FrameStatus::kOk) continue;
    const SE3* T = groundTruthAt(dataset.groundtruth(), frame.t_ns, 20'000'000LL);
    if (!T) continue;
    FrameInfo f;
    f.t_ns = frame.t_ns;
    f.T_w_c = *T;
    f.all = describeFrame(frame, cv::Mat(), camera, vocab);
    if (kind != SegmenterKind::kNone) {
      const Segmentation segmentation = segmenter->segment(frame);
      std::vector<InstanceDecision> decisions;  // potentially dynamic instances are dynamic (with --mask-dynamic)
      const cv::Mat keep = potentiallyDynamicMask(segmentation, &decisions);
      if (!keep.empty() && c.mask_dynamic) f.off_dynamic = describeFrame(frame, keep, camera, vocab);
      f.instances = describeInstances(segmentation, c.mask_dynamic ? decisions : std::vector<InstanceDecision>{},
                                      frame.depth_m, camera);
    }
    frames.push_back(std::move(f));
    line.update("frame %zu/%zu", i + 1, dataset.size());
  }
  line.done();
  return frames;
}

struct Verified {
  int accepted = 0, right_pose = 0, same_place = 0;
  double worst_right_t_m = 0;
};

/// Each frame as a query against the earlier ones: the four variants' proposals, and the
/// geometric verification of the semantic variant's proposals at the threshold.
class LoopQueries {
 public:
  LoopQueries(const std::vector<FrameInfo>& frames, const PinholeCamera& camera, const EvalLoopsSettings& c,
              double threshold)
      : frames_(frames), camera_(camera), c_(c), threshold_(threshold),
        gap_(static_cast<TimeNs>(c.gap_s * kNsPerSecond)),
        cos_angle_(std::cos(c.angle_deg * M_PI / 180.0)),
        diagonal_(std::hypot(camera.width, camera.height)),
        pose_tol_rad_(c.pose_tol_deg * M_PI / 180) {
    curves.resize(4);
    for (int v = 0; v < 4; ++v) curves[v].name = std::vector<std::string>{"ORB", "LBD", "ORB+LBD", "ORB+LBD+semantic"}[v];
  }

  void run() {
    for (size_t i = 0; i < frames_.size(); ++i) query(i);
  }

  std::vector<Curve> curves;
  Verified verified;
  int queries_with_truth = 0, verifications = 0;

 private:
  bool samePlace(const FrameInfo& a, const FrameInfo& b) const {
    const Eigen::Vector3d za = a.T_w_c.rotation() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d zb = b.T_w_c.rotation() * Eigen::Vector3d::UnitZ();
    return (a.T_w_c.translation() - b.T_w_c.translation()).norm() < c_.distance && za.dot(zb) > cos_angle_;
  }

  // Variant 4 (v == 3) on the semantic descriptions; `appearance_only` leaves out its
  // instance factor (the reference score: covisible keyframes are not weighed either).
  double variantScore(int v, const FrameInfo& a, const FrameInfo& b, bool appearance_only = false) const {
    const KeyframeBow& ba = v == 3 ? a.semantic().bow : a.all.bow;
    const KeyframeBow& bb = v == 3 ? b.semantic().bow : b.all.bow;
    const double so_ = bowScore(ba.orb, bb.orb), sl = bowScore(ba.lbd, bb.lbd);
    if (v == 0) return so_;
    if (v == 1) return sl;
    double s = combinedScore(so_, sl, !ba.lbd.empty() && !bb.lbd.empty(), lo_);
    if (v == 3 && !appearance_only && !a.instances.empty() && !b.instances.empty())
      s *= matchInstances(a.instances, b.instances, diagonal_, lo_.semantic).factor;
    return s;
  }

  void query(size_t i) {
    const FrameInfo& q = frames_[i];
    bool has_truth = false, has_candidate = false;
    for (size_t j = 0; j < i; ++j)
      if (q.t_ns - frames_[j].t_ns >= gap_) {
        has_candidate = true;
        has_truth = has_truth || samePlace(q, frames_[j]);
      }
    if (!has_candidate) return;
    queries_with_truth += has_truth;
    for (int v = 0; v < 4; ++v) {
      size_t best_j = 0;
      const ScoredProposal p = propose(v, i, &best_j);
      if (v == 3 && p.score >= threshold_) {
        verify(q, frames_[best_j], p);
        ++verifications;
      }
      curves[v].proposals.push_back(p);
    }
  }

  /// The best-scoring frame at least the gap back, its score normalised by the best of the last second.
  ScoredProposal propose(int v, size_t i, size_t* best_j) const {
    const FrameInfo& q = frames_[i];
    double reference = 0;
    for (size_t j = 0; j < i; ++j)
      if (q.t_ns - frames_[j].t_ns <= kNsPerSecond) reference = std::max(reference, variantScore(v, q, frames_[j], true));
    double best = -1;
    for (size_t j = 0; j < i; ++j) {
      if (q.t_ns - frames_[j].t_ns < gap_) continue;
      const double s = variantScore(v, q, frames_[j]);
      if (s > best) best = s, *best_j = j;
    }
    return ScoredProposal{reference > 0 ? best / reference : best, samePlace(q, frames_[*best_j])};
  }

  void verify(const FrameInfo& q, const FrameInfo& cand, const ScoredProposal& p) {
    LoopCandidate c;
    const FrameDescription &qs = q.semantic(), &cs = cand.semantic();
    verifyGeometry(qs.features, cs.features, camera_, lo_, &c, nullptr, &qs.geometry, &cs.geometry);
    if (c.status != LoopStatus::kAccepted) return;
    // A false loop is one whose verified relative pose is wrong: an accepted view just
    // beyond the ground-truth radius (an overlap at 25 degrees) with the right pose is not.
    const SE3 err = (q.T_w_c.inverse() * cand.T_w_c).inverse() * c.T_query_candidate;
    const bool right = err.translation().norm() < c_.pose_tol_m &&
                       err.quaternion().angularDistance(Eigen::Quaterniond::Identity()) < pose_tol_rad_;
    ++verified.accepted;
    verified.right_pose += right;
    verified.same_place += p.correct;
    if (right) verified.worst_right_t_m = std::max(verified.worst_right_t_m, err.translation().norm());
  }

  const std::vector<FrameInfo>& frames_;
  const PinholeCamera& camera_;
  const EvalLoopsSettings& c_;
  const double threshold_;
  const TimeNs gap_;
  const double cos_angle_, diagonal_, pose_tol_rad_;
  const LoopOptions lo_;
};

/// Each variant's P-R curve and operating point into the CSV, the JSON and the console.
void reportCurves(std::vector<Curve>& curves, int queries_with_truth, double threshold, std::ostringstream& csv,
                  Json& json) {
  for (size_t v = 0; v < curves.size(); ++v) {
    Curve& c = curves[v];
    c.pr = precisionRecall(c.proposals, queries_with_truth);
    c.at_threshold = operatingPoint(c.proposals, queries_with_truth, threshold);
    for (const PrPoint& p : c.pr.points)
      csv << c.name << "," << p.threshold << "," << p.precision << "," << p.recall << "," << p.true_positives << ","
          << p.false_positives << "\n";
    json["variants"][c.name] = {{"recall_at_precision_1", c.pr.recall_at_precision_1},
                                {"precision_at_threshold", c.at_threshold.precision},
                                {"recall_at_threshold", c.at_threshold.recall},
                                {"proposals", c.proposals.size()}};
    std::printf("%-18s recall at precision 1.0: %.3f; at threshold %.2f: precision %.3f recall %.3f  (%d queries with a "
                "true loop, %zu proposals)\n",
                c.name.c_str(), c.pr.recall_at_precision_1, threshold, c.at_threshold.precision, c.at_threshold.recall,
                queries_with_truth, c.proposals.size());
  }
}

/// Precision: right relative poses / accepted; recall: accepted same places / true loops.
PrPoint verifiedPoint(const Verified& verified, int queries_with_truth, double threshold) {
  PrPoint at_verified;
  at_verified.threshold = threshold;
  at_verified.true_positives = verified.right_pose;
  at_verified.false_positives = verified.accepted - verified.right_pose;
  at_verified.precision = verified.accepted ? static_cast<double>(verified.right_pose) / verified.accepted : 1.0;
  at_verified.recall = queries_with_truth ? static_cast<double>(verified.same_place) / queries_with_truth : 0.0;
  return at_verified;
}

/// The console summary and pr.csv, summary.json, pr.png.
void reportEvalLoops(const EvalLoopsSettings& c, size_t frame_count, int with_instances, double threshold,
                     LoopQueries& queries) {
  std::ostringstream csv;
  csv << "variant,threshold,precision,recall,true_positives,false_positives\n";
  Json json = {{"dataset", c.dir},
               {"frames", frame_count},
               {"queries_with_true_loop", queries.queries_with_truth},
               {"frames_with_instances", with_instances},
               {"distance_m", c.distance},
               {"angle_deg", c.angle_deg},
               {"min_gap_s", c.gap_s},
               {"variants", Json::object()}};
  std::vector<Curve>& curves = queries.curves;
  reportCurves(curves, queries.queries_with_truth, threshold, csv, json);
  const Verified& verified = queries.verified;
  const PrPoint at_verified = verifiedPoint(verified, queries.queries_with_truth, threshold);
  const double semantic_margin = minPrecisionMargin(curves[3].pr, curves[2].pr);
  json["threshold"] = threshold;
  json["verified_at_threshold"] = {{"precision", at_verified.precision},
                                   {"recall", at_verified.recall},
                                   {"verifications", queries.verifications},
                                   {"accepted", verified.accepted},
                                   {"right_pose", verified.right_pose},
                                   {"same_place", verified.same_place},
                                   {"worst_right_translation_m", verified.worst_right_t_m}};
  json["semantic_min_precision_margin"] = semantic_margin;
  std::printf("ORB+LBD+semantic, verified at threshold %.2f: precision %.3f recall %.3f (%d verified, %d accepted, %d "
              "with the right relative pose, %d within the ground-truth radius)\n",
              threshold, at_verified.precision, at_verified.recall, queries.verifications, verified.accepted,
              verified.right_pose, verified.same_place);
  std::printf("semantic vs ORB+LBD: minimum precision margin over the curve %+.3f (>= 0: at least as good everywhere)\n",
              semantic_margin);
  std::filesystem::create_directories(c.out);
  writeFileAtomically(c.out + "/pr.csv", csv.str());
  writeFileAtomically(c.out + "/summary.json", jsonText(json));
  drawCurves(c.out + "/pr.png", curves, at_verified, std::filesystem::path(c.dir).filename().string() + ": loop detection P-R");
  std::printf("outputs: %s/pr.csv pr.png summary.json\n", c.out.c_str());
}

}  // namespace

int runEvalLoops(int argc, char** argv) {
  Args args("eval loops", "Precision-recall of loop detection (place recognition) against ground-truth poses.");
  declareEvalLoopsOptions(args);
  if (!args.parse(argc, argv)) return 0;
  const EvalLoopsSettings c = readEvalLoopsSettings(args);
  const PinholeCamera camera = loadCameraFile(args.has("calib") ? args.str("calib") : c.dir + "/camera.xml");
  TumDataset dataset = TumDataset::open(c.dir, camera);
  if (!dataset.hasGroundtruth()) throw IoError(c.dir + ": no groundtruth.txt; eval loops needs ground-truth poses");
  const VocabularySet vocab = loadVocabulary(args.has("vocab") ? args.str("vocab") : defaultVocabularyPath());

  const SegmenterOptions so = evalSegmenterOptions(args.str("segmenter"), dataset);
  std::unique_ptr<Segmenter> segmenter = makeSegmenter(so);
  const std::vector<FrameInfo> frames = describeFrames(dataset, camera, vocab, so.kind, segmenter.get(), c);
  if (frames.size() < 2) throw DataError(c.dir + ": fewer than two frames with ground truth");

  int with_instances = 0;
  for (const FrameInfo& f : frames) with_instances += !f.instances.empty();
  std::printf("%zu frames, %d with segmented instances\n", frames.size(), with_instances);
  const double threshold = args.has("threshold") ? args.number("threshold") : LoopOptions().min_normalised_score;
  LoopQueries queries(frames, camera, c, threshold);
  queries.run();
  reportEvalLoops(c, frames.size(), with_instances, threshold, queries);
  return 0;
}

}  // namespace plslam::cli
