#include "io/dataset.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <system_error>
#include <stdexcept>

#include "core/error.h"
#include "core/log.h"
#include "io/associate.h"
#include "io/trajectory_file.h"
#include "io/tum_line.h"

namespace fs = std::filesystem;

namespace plslam {

namespace {
const Logger kLog("io");

struct ListItem {
  TimeNs t_ns = 0;
  std::vector<std::string> fields;  // the fields after the stamp
};

/// The lines of a TUM list as associate.py's read_file_list reads them: commas and tabs
/// are spaces, '#' starts a comment line, a duplicated stamp keeps the last line.
/// `min_fields` counts the fields after the stamp; `stamp_fields` lists further fields
/// (indices into ListItem::fields) that must be stamps too.
std::vector<ListItem> readList(const std::string& path, size_t min_fields, const std::vector<size_t>& stamp_fields,
                               DatasetListReport* report) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open list file");
  std::map<TimeNs, ListItem> items;
  std::string line;
  int lineno = 0, skipped = 0, duplicates = 0;
  while (std::getline(in, line)) {
    ++lineno;
    std::vector<std::string> f;
    if (!splitTumLine(line, &f)) continue;
    ListItem item;
    item.fields.assign(f.begin() + 1, f.end());
    bool ok = item.fields.size() >= min_fields && parseSecondsStamp(f[0], &item.t_ns);
    for (size_t k : stamp_fields) {
      TimeNs unused = 0;
      ok = ok && parseSecondsStamp(item.fields[k], &unused);
    }
    if (!ok) {
      ++skipped;
      kLog.debug(str(path, ":", lineno, ": not a 'stamp path' line, skipped"));
      continue;
    }
    if (items.count(item.t_ns)) {
      ++report->duplicate_stamps;
      ++duplicates;
    }
    items[item.t_ns] = std::move(item);
  }
  if (skipped > 0) kLog.warn(str(path, ": skipped ", skipped, " unparsable line(s)"));
  if (duplicates > 0)
    kLog.warn(str(path, ": ", duplicates, " duplicated timestamp(s); the last line of each is kept"));
  report->lines_skipped += skipped;
  if (items.empty()) throw IoError(path + ": no usable 'timestamp filename' line");
  std::vector<ListItem> out;
  out.reserve(items.size());
  for (auto& [t, item] : items) out.push_back(std::move(item));
  return out;
}

bool looksLikeDepthPath(const std::string& p) {
  std::string s = p;
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s.find("depth") != std::string::npos;
}

std::string typeName(const cv::Mat& m) {
  const int depth = m.depth();
  const char* d = depth == CV_8U ? "8-bit" : depth == CV_16U ? "16-bit" : depth == CV_32F ? "32-bit float" : "other";
  return str(d, " ", m.channels(), "-channel");
}

std::string findGroundtruth(const std::string& dir, const DatasetOptions& options) {
  if (!options.groundtruth_file.empty()) {
    if (!fs::exists(options.groundtruth_file)) throw IoError(options.groundtruth_file + ": ground truth file not found");
    return options.groundtruth_file;
  }
  const fs::path gt = fs::path(dir) / "groundtruth.txt";
  if (fs::exists(gt)) return gt.string();
  // ICL-NUIM names its TUM-format ground truth "<sequence>.gt.freiburg".
  std::vector<std::string> icl;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.size() > 12 && name.compare(name.size() - 12, 12, ".gt.freiburg") == 0)
      icl.push_back(e.path().string());
  }
  if (icl.size() == 1) return icl.front();
  if (icl.size() > 1) kLog.warn(dir + ": several *.gt.freiburg files, none loaded (name one with groundtruth_file)");
  return "";
}

std::vector<InstanceLabel> readInstanceLabels(const std::string& path) {
  std::vector<InstanceLabel> labels;
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::string line;
  int skipped = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t b = line.find_first_not_of(" \t");
    if (b == std::string::npos || line[b] == '#') continue;
    std::istringstream is(line);
    InstanceLabel l;
    if (!(is >> l.instance_id >> l.class_id)) {
      ++skipped;
      continue;
    }
    std::getline(is >> std::ws, l.class_name);  // the rest of the line: names may hold spaces
    labels.push_back(l);
  }
  if (skipped > 0) kLog.warn(str(path, ": skipped ", skipped, " line(s) that are not 'instance_id class_id class_name'"));
  return labels;
}
}  // namespace

const char* toString(FrameStatus status) {
  switch (status) {
    case FrameStatus::kOk: return "ok";
    case FrameStatus::kMissingFile: return "missing file";
    case FrameStatus::kUnreadable: return "unreadable image";
    case FrameStatus::kSizeMismatch: return "image size differs from the camera";
    case FrameStatus::kBadDepthType: return "depth not 16-bit single channel";
    case FrameStatus::kBadColourType: return "colour not 8-bit 3-channel";
    case FrameStatus::kBadMaskType: return "mask not 16-bit single channel";
    case FrameStatus::kNoDepth: return "depth image without any valid pixel";
  }
  return "?";
}

namespace {

/// rgb.txt and depth.txt: each colour stamp paired with the depth stamp nearest in time.
std::vector<DatasetEntry> pairColourAndDepth(const std::string& rgb_list, const std::string& depth_list,
                                             const DatasetOptions& options, DatasetListReport* rep) {
  if (!fs::exists(depth_list)) throw IoError(depth_list + ": not found (a TUM folder needs rgb.txt and depth.txt)");
  const auto rgb = readList(rgb_list, 1, {}, rep);
  const auto depth = readList(depth_list, 1, {}, rep);
  rep->rgb_listed = static_cast<int>(rgb.size());
  rep->depth_listed = static_cast<int>(depth.size());
  std::vector<TimeNs> t_rgb, t_depth;
  for (const auto& r : rgb) t_rgb.push_back(r.t_ns);
  for (const auto& d : depth) t_depth.push_back(d.t_ns);
  std::vector<DatasetEntry> entries;
  for (const StampMatch& m : associateStamps(t_rgb, t_depth, options.max_difference_s)) {
    DatasetEntry e;
    e.t_rgb_ns = rgb[m.first].t_ns;
    e.t_depth_ns = depth[m.second].t_ns;
    e.rgb_path = rgb[m.first].fields[0];
    e.depth_path = depth[m.second].fields[0];
    entries.push_back(e);
  }
  rep->rgb_unpaired = rep->rgb_listed - static_cast<int>(entries.size());
  rep->depth_unpaired = rep->depth_listed - static_cast<int>(entries.size());
  if (entries.empty())
    throw IoError(str(rgb_list, " and ", depth_list, ": no colour stamp has a depth stamp within ",
                      options.max_difference_s, " s"));
  return entries;
}

/// associations.txt (ICL-NUIM, associate.py output), sorted by colour stamp.
std::vector<DatasetEntry> readAssociations(const std::string& assoc_list, DatasetListReport* rep) {
  rep->layout = DatasetListReport::Layout::kAssociations;
  std::vector<DatasetEntry> entries;
  for (const ListItem& item : readList(assoc_list, 3, {1}, rep)) {
    DatasetEntry e;
    e.t_rgb_ns = item.t_ns;
    e.rgb_path = item.fields[0];
    parseSecondsStamp(item.fields[1], &e.t_depth_ns);
    e.depth_path = item.fields[2];
    // The published ICL-NUIM archives list depth first; associate.py output lists colour first.
    if (looksLikeDepthPath(e.rgb_path) && !looksLikeDepthPath(e.depth_path)) {
      std::swap(e.rgb_path, e.depth_path);
      std::swap(e.t_rgb_ns, e.t_depth_ns);
    }
    entries.push_back(e);
  }
  std::stable_sort(entries.begin(), entries.end(),
                   [](const DatasetEntry& a, const DatasetEntry& b) { return a.t_rgb_ns < b.t_rgb_ns; });
  rep->rgb_listed = rep->depth_listed = static_cast<int>(entries.size());
  return entries;
}

/// masks.txt: each frame's instance mask nearest in time (within max_difference_s).
void attachMasks(const std::string& mask_list, const DatasetOptions& options, std::vector<DatasetEntry>* entries,
                 DatasetListReport* rep) {
  const auto masks = readList(mask_list, 1, {}, rep);
  rep->masks_listed = static_cast<int>(masks.size());
  std::vector<double> t_masks;
  for (const auto& m : masks) t_masks.push_back(stampSeconds(m.t_ns));
  for (DatasetEntry& e : *entries) {
    const double t = stampSeconds(e.t_rgb_ns);
    const size_t k = findClosestIndex(t_masks, t);
    if (std::abs(t_masks[k] - t) < options.max_difference_s) {
      e.mask_path = masks[k].fields[0];
    } else {
      ++rep->frames_without_mask;
    }
  }
  if (rep->frames_without_mask > 0)
    kLog.warn(str(mask_list, ": ", rep->frames_without_mask, " frame(s) have no mask within ", options.max_difference_s, " s"));
}

}  // namespace

TumDataset TumDataset::open(const std::string& dir, const PinholeCamera& camera, const DatasetOptions& options) {
  if (!fs::is_directory(dir))
    throw IoError(dir + (fs::exists(dir) ? ": not a folder" : ": dataset folder not found"));
  if (!(options.max_difference_s > 0)) throw ConfigError(str("dataset max_difference_s must be positive, got ", options.max_difference_s));
  if (options.max_frames < 0) throw ConfigError(str("dataset max_frames must be >= 0, got ", options.max_frames));
  camera.validate(str("camera for dataset ", dir));

  TumDataset ds;
  ds.dir_ = dir;
  ds.camera_ = camera;
  ds.options_ = options;
  DatasetListReport& rep = ds.list_report_;
  const fs::path root(dir);
  const std::string rgb_list = (root / "rgb.txt").string();
  const std::string depth_list = (root / "depth.txt").string();
  const std::string assoc_list = (root / "associations.txt").string();

  if (fs::exists(rgb_list))
    ds.entries_ = pairColourAndDepth(rgb_list, depth_list, options, &rep);
  else if (fs::exists(assoc_list))
    ds.entries_ = readAssociations(assoc_list, &rep);
  else
    throw IoError(rgb_list + ": not found (a TUM RGB-D folder needs rgb.txt and depth.txt, or associations.txt)");

  if (options.max_frames > 0 && ds.entries_.size() > static_cast<size_t>(options.max_frames)) {
    rep.cut_by_max_frames = static_cast<int>(ds.entries_.size()) - options.max_frames;
    ds.entries_.resize(static_cast<size_t>(options.max_frames));
  }

  const std::string mask_list = (root / "masks.txt").string();
  if (options.load_masks && fs::exists(mask_list)) {
    attachMasks(mask_list, options, &ds.entries_, &rep);
    const fs::path labels = root / "masks" / "instances.txt";
    if (fs::exists(labels)) ds.instance_labels_ = readInstanceLabels(labels.string());
  }

  const std::string gt = findGroundtruth(dir, options);
  if (!gt.empty()) ds.groundtruth_ = readTumTrajectory(gt);

  ds.status_.assign(ds.entries_.size(), -1);
  // Colour frames without depth are frames the run will not see: the user should hear of it.
  if (rep.rgb_unpaired > 0)
    kLog.warn(str(rgb_list, ": ", rep.rgb_unpaired, " colour frame(s) have no depth stamp within ", options.max_difference_s,
                  " s in ", depth_list, " and are left out"));
  if (rep.rgb_unpaired > 0 || rep.depth_unpaired > 0 || rep.lines_skipped > 0)
    kLog.info(str(dir, ": ", ds.entries_.size(), " frames (", rep.rgb_unpaired, " colour and ", rep.depth_unpaired,
                  " depth stamps unpaired, ", rep.lines_skipped, " list lines skipped)"));
  return ds;
}

std::vector<TimeNs> TumDataset::stamps() const {
  std::vector<TimeNs> out;
  out.reserve(entries_.size());
  for (const auto& e : entries_) out.push_back(e.t_rgb_ns);
  return out;
}

int TumDataset::skippedTotal() const {
  int n = 0;
  for (int s = 1; s < kFrameStatusCount; ++s) n += counts_[s];
  return n;
}

std::string TumDataset::skippedText() const {
  std::string text;
  for (int s = 1; s < kFrameStatusCount; ++s) {
    const int n = counts_[s];
    if (n > 0) text += (text.empty() ? "" : ", ") + std::to_string(n) + " " + toString(static_cast<FrameStatus>(s));
  }
  return text;
}

FrameStatus TumDataset::load(size_t i, RgbdFrame* frame, std::string* reason) {
  if (i >= entries_.size()) throw std::out_of_range(str(dir_, ": frame ", i, " requested, the dataset has ", entries_.size()));
  std::string why;
  const FrameStatus s = loadImpl(i, frame, &why);
  // Count each frame once, under the outcome of its latest load.
  if (status_[i] >= 0) --counts_[status_[i]];
  status_[i] = static_cast<int>(s);
  ++counts_[status_[i]];
  if (s != FrameStatus::kOk) {
    kLog.warn(str(dir_, ": frame ", i, " (", entries_[i].rgb_path, ") skipped: ", why));
    if (reason) *reason = why;
  }
  return s;
}

bool TumDataset::next(RgbdFrame* frame) {
  while (cursor_ < entries_.size()) {
    if (load(cursor_++, frame) == FrameStatus::kOk) return true;
  }
  return false;
}

FrameStatus TumDataset::loadImpl(size_t i, RgbdFrame* frame, std::string* why) const {
  const DatasetEntry& e = entries_[i];
  auto full = [&](const std::string& p) { return fs::path(p).is_absolute() ? p : (fs::path(dir_) / p).string(); };
  // Reads one image; a missing or undecodable file is a skip.
  auto read = [&](const std::string& listed, cv::Mat* img) {
    const std::string path = full(listed);
    std::error_code ec;  // a name the file system refuses (too long, ...) is a missing file, not a throw
    if (!fs::is_regular_file(path, ec)) {
      const bool odd = ec && ec != std::errc::no_such_file_or_directory;
      *why = listed + (odd ? ": " + ec.message() : std::string(": file not found"));
      return FrameStatus::kMissingFile;
    }
    *img = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (img->empty()) {
      *why = listed + ": cannot decode the image";
      return FrameStatus::kUnreadable;
    }
    return FrameStatus::kOk;
  };
  auto sizeOk = [&](const std::string& listed, const cv::Mat& img) {
    if (img.cols == camera_.width && img.rows == camera_.height) return true;
    *why = str(listed, ": image is ", img.cols, "x", img.rows, " but the camera is ", camera_.width, "x", camera_.height);
    return false;
  };

  cv::Mat colour, depth, mask;
  FrameStatus s = read(e.rgb_path, &colour);
  if (s != FrameStatus::kOk) return s;
  if ((s = read(e.depth_path, &depth)) != FrameStatus::kOk) return s;
  if (!e.mask_path.empty() && (s = read(e.mask_path, &mask)) != FrameStatus::kOk) return s;

  if (colour.type() == CV_8UC1 && options_.convert_grey) {
    cv::cvtColor(colour, colour, cv::COLOR_GRAY2BGR);
  } else if (colour.type() != CV_8UC3) {
    *why = str(e.rgb_path, ": colour image is ", typeName(colour), ", expected 8-bit 3-channel");
    return FrameStatus::kBadColourType;
  }
  if (depth.type() != CV_16UC1) {
    *why = str(e.depth_path, ": depth image is ", typeName(depth), ", expected 16-bit single channel");
    return FrameStatus::kBadDepthType;
  }
  if (!mask.empty() && mask.type() != CV_16UC1) {
    *why = str(e.mask_path, ": instance mask is ", typeName(mask), ", expected 16-bit single channel");
    return FrameStatus::kBadMaskType;
  }
  if (!sizeOk(e.rgb_path, colour) || !sizeOk(e.depth_path, depth) || (!mask.empty() && !sizeOk(e.mask_path, mask)))
    return FrameStatus::kSizeMismatch;
  if (cv::countNonZero(depth) == 0) {
    *why = e.depth_path + ": depth image has no valid pixel (all zero)";
    return FrameStatus::kNoDepth;
  }

  frame->t_ns = e.t_rgb_ns;
  frame->index = static_cast<int>(i);
  frame->bgr = colour;
  frame->depth_m = depthToMetres(depth, camera_.depth_scale);
  frame->instance_ids = mask;
  frame->name = e.rgb_path;
  return FrameStatus::kOk;
}

}  // namespace plslam
