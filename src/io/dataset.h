// Frame source over an RGB-D dataset folder in the TUM layout:
//
//   rgb.txt, depth.txt     "stamp path" lines ('#' comments); colour and depth are paired
//                          like the TUM tools' associate.py (see io/associate.h)
//   groundtruth.txt        optional TUM trajectory (T_w_c)
//   masks.txt              optional "stamp masks/x.png" 16-bit instance masks (plslam synth);
//                          each colour frame takes the closest mask within max_difference
//   masks/instances.txt    optional "instance_id class_id class_name" lines
//
// ICL-NUIM's TUM-format folders are read too: they have no rgb.txt/depth.txt but an
// associations.txt whose lines pair the images directly ("t depth/x.png t rgb/x.png" in
// the published archives, "t_rgb rgb/x.png t_depth depth/x.png" as written by
// associate.py; which is which is told by the folder names in the paths) and may have
// their ground truth as "<name>.gt.freiburg". Their depth is 5000 units per metre,
// which the camera's depth_scale says, as for TUM.
//
// Problems with the folder itself (missing folder or lists, nothing left after
// association) throw IoError naming the file. Unparsable list lines are counted, logged
// and skipped. A frame whose files are missing, unreadable or inconsistent with the camera
// is a counted, logged skip with its reason (FrameStatus), never a crash.
//
// Thread safety: none; use one TumDataset from one thread.
#pragma once

#include <string>
#include <vector>

#include "camera/pinhole_camera.h"
#include "core/frame.h"
#include "core/trajectory.h"
#include "io/frame_source.h"

namespace plslam {

struct DatasetOptions {
  double max_difference_s = 0.02;  ///< colour/depth (and mask) pairing window, seconds (associate.py's default)
  int max_frames = 0;              ///< keep only the first N associated frames; 0 = all
  bool load_masks = true;          ///< read instance masks when the folder has masks.txt
  bool convert_grey = true;        ///< accept 8-bit single-channel colour images (converted to BGR)
  std::string groundtruth_file;    ///< ground truth to load instead of <dir>/groundtruth.txt (empty: look in the folder)
};

/// Why a frame could or could not be loaded.
enum class FrameStatus {
  kOk = 0,
  kMissingFile,     ///< a listed image file does not exist
  kUnreadable,      ///< the file exists but OpenCV cannot decode it
  kSizeMismatch,    ///< colour, depth or mask size differs from the camera's
  kBadDepthType,    ///< depth is not 16-bit single channel
  kBadColourType,   ///< colour is not 8-bit 3-channel (nor grey when convert_grey)
  kBadMaskType,     ///< instance mask is not 16-bit single channel
  kNoDepth,         ///< the depth image has no valid pixel (all zero)
};
constexpr int kFrameStatusCount = 8;
const char* toString(FrameStatus status);

/// One associated frame of the folder.
struct DatasetEntry {
  TimeNs t_rgb_ns = 0;
  TimeNs t_depth_ns = 0;
  std::string rgb_path;    ///< as listed (relative to the folder)
  std::string depth_path;  ///< as listed
  std::string mask_path;   ///< as listed in masks.txt; empty when the frame has no mask
};

/// A class of an instance id in the masks (masks/instances.txt).
struct InstanceLabel {
  int instance_id = 0;
  int class_id = 0;
  std::string class_name;
};

/// What open() found in the lists.
struct DatasetListReport {
  enum class Layout { kTumLists, kAssociations };
  Layout layout = Layout::kTumLists;
  int rgb_listed = 0;            ///< stamps in rgb.txt (or lines of associations.txt)
  int depth_listed = 0;          ///< stamps in depth.txt
  int lines_skipped = 0;         ///< list lines that could not be parsed (all lists)
  int duplicate_stamps = 0;      ///< repeated stamps within a list (the last line kept, as associate.py does)
  int rgb_unpaired = 0;          ///< colour stamps without a depth stamp within max_difference
  int depth_unpaired = 0;        ///< depth stamps left unused
  int cut_by_max_frames = 0;     ///< associated frames dropped by max_frames
  int masks_listed = 0;          ///< stamps in masks.txt
  int frames_without_mask = 0;   ///< frames with no mask within max_difference (when masks.txt exists)
};

class TumDataset : public FrameSource {
 public:
  /// Reads the lists of `dir` and associates them. `camera` gives the expected image
  /// size and the depth scale. Throws IoError for a missing folder or list, a list with no
  /// usable line, no pair after association, or an unreadable ground truth file.
  static TumDataset open(const std::string& dir, const PinholeCamera& camera, const DatasetOptions& options = {});

  const std::string& dir() const { return dir_; }
  const std::string& location() const override { return dir_; }
  const PinholeCamera& camera() const { return camera_; }
  /// Number of associated frames (before any per-frame skip).
  size_t size() const override { return entries_.size(); }
  const std::vector<DatasetEntry>& entries() const { return entries_; }
  /// Colour stamps of all associated frames, in order.
  std::vector<TimeNs> stamps() const;
  const DatasetListReport& listReport() const { return list_report_; }

  /// Loads frame i (0 <= i < size()). On kOk fills `frame` (t_ns = colour stamp, index = i,
  /// depth in metres, instance_ids when a mask is listed); otherwise leaves `frame`
  /// unspecified, logs the reason with the file name, sets `reason` and counts the skip
  /// (once per frame, however often it is loaded).
  FrameStatus load(size_t i, RgbdFrame* frame, std::string* reason = nullptr);
  /// The next loadable frame in order, skipping (and counting) bad ones; false at the end.
  bool next(RgbdFrame* frame) override;
  /// Restarts next() from the first frame.
  void rewind() { cursor_ = 0; }

  /// Frames skipped so far for `status` (status kOk: frames loaded successfully).
  int count(FrameStatus status) const { return counts_[static_cast<int>(status)]; }
  /// All frames skipped so far, whatever the reason.
  int skippedTotal() const override;
  std::string skippedText() const override;

  /// The ground truth, empty when the folder has none.
  const Trajectory& groundtruth() const override { return groundtruth_; }
  /// Instance classes from masks/instances.txt (empty without it).
  const std::vector<InstanceLabel>& instanceLabels() const { return instance_labels_; }

 private:
  TumDataset() = default;
  FrameStatus loadImpl(size_t i, RgbdFrame* frame, std::string* reason) const;

  std::string dir_;
  PinholeCamera camera_;
  DatasetOptions options_;
  std::vector<DatasetEntry> entries_;
  DatasetListReport list_report_;
  Trajectory groundtruth_;
  std::vector<InstanceLabel> instance_labels_;
  std::vector<int> status_;  // per frame: -1 not loaded yet, else the FrameStatus of its last load
  int counts_[kFrameStatusCount] = {};
  size_t cursor_ = 0;
};

}  // namespace plslam
