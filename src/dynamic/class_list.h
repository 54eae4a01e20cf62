// The class names of a segmenter (index = class id) and the configurable prior of which
// classes may move ("potentially dynamic").
//
// Names files have one name a line (Darknet/YOLO style, as shared/models/coco.names):
// CRLF endings, surrounding spaces, a UTF-8 BOM and trailing blank lines are accepted;
// a blank line inside the list (it would shift every later class id) or a repeated name
// is refused. Lookups by name also accept the other common COCO spellings
// (motorcycle/motorbike, airplane/aeroplane, couch/sofa, potted plant/pottedplant,
// dining table/diningtable, tv/tvmonitor) and ignore case.
//
// Thread safety: const methods may be called from any thread.
#pragma once

#include <string>
#include <vector>

namespace plslam {

class ClassList {
 public:
  /// Reads a names file. Throws IoError naming the file when it is missing, unreadable,
  /// empty, has a blank line inside the list or a repeated name. The dynamic set is the
  /// default one (defaultDynamicNames(), those of its names the file has).
  static ClassList load(const std::string& path);
  /// From names in memory (`source` names them in messages); same rules as load().
  static ClassList fromNames(const std::vector<std::string>& names, const std::string& source = "<names>");
  /// The 80 COCO names in YOLO's order and coco.names' spelling, for use without a file.
  static ClassList coco();
  /// The default potentially dynamic classes: people, vehicles and animals, COCO spellings
  /// as in coco.names (person, bicycle, car, motorbike, bus, train, truck, boat, bird, cat,
  /// dog, horse, sheep, cow, elephant, bear, zebra, giraffe).
  static const std::vector<std::string>& defaultDynamicNames();

  size_t size() const { return names_.size(); }
  const std::vector<std::string>& names() const { return names_; }
  /// The name of a class id; "class<id>" when out of range (so messages never fail).
  std::string name(int class_id) const;
  /// The class id of a name (exact, then case-insensitive, then the alias spellings); -1 if none.
  int find(const std::string& name) const;
  /// Where the list came from (file path, "<builtin coco>"...), for messages.
  const std::string& source() const { return source_; }

  /// Replaces the dynamic set. Throws ConfigError naming the first name the list does not
  /// have (and the list's source). An empty vector makes no class dynamic.
  void setDynamic(const std::vector<std::string>& names);
  /// Whether class_id is in the dynamic set (false when out of range).
  bool isDynamic(int class_id) const;
  /// The dynamic set as names, in class id order.
  std::vector<std::string> dynamicNames() const;

 private:
  ClassList() = default;
  void setDefaultDynamic();

  std::vector<std::string> names_;
  std::vector<bool> dynamic_;
  std::string source_;
};

}  // namespace plslam
