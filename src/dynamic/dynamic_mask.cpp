#include "dynamic/dynamic_mask.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

const char* instanceDecisionReasonName(InstanceDecisionReason reason) {
  switch (reason) {
    case InstanceDecisionReason::kMovingByGeometry: return "moving_by_geometry";
    case InstanceDecisionReason::kStillByGeometry: return "still_by_geometry";
    case InstanceDecisionReason::kClassPrior: return "class_prior";
    case InstanceDecisionReason::kStaticClass: return "static_class";
  }
  return "unknown";
}

namespace {

template <typename Polygon>
void fillPolygon(cv::Mat* area, const Polygon& polygon) {
  std::vector<cv::Point> pts;
  for (const auto& p : polygon) pts.emplace_back(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
  if (!pts.empty()) cv::fillConvexPoly(*area, pts, cv::Scalar(255));
}

void dilate(cv::Mat* area, int radius_px) {
  if (radius_px <= 0) return;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius_px + 1, 2 * radius_px + 1));
  cv::dilate(*area, *area, kernel);
}

void validateEvidence(const DynamicEvidence& ev, size_t n, const MotionCheckResult* motion, const Segmentation* seg,
                      cv::Size size) {
  if (size.width <= 0 || size.height <= 0) throw DataError(str("dynamic mask: bad image size ", size.width, "x", size.height));
  if (motion && (motion->moving.size() != n || motion->evidence.size() != n))
    throw DataError(str("dynamic mask: the motion check has ", motion->moving.size(), " flags for ", n, " correspondences"));
  if (ev.delaunay && (ev.delaunay->moving.size() != n || ev.delaunay->in_graph.size() != n))
    throw DataError(str("dynamic mask: the Delaunay result has ", ev.delaunay->moving.size(), " flags for ", n,
                        " correspondences"));
  if (seg && (seg->instance_ids.type() != CV_16UC1 || seg->instance_ids.size() != size))
    throw DataError(str("dynamic mask: the instance label image is ", seg->instance_ids.cols, "x", seg->instance_ids.rows,
                        " type ", seg->instance_ids.type(), ", expected CV_16UC1 ", size.width, "x", size.height));
}

/// Per-feature evidence: the geometric check first, else the Delaunay graph (-1 unknown, 0 still, 1 moving).
std::vector<int8_t> featureMotion(size_t n, const MotionCheckResult* motion, const DelaunayMotionResult* graph,
                                  DynamicMaskResult* res) {
  std::vector<int8_t> moving(n, -1);
  for (size_t i = 0; i < n; ++i) {
    if (motion && motion->evidence[i] != MotionEvidence::kNone) moving[i] = motion->moving[i];
    else if (graph && graph->in_graph[i]) moving[i] = graph->moving[i];
    if (moving[i] >= 0) ++res->stats.features_checked;
  }
  return moving;
}

/// The instance id under each feature's current pixel (0 without labels or outside the image).
std::vector<int> featureLabels(const std::vector<MotionCorrespondence>& corr, const cv::Mat* labels, cv::Size size) {
  if (labels && (labels->type() != CV_16UC1 || labels->size() != size))
    throw DataError("dynamic mask: the feature labels differ from the instance label image in size or type");
  const size_t n = corr.size();
  std::vector<int> label(n, 0);
  if (labels) {
    for (size_t i = 0; i < n; ++i) {
      const auto& uv = corr[i].uv_cur;
      if (!uv.allFinite()) continue;
      const int x = static_cast<int>(std::lround(uv.x())), y = static_cast<int>(std::lround(uv.y()));
      if (x >= 0 && y >= 0 && x < size.width && y < size.height) label[i] = labels->at<uint16_t>(y, x);
    }
  }
  return label;
}

/// An instance is dynamic by the geometry of its checked features when it has enough of them,
/// else by its class.
InstanceDecision decideInstance(const Instance& inst, const std::vector<int>& label, const std::vector<int8_t>& moving,
                                const DynamicMaskOptions& o) {
  InstanceDecision d;
  d.instance_id = inst.id;
  d.class_id = inst.class_id;
  d.class_name = inst.class_name;
  for (size_t i = 0; i < label.size(); ++i) {
    if (label[i] != inst.id) continue;
    ++d.features;
    if (moving[i] < 0) continue;
    ++d.checked;
    d.moving += moving[i];
  }
  if (d.checked >= o.min_checked_features) {
    const bool moves = d.moving >= o.min_moving_features && d.moving >= o.moving_fraction * d.checked;
    if (!moves) d.reason = InstanceDecisionReason::kStillByGeometry;
    else if (inst.potentially_dynamic || o.static_classes_can_move) d.reason = InstanceDecisionReason::kMovingByGeometry;
    else d.reason = InstanceDecisionReason::kStaticClass;
    d.dynamic = d.reason == InstanceDecisionReason::kMovingByGeometry;
  } else {
    d.dynamic = inst.potentially_dynamic;
    d.reason = d.dynamic ? InstanceDecisionReason::kClassPrior : InstanceDecisionReason::kStaticClass;
  }
  return d;
}

/// Instances: decided, and the dynamic ones painted into the area and their features flagged.
void addInstances(const Segmentation& seg, const std::vector<int>& label, const std::vector<int8_t>& moving,
                  const DynamicMaskOptions& o, cv::Mat* dynamic_area, DynamicMaskResult* res) {
  res->stats.instances = static_cast<int>(seg.instances.size());
  for (const Instance& inst : seg.instances) {
    InstanceDecision d = decideInstance(inst, label, moving, o);
    if (d.dynamic) {
      ++res->stats.instances_dynamic;
      dynamic_area->setTo(255, seg.instance_ids == inst.id);
      for (size_t i = 0; i < label.size(); ++i)
        if (label[i] == inst.id) res->feature_dynamic[i] = 1;
    }
    res->instances.push_back(std::move(d));
  }
}

/// Delaunay regions outside the instances, unless the geometric check contradicts them.
void addRegions(const std::vector<MovingRegion>& regions, const std::vector<int>& label, const MotionCheckResult* motion,
                const DynamicMaskOptions& o, cv::Mat* dynamic_area, DynamicMaskResult* res) {
  const size_t n = label.size();
  for (size_t r = 0; r < regions.size(); ++r) {
    RegionDecision d;
    d.region = static_cast<int>(r);
    int on_instances = 0;
    for (int i : regions[r].features) {
      if (i < 0 || static_cast<size_t>(i) >= n) throw DataError(str("dynamic mask: region feature ", i, " out of range"));
      on_instances += label[i] != 0;
      if (motion && motion->evidence[i] != MotionEvidence::kNone) {
        ++d.checked;
        d.moving += motion->moving[i];
      }
    }
    if (on_instances >= o.region_inside_fraction * regions[r].features.size()) {
      d.reason = RegionDecisionReason::kInsideInstance;
    } else if (d.checked >= o.region_min_checked && d.moving < o.region_min_moving_fraction * d.checked) {
      d.reason = RegionDecisionReason::kContradictedByGeometry;
    } else {
      d.dynamic = true;
      d.reason = RegionDecisionReason::kAccepted;
      ++res->stats.regions_dynamic;
      // The triangles the region covers; the hull only when it has none (a thin chain).
      for (const auto& t : regions[r].triangles) fillPolygon(dynamic_area, t);
      if (regions[r].triangles.empty()) fillPolygon(dynamic_area, regions[r].hull);
      for (int i : regions[r].features) res->feature_dynamic[i] = 1;
    }
    res->regions.push_back(d);
  }
}

/// Single moving features: flagged, and a disc around each.
void addMovingFeatures(const std::vector<MotionCorrespondence>& corr, const std::vector<int8_t>& moving,
                       const DynamicMaskOptions& o, cv::Mat* dynamic_area, DynamicMaskResult* res) {
  for (size_t i = 0; i < corr.size(); ++i) {
    if (moving[i] != 1) continue;
    res->feature_dynamic[i] = 1;
    if (o.feature_radius_px > 0 && corr[i].uv_cur.allFinite())
      cv::circle(*dynamic_area, cv::Point(static_cast<int>(std::lround(corr[i].uv_cur.x())), static_cast<int>(std::lround(corr[i].uv_cur.y()))),
                 o.feature_radius_px, cv::Scalar(255), cv::FILLED);
  }
}

}  // namespace

DynamicMaskResult fuseDynamicMask(const DynamicEvidence& ev, cv::Size size, const DynamicMaskOptions& o) {
  static const std::vector<MotionCorrespondence> kNoCorrespondences;
  const auto& corr = ev.correspondences ? *ev.correspondences : kNoCorrespondences;
  const size_t n = corr.size();
  const MotionCheckResult* motion = ev.motion && ev.motion->ok() ? ev.motion : nullptr;
  const DelaunayMotionResult* graph = o.use_delaunay_evidence ? ev.delaunay : nullptr;
  const Segmentation* seg = ev.segmentation && !ev.segmentation->empty() ? ev.segmentation : nullptr;
  validateEvidence(ev, n, motion, seg, size);

  DynamicMaskResult res;
  res.feature_dynamic.assign(n, 0);
  res.stats.features = static_cast<int>(n);
  const std::vector<int8_t> moving = featureMotion(n, motion, graph, &res);
  const cv::Mat* labels = seg && ev.feature_labels ? ev.feature_labels : seg ? &seg->instance_ids : nullptr;
  const std::vector<int> label = featureLabels(corr, labels, size);

  res.mask = cv::Mat(size, CV_8UC1, cv::Scalar(255));
  cv::Mat dynamic_area(size, CV_8UC1, cv::Scalar(0));
  if (seg) addInstances(*seg, label, moving, o, &dynamic_area, &res);
  if (ev.delaunay) addRegions(ev.delaunay->regions, label, motion, o, &dynamic_area, &res);
  addMovingFeatures(corr, moving, o, &dynamic_area, &res);

  dilate(&dynamic_area, o.dilate_px);
  if (ev.moving_triangles && !ev.moving_triangles->empty()) {  // grown on its own: its triangles lie on the object
    cv::Mat moving_area(size, CV_8UC1, cv::Scalar(0));
    for (const auto& t : *ev.moving_triangles) fillPolygon(&moving_area, t);
    dilate(&moving_area, o.moving_area_dilate_px);
    dynamic_area |= moving_area;
  }
  res.mask.setTo(0, dynamic_area);
  res.stats.dynamic_pixels = cv::countNonZero(dynamic_area);
  for (uint8_t f : res.feature_dynamic) res.stats.features_dynamic += f;
  return res;
}

}  // namespace plslam
