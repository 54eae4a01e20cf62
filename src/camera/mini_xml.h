// A small XML reader for the flat files plslam reads (ViSP camera files): elements,
// text, comments and the XML declaration; attributes are skipped; no DTDs or entities
// other than the five predefined ones. Errors carry the line number.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace plslam {

struct XmlNode {
  std::string name;
  std::string text;  ///< concatenated character data, trimmed
  int line = 0;      ///< line of the start tag
  std::vector<XmlNode> children;

  /// First child with this name, or nullptr.
  const XmlNode* child(const std::string& n) const;
  std::vector<const XmlNode*> childrenNamed(const std::string& n) const;
};

/// Parses a document and returns its root element. Throws IoError("<source>:<line>: ...").
XmlNode parseXml(const std::string& content, const std::string& source);

}  // namespace plslam
