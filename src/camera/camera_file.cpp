#include "camera/camera_file.h"

#include <fstream>
#include <sstream>

#include "camera/mini_xml.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {

const Logger kLog("camera");

double number(const XmlNode& parent, const char* key, const std::string& path, bool required, double fallback) {
  const XmlNode* n = parent.child(key);
  if (!n) {
    if (required) throw IoError(str(path, ":", parent.line, ": <", parent.name, "> has no <", key, ">"));
    return fallback;
  }
  std::istringstream is(n->text);
  double v = 0;
  std::string rest;
  if (!(is >> v) || (is >> rest)) throw IoError(str(path, ":", n->line, ": <", key, "> value '", n->text, "' is not a number"));
  return v;
}

int integer(const XmlNode& parent, const char* key, const std::string& path) {
  const double v = number(parent, key, path, true, 0);
  // The range check first: converting a double outside long long's range is undefined.
  if (!(v >= -1e9 && v <= 1e9) || v != static_cast<double>(static_cast<long long>(v)))
    throw IoError(str(path, ": <", key, "> must be a whole number, got ", v));
  return static_cast<int>(v);
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open camera file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

PinholeCamera parseCameraFile(const std::string& content, const std::string& path, const std::string& camera_name) {
  const XmlNode root = parseXml(content, path);
  if (root.name != "root") throw IoError(path + ": root element is <" + root.name + ">, expected <root> (ViSP camera file)");
  const XmlNode* cam = nullptr;
  for (const XmlNode* c : root.childrenNamed("camera")) {
    const XmlNode* n = c->child("name");
    if (camera_name.empty() || (n && n->text == camera_name)) {
      cam = c;
      break;
    }
  }
  if (!cam) {
    throw IoError(camera_name.empty() ? path + ": no <camera> element"
                                      : path + ": no <camera> named '" + camera_name + "'");
  }
  PinholeCamera out;
  if (const XmlNode* n = cam->child("name")) out.name = n->text;
  out.width = integer(*cam, "image_width", path);
  out.height = integer(*cam, "image_height", path);

  // Prefer the model without distortion (ViSP writes both when calibrated); the
  // Brown-Conrady coefficients come from <rgbd>.
  const XmlNode* model = nullptr;
  for (const XmlNode* m : cam->childrenNamed("model")) {
    const XmlNode* t = m->child("type");
    if (!t) throw IoError(str(path, ":", m->line, ": <model> has no <type>"));
    if (t->text == "perspectiveProjWithoutDistortion") {
      model = m;
      break;
    }
    if (t->text == "perspectiveProjWithDistortion") {
      if (!model) model = m;
    } else {
      throw IoError(str(path, ":", t->line, ": camera model type '", t->text,
                        "' is not supported (perspectiveProjWithoutDistortion or perspectiveProjWithDistortion)"));
    }
  }
  if (!model) throw IoError(path + ": <camera> has no <model>");
  out.fx = number(*model, "px", path, true, 0);
  out.fy = number(*model, "py", path, true, 0);
  out.cx = number(*model, "u0", path, true, 0);
  out.cy = number(*model, "v0", path, true, 0);
  if (model->child("type")->text == "perspectiveProjWithDistortion") out.dist[0] = number(*model, "kud", path, true, 0);

  const XmlNode* info = cam->child("additional_information");
  if (const XmlNode* rgbd = info ? info->child("rgbd") : nullptr) {
    out.depth_scale = number(*rgbd, "depth_scale", path, true, 0);
    if (const XmlNode* d = rgbd->child("distortion")) {
      const char* keys[] = {"k1", "k2", "p1", "p2", "k3"};
      for (int i = 0; i < 5; ++i) out.dist[i] = number(*d, keys[i], path, false, 0.0);
    }
  } else {
    out.depth_scale = 1000.0;
    kLog.info(path + ": no <rgbd> element: assuming a depth scale of 1000 units per metre");
  }
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
  std::ostringstream os;
  os.precision(10);
  os << "<?xml version=\"1.0\"?>\n";
  if (!comment.empty()) os << "<!-- " << comment << " -->\n";
  os << "<root>\n  <camera>\n    <name>" << (c.name.empty() ? "Camera" : c.name) << "</name>\n"
     << "    <image_width>" << c.width << "</image_width>\n    <image_height>" << c.height << "</image_height>\n"
     << "    <model>\n      <type>perspectiveProjWithoutDistortion</type>\n"
     << "      <px>" << c.fx << "</px>\n      <py>" << c.fy << "</py>\n"
     << "      <u0>" << c.cx << "</u0>\n      <v0>" << c.cy << "</v0>\n    </model>\n"
     << "    <additional_information>\n"
     << "      <!-- plslam: depth units per metre and Brown-Conrady distortion (OpenCV order); ViSP skips <additional_information>. -->\n"
     << "      <rgbd>\n        <depth_scale>" << c.depth_scale << "</depth_scale>\n        <distortion>\n"
     << "          <k1>" << c.dist[0] << "</k1>\n          <k2>" << c.dist[1] << "</k2>\n          <p1>" << c.dist[2]
     << "</p1>\n          <p2>" << c.dist[3] << "</p2>\n          <k3>" << c.dist[4] << "</k3>\n        </distortion>\n"
     << "      </rgbd>\n    </additional_information>\n  </camera>\n</root>\n";
  writeFileAtomically(path, os.str());
}

void checkImageSize(const PinholeCamera& camera, int width, int height, const std::string& what) {
  if (width != camera.width || height != camera.height)
    throw DataError(str(what, ": image is ", width, "x", height, " but camera '", camera.name, "' is ",
                        camera.width, "x", camera.height));
}

}  // namespace plslam
