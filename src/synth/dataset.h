// Writing a synthetic scene as a TUM RGB-D style folder, and a contact sheet preview.
//
// Folder layout written by writeDataset(scene, DIR):
//
//   DIR/rgb/<stamp>.png       colour, 8-bit 3-channel PNG
//   DIR/depth/<stamp>.png     depth, 16-bit PNG, 5000 units per metre, 0 = no reading
//   DIR/masks/<stamp>.png     instance ids, 16-bit PNG: 0 = static background, k >= 1 = the
//                             pixels of moving object k (ids are stable over the sequence)
//   DIR/masks/instances.txt   one line per moving object: "instance_id class_id class_name"
//                             (COCO class ids: 0 person); only the header for static scenes
//   DIR/rgb.txt               "stamp rgb/<stamp>.png" per frame (TUM format, '#' header)
//   DIR/depth.txt             "stamp depth/<stamp>.png" per frame; stamp = colour stamp +
//                             DatasetOptions::depth_offset_ns (the image content is always
//                             rendered at the colour time)
//   DIR/masks.txt             "stamp masks/<stamp>.png" per frame (colour stamps)
//   DIR/groundtruth.txt       T_w_c of every frame at its colour stamp (TUM trajectory)
//   DIR/camera.xml            the camera (camera/camera_file.h), name "synthetic"
//   DIR/scene.txt             Scene::describe(): kind, seed, noise, boxes, persons
//   DIR/exposure.txt          fast scene only: "stamp gain subframes" per colour image (the
//                             colour integrates over an exposure centred on its stamp; the
//                             depth and groundtruth.txt are at the stamp itself)
//
// <stamp> is the frame time in seconds with 6 decimals (core/time.h formatSecondsStamp);
// frames are 30 Hz, stamps are whole microseconds. The index files are written last and
// atomically, so an interrupted run leaves no rgb.txt. Existing files of the same names are
// replaced. The same scene (kind, options, seed) gives byte-identical files.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "synth/scene.h"

namespace plslam::synth {

struct DatasetOptions {
  TimeNs depth_offset_ns = 0;  ///< depth stamps are the colour stamps plus this (real Kinect streams: a few ms)
  bool write_masks = true;     ///< write masks/, masks.txt and masks/instances.txt
  int png_compression = 1;     ///< zlib level 0..9 of all PNGs (RLE strategy; files are identical for the same level)
  int threads = 1;             ///< frames rendered in parallel (the output does not depend on it)
  std::function<void(int done, int total)> progress;  ///< called after each frame (serialised); may be empty
};

/// Renders every frame of `scene` and writes the folder above (created if missing).
/// Throws IoError naming the file that could not be written.
void writeDataset(const Scene& scene, const std::string& dir, const DatasetOptions& options = {});

/// Depth (CV_32F metres) as a colour image: near blue, far red, black where NaN.
cv::Mat colourDepth(const cv::Mat& depth_m, double max_depth_m = 6.0);
/// Colour image with the instance ids painted over it (one colour per id, half transparent).
cv::Mat overlayInstances(const cv::Mat& bgr, const cv::Mat& instance_ids);

/// The frames a preview shows: one per third of the sequence (for scenes with moving
/// objects, the one where they cover most of the image).
std::vector<int> previewFrames(const Scene& scene);
/// A contact sheet: one row per frame with colour, depth colour-mapped and masks overlaid,
/// each at half size, labelled. `frames` empty: previewFrames(scene).
cv::Mat makePreview(const Scene& scene, std::vector<int> frames = {});
/// Writes makePreview() as a PNG; throws IoError on failure.
void writePreview(const Scene& scene, const std::string& path, const std::vector<int>& frames = {});

}  // namespace plslam::synth
