// What the dynamic-object stages exchange: instances found by a segmenter, and the
// per-frame decision of which pixels and features are dynamic.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/time.h"

namespace plslam {

/// One object instance in one image.
struct Instance {
  int id = 0;                    ///< 1-based within its frame (the value in Segmentation::instance_ids)
  int class_id = -1;             ///< class index in the class list (COCO: 0 person)
  std::string class_name;        ///< class name, for messages and maps
  float score = 1.0f;            ///< detector confidence (1 for replayed masks)
  cv::Rect box;                  ///< bounding box, image pixels
  bool potentially_dynamic = false;  ///< its class may move (the configurable class prior)
  int source_id = 0;             ///< the object's id in the source when it has one that lasts across frames (replay: its mask value); 0 otherwise
};

/// The instances of one image and a label image.
struct Segmentation {
  TimeNs t_ns = 0;              ///< stamp of the image that was segmented
  std::vector<Instance> instances;
  cv::Mat instance_ids;         ///< CV_16UC1, image size: 0 = no instance, k = instances[k-1]
  double ms = 0;                ///< time the segmenter took
  bool empty() const { return instance_ids.empty(); }
};

}  // namespace plslam
