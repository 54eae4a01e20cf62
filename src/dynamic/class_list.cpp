#include "dynamic/class_list.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/log.h"

namespace plslam {
namespace {

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Pairs of spellings of the same COCO class (Darknet's coco.names vs the 2017 annotations).
const std::vector<std::pair<std::string, std::string>>& aliases() {
  static const std::vector<std::pair<std::string, std::string>> a = {
      {"motorbike", "motorcycle"},     {"aeroplane", "airplane"}, {"sofa", "couch"},
      {"pottedplant", "potted plant"}, {"diningtable", "dining table"}, {"tvmonitor", "tv"}};
  return a;
}

// Checks the cleaned names; returns an error message or "".
std::string validate(const std::vector<std::string>& names, const std::vector<int>& line_of) {
  if (names.empty()) return "no class names (empty list)";
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty())
      return str("line ", line_of[i], " is blank inside the list (class ids are line indices)");
    for (size_t j = 0; j < i; ++j)
      if (names[j] == names[i])
        return str("class name '", names[i], "' repeated (lines ", line_of[j], " and ", line_of[i], ")");
  }
  return "";
}

}  // namespace

const std::vector<std::string>& ClassList::defaultDynamicNames() {
  static const std::vector<std::string> names = {"person", "bicycle", "car",   "motorbike", "bus",  "train",
                                                 "truck",  "boat",    "bird",  "cat",       "dog",  "horse",
                                                 "sheep",  "cow",     "elephant", "bear",   "zebra", "giraffe"};
  return names;
}

ClassList ClassList::coco() {
  static const std::vector<std::string> names = {
      "person",        "bicycle",      "car",          "motorbike",     "aeroplane",   "bus",
      "train",         "truck",        "boat",         "traffic light", "fire hydrant", "stop sign",
      "parking meter", "bench",        "bird",         "cat",           "dog",         "horse",
      "sheep",         "cow",          "elephant",     "bear",          "zebra",       "giraffe",
      "backpack",      "umbrella",     "handbag",      "tie",           "suitcase",    "frisbee",
      "skis",          "snowboard",    "sports ball",  "kite",          "baseball bat", "baseball glove",
      "skateboard",    "surfboard",    "tennis racket", "bottle",       "wine glass",  "cup",
      "fork",          "knife",        "spoon",        "bowl",          "banana",      "apple",
      "sandwich",      "orange",       "broccoli",     "carrot",        "hot dog",     "pizza",
      "donut",         "cake",         "chair",        "sofa",          "pottedplant", "bed",
      "diningtable",   "toilet",       "tvmonitor",    "laptop",        "mouse",       "remote",
      "keyboard",      "cell phone",   "microwave",    "oven",          "toaster",     "sink",
      "refrigerator",  "book",         "clock",        "vase",          "scissors",    "teddy bear",
      "hair drier",    "toothbrush"};
  return fromNames(names, "<builtin coco>");
}

ClassList ClassList::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(str("class names file '", path, "': cannot open (missing or unreadable)"));
  std::vector<std::string> names;
  std::vector<int> line_of;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    names.push_back(trim(line));  // trim also drops the '\r' of CRLF files
    line_of.push_back(line_no);
  }
  if (in.bad()) throw IoError(str("class names file '", path, "': read error"));
  while (!names.empty() && names.back().empty()) {  // trailing blank lines are harmless
    names.pop_back();
    line_of.pop_back();
  }
  const std::string problem = validate(names, line_of);
  if (!problem.empty()) throw IoError(str("class names file '", path, "': ", problem));
  ClassList list;
  list.names_ = std::move(names);
  list.source_ = path;
  list.setDefaultDynamic();
  return list;
}

ClassList ClassList::fromNames(const std::vector<std::string>& names, const std::string& source) {
  ClassList list;
  std::vector<int> line_of;
  for (size_t i = 0; i < names.size(); ++i) {
    list.names_.push_back(trim(names[i]));
    line_of.push_back(static_cast<int>(i) + 1);
  }
  const std::string problem = validate(list.names_, line_of);
  if (!problem.empty()) throw ConfigError(str("class names ", source, ": ", problem));
  list.source_ = source;
  list.setDefaultDynamic();
  return list;
}

std::string ClassList::name(int class_id) const {
  if (class_id < 0 || class_id >= static_cast<int>(names_.size())) return str("class", class_id);
  return names_[class_id];
}

int ClassList::find(const std::string& raw) const {
  const std::string wanted = trim(raw);
  for (size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == wanted) return static_cast<int>(i);
  const std::string low = lower(wanted);
  for (size_t i = 0; i < names_.size(); ++i)
    if (lower(names_[i]) == low) return static_cast<int>(i);
  for (const auto& [a, b] : aliases()) {
    std::string other;
    if (low == a) other = b;
    if (low == b) other = a;
    if (other.empty()) continue;
    for (size_t i = 0; i < names_.size(); ++i)
      if (lower(names_[i]) == other) return static_cast<int>(i);
  }
  return -1;
}

void ClassList::setDynamic(const std::vector<std::string>& names) {
  std::vector<bool> dynamic(names_.size(), false);
  for (const std::string& n : names) {
    const int id = find(n);
    if (id < 0)
      throw ConfigError(str("dynamic class '", n, "' is not a class of ", source_, " (", names_.size(),
                            " classes; e.g. '", names_.front(), "')"));
    dynamic[id] = true;
  }
  dynamic_ = std::move(dynamic);
}

void ClassList::setDefaultDynamic() {
  dynamic_.assign(names_.size(), false);
  for (const std::string& n : defaultDynamicNames()) {
    const int id = find(n);
    if (id >= 0) dynamic_[id] = true;
  }
}

bool ClassList::isDynamic(int class_id) const {
  return class_id >= 0 && class_id < static_cast<int>(dynamic_.size()) && dynamic_[class_id];
}

std::vector<std::string> ClassList::dynamicNames() const {
  std::vector<std::string> out;
  for (size_t i = 0; i < names_.size(); ++i)
    if (dynamic_[i]) out.push_back(names_[i]);
  return out;
}

}  // namespace plslam
