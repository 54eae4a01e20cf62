#include "ros1/bag_source.h"

#include <rosbag/view.h>

#include <algorithm>

#include "core/error.h"
#include "core/log.h"
#include "io/associate.h"
#include "io/trajectory_file.h"
#include "ros1/msg_convert.h"

namespace plslam::ros1 {

namespace {
const Logger kLog("ros1");

bool hasTopic(const rosbag::Bag& bag, const std::string& topic) {
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  return view.size() > 0;
}

std::string topicList(const rosbag::Bag& bag) {
  rosbag::View view(bag);
  std::string out;
  for (const rosbag::ConnectionInfo* c : view.getConnections()) out += (out.empty() ? "" : ", ") + c->topic;
  return out.empty() ? "none" : out;
}

BagTopics chooseTopics(const rosbag::Bag& bag, const BagOptions& options, const std::string& path) {
  if (!options.topics.colour.empty()) return options.topics;
  for (const BagTopics& t : knownBagLayouts())
    if (hasTopic(bag, t.colour) && hasTopic(bag, t.depth)) return t;
  throw IoError(path + ": no colour and depth topics of a known layout (TUM's /camera/rgb/image_color + "
                       "/camera/depth/image, or RealSense's /camera/color/image_raw + "
                       "/camera/aligned_depth_to_color/image_raw); the bag has: " + topicList(bag));
}

}  // namespace

std::vector<BagTopics> knownBagLayouts() {
  return {{"/camera/rgb/image_color", "/camera/depth/image", "/camera/rgb/camera_info"},
          {"/camera/color/image_raw", "/camera/aligned_depth_to_color/image_raw", "/camera/color/camera_info"}};
}

BagSource::~BagSource() = default;

std::unique_ptr<BagSource> BagSource::open(const std::string& path, const BagOptions& options) {
  std::unique_ptr<BagSource> src(new BagSource());
  src->path_ = path;
  src->bag_ = std::make_unique<rosbag::Bag>();
  try {
    src->bag_->open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw IoError(path + ": cannot read the bag (" + e.what() + ")");
  }
  src->topics_ = chooseTopics(*src->bag_, options, path);
  src->index();
  src->pair(options);
  if (!options.groundtruth_file.empty()) src->groundtruth_ = readTumTrajectory(options.groundtruth_file);
  kLog.info(str(path, ": ", src->pairs_.size(), " frames from ", src->topics_.colour, " (", src->colour_.size(),
                " messages) and ", src->topics_.depth, " (", src->depth_.size(), " messages)"));
  return src;
}

void BagSource::index() {
  rosbag::View view(*bag_, rosbag::TopicQuery({topics_.colour, topics_.depth, topics_.camera_info}));
  bool have_camera = false;
  for (const rosbag::MessageInstance& m : view) {
    if (m.getTopic() == topics_.camera_info) {
      if (have_camera) continue;
      const auto info = m.instantiate<sensor_msgs::CameraInfo>();
      if (!info) throw DataError(path_ + ": " + topics_.camera_info + " is not sensor_msgs/CameraInfo");
      camera_ = cameraFromInfo(*info);
      have_camera = true;
      continue;
    }
    const auto image = m.instantiate<sensor_msgs::Image>();
    if (!image) throw DataError(path_ + ": " + m.getTopic() + " is not sensor_msgs/Image");
    (m.getTopic() == topics_.colour ? colour_ : depth_).push_back({toNs(image->header.stamp), m});
  }
  if (!have_camera) throw DataError(path_ + ": no camera_info message on " + topics_.camera_info);
}

void BagSource::pair(const BagOptions& options) {
  // One message per stamp (the last, as associate.py keeps), then associate.py's pairing.
  auto unique = [](std::vector<Stamped>* list) {
    std::map<TimeNs, size_t> last;
    for (size_t i = 0; i < list->size(); ++i) last[(*list)[i].t_ns] = i;
    std::vector<Stamped> kept;
    for (const auto& [t, i] : last) kept.push_back((*list)[i]);
    *list = std::move(kept);
  };
  unique(&colour_);
  unique(&depth_);
  std::vector<TimeNs> tc, td;
  for (const Stamped& s : colour_) tc.push_back(s.t_ns);
  for (const Stamped& s : depth_) td.push_back(s.t_ns);
  for (const StampMatch& m : associateStamps(tc, td, options.max_difference_s)) pairs_.emplace_back(m.first, m.second);
  if (options.max_frames > 0 && pairs_.size() > static_cast<size_t>(options.max_frames)) pairs_.resize(options.max_frames);
  if (pairs_.empty())
    throw DataError(str(path_, ": no colour/depth pair within ", options.max_difference_s, " s (", colour_.size(),
                        " colour, ", depth_.size(), " depth messages)"));
}

std::string BagSource::load(size_t i, RgbdFrame* frame) const {
  const Stamped& c = colour_[pairs_[i].first];
  const Stamped& d = depth_[pairs_[i].second];
  try {
    const auto colour = c.message.instantiate<sensor_msgs::Image>();
    const auto depth = d.message.instantiate<sensor_msgs::Image>();
    frame->bgr = colourToBgr(*colour);
    frame->depth_m = depthToMetres(*depth);
  } catch (const Error& e) {
    return e.what();
  }
  if (frame->bgr.cols != camera_.width || frame->bgr.rows != camera_.height || frame->depth_m.size() != frame->bgr.size())
    return str("image size ", frame->bgr.cols, "x", frame->bgr.rows, " / depth ", frame->depth_m.cols, "x",
               frame->depth_m.rows, " differs from the camera_info's ", camera_.width, "x", camera_.height);
  frame->t_ns = c.t_ns;
  frame->index = static_cast<int>(i);
  frame->instance_ids = cv::Mat();
  frame->name = str(topics_.colour, "@", stampSeconds(c.t_ns));
  return "";
}

bool BagSource::next(RgbdFrame* frame) {
  while (cursor_ < pairs_.size()) {
    const size_t i = cursor_++;
    const std::string why = load(i, frame);
    if (why.empty()) return true;
    ++skipped_[why];
    kLog.warn(str(path_, ": frame ", i, " skipped: ", why));
  }
  return false;
}

int BagSource::skippedTotal() const {
  int n = 0;
  for (const auto& [why, count] : skipped_) n += count;
  return n;
}

std::string BagSource::skippedText() const {
  std::string text;
  for (const auto& [why, count] : skipped_) text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + why;
  return text;
}

}  // namespace plslam::ros1
