#include "camera/camera_file.h"

#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {

const Logger kLog("camera");

// A parsed camera file and where it came from, for messages that name the file and line.
struct XmlFile {
  pugi::xml_document doc;
  const std::string& content;
  const std::string& path;

  // "<path>:<line>" of a node (pugixml keeps byte offsets; lines are counted from them).
  std::string at(const pugi::xml_node& n) const { return at(n.offset_debug()); }
  std::string at(ptrdiff_t offset) const {
    const auto end = content.begin() + std::clamp<ptrdiff_t>(offset, 0, static_cast<ptrdiff_t>(content.size()));
    return str(path, ":", 1 + std::count(content.begin(), end, '\n'));
  }
};

// Parses `content`; a UTF-8 byte order mark, character references, comments and a DOCTYPE
// are accepted (pugixml), character data is trimmed.
void parseXml(XmlFile* file) {
  const pugi::xml_parse_result r = file->doc.load_buffer(file->content.data(), file->content.size(),
                                                         pugi::parse_default | pugi::parse_trim_pcdata);
  if (!r) throw IoError(str(file->at(r.offset), ": malformed XML: ", r.description()));
}

double number(const XmlFile& file, const pugi::xml_node& parent, const char* key, bool required, double fallback) {
  const pugi::xml_node n = parent.child(key);
  if (!n) {
    if (required) throw IoError(str(file.at(parent), ": <", parent.name(), "> has no <", key, ">"));
    return fallback;
  }
  const std::string text = n.child_value();
  std::istringstream is(text);
  double v = 0;
  std::string rest;
  if (!(is >> v) || (is >> rest)) throw IoError(str(file.at(n), ": <", key, "> value '", text, "' is not a number"));
  return v;
}

int integer(const XmlFile& file, const pugi::xml_node& parent, const char* key) {
  const double v = number(file, parent, key, true, 0);
  // The range check first: converting a double outside long long's range is undefined.
  if (!(v >= -1e9 && v <= 1e9) || v != static_cast<double>(static_cast<long long>(v)))
    throw IoError(str(file.at(parent.child(key)), ": <", key, "> must be a whole number, got ", v));
  return static_cast<int>(v);
}

bool named(const pugi::xml_node& node, const char* child, const std::string& value) {
  return value == node.child_value(child);
}

pugi::xml_node findCamera(const XmlFile& file, const std::string& camera_name) {
  const pugi::xml_node root = file.doc.document_element();
  if (std::string(root.name()) != "root")
    throw IoError(str(file.at(root), ": root element is <", root.name(), ">, expected <root> (ViSP camera file)"));
  for (const pugi::xml_node c : root.children("camera"))
    if (camera_name.empty() || (c.child("name") && named(c, "name", camera_name))) return c;
  throw IoError(camera_name.empty() ? file.path + ": no <camera> element"
                                    : file.path + ": no <camera> named '" + camera_name + "'");
}

// Prefer the model without distortion (ViSP writes both when calibrated); the
// Brown-Conrady coefficients come from <rgbd>.
pugi::xml_node findModel(const XmlFile& file, const pugi::xml_node& cam) {
  pugi::xml_node model;
  for (const pugi::xml_node m : cam.children("model")) {
    const pugi::xml_node t = m.child("type");
    if (!t) throw IoError(str(file.at(m), ": <model> has no <type>"));
    if (named(m, "type", "perspectiveProjWithoutDistortion")) return m;
    if (!named(m, "type", "perspectiveProjWithDistortion"))
      throw IoError(str(file.at(t), ": camera model type '", t.child_value(),
                        "' is not supported (perspectiveProjWithoutDistortion or perspectiveProjWithDistortion)"));
    if (!model) model = m;
  }
  if (!model) throw IoError(file.path + ": <camera> has no <model>");
  return model;
}

void readRgbd(const XmlFile& file, const pugi::xml_node& cam, PinholeCamera* out) {
  const pugi::xml_node rgbd = cam.child("additional_information").child("rgbd");
  if (!rgbd) {
    out->depth_scale = 1000.0;
    // A warning, not info: the default log level hides info, and a TUM sequence (5000 units
    // per metre) read at 1000 has every depth 5 x too large, with nothing else to show it.
    kLog.warn(file.path +
              ": no <rgbd> element: assuming a depth scale of 1000 units per metre (RealSense); "
              "TUM RGB-D and ICL-NUIM need 5000: add <additional_information><rgbd><depth_scale>5000</depth_scale></rgbd>"
              "</additional_information> to <camera> (see calib/tum_freiburg1.xml)");
    return;
  }
  out->depth_scale = number(file, rgbd, "depth_scale", true, 0);
  if (const pugi::xml_node d = rgbd.child("distortion")) {
    const char* keys[] = {"k1", "k2", "p1", "p2", "k3"};
    for (int i = 0; i < 5; ++i) out->dist[i] = number(file, d, keys[i], false, 0.0);
  }
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open camera file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The shortest text that reads back as the same double.
std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, r.ptr);
}

void addText(pugi::xml_node parent, const char* name, const std::string& text) {
  parent.append_child(name).text().set(text.c_str());
}

std::string cameraXml(const PinholeCamera& c, const std::string& comment) {
  pugi::xml_document doc;
  doc.append_child(pugi::node_declaration).append_attribute("version") = "1.0";
  if (!comment.empty()) doc.append_child(pugi::node_comment).set_value((" " + comment + " ").c_str());
  pugi::xml_node cam = doc.append_child("root").append_child("camera");
  addText(cam, "name", c.name.empty() ? "Camera" : c.name);
  addText(cam, "image_width", std::to_string(c.width));
  addText(cam, "image_height", std::to_string(c.height));
  pugi::xml_node model = cam.append_child("model");
  addText(model, "type", "perspectiveProjWithoutDistortion");
  addText(model, "px", shortest(c.fx));
  addText(model, "py", shortest(c.fy));
  addText(model, "u0", shortest(c.cx));
  addText(model, "v0", shortest(c.cy));
  pugi::xml_node info = cam.append_child("additional_information");
  info.append_child(pugi::node_comment)
      .set_value(" plslam: depth units per metre and Brown-Conrady distortion (OpenCV order); ViSP skips <additional_information>. ");
  pugi::xml_node rgbd = info.append_child("rgbd");
  addText(rgbd, "depth_scale", shortest(c.depth_scale));
  pugi::xml_node dist = rgbd.append_child("distortion");
  const char* keys[] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) addText(dist, keys[i], shortest(c.dist[i]));
  std::ostringstream os;
  doc.save(os, "  ", pugi::format_default, pugi::encoding_utf8);
  return os.str();
}

}  // namespace

PinholeCamera parseCameraFile(const std::string& content, const std::string& path, const std::string& camera_name) {
  XmlFile file{{}, content, path};
  parseXml(&file);
  const pugi::xml_node cam = findCamera(file, camera_name);
  PinholeCamera out;
  out.name = cam.child_value("name");
  out.width = integer(file, cam, "image_width");
  out.height = integer(file, cam, "image_height");
  const pugi::xml_node model = findModel(file, cam);
  out.fx = number(file, model, "px", true, 0);
  out.fy = number(file, model, "py", true, 0);
  out.cx = number(file, model, "u0", true, 0);
  out.cy = number(file, model, "v0", true, 0);
  if (named(model, "type", "perspectiveProjWithDistortion")) out.dist[0] = number(file, model, "kud", true, 0);
  readRgbd(file, cam, &out);
  out.validate(path);
  if (out.fx < 0 || out.fy < 0)
    kLog.info(str(path, ": negative focal length (px ", out.fx, ", py ", out.fy,
                  "): the image axis runs against the camera frame's, poses are in that camera frame"));
  return out;
}

PinholeCamera loadCameraFile(const std::string& path, const std::string& camera_name) {
  return parseCameraFile(readFile(path), path, camera_name);
}

void saveCameraFile(const std::string& path, const PinholeCamera& c, const std::string& comment) {
  c.validate(path);
  writeFileAtomically(path, cameraXml(c, comment));
}

void checkImageSize(const PinholeCamera& camera, int width, int height, const std::string& what) {
  if (width != camera.width || height != camera.height)
    throw DataError(str(what, ": image is ", width, "x", height, " but camera '", camera.name, "' is ",
                        camera.width, "x", camera.height));
}

}  // namespace plslam
