#include "dynamic/onnx_check.h"

#include <algorithm>
#include <fstream>
#include <set>
#include <tuple>

#include "core/error.h"
#include "core/log.h"

namespace plslam {
namespace {

constexpr uint64_t kMaxProtobufBytes = 2147483647ull;  // protobuf refuses messages of 2 GiB and more
constexpr size_t kMaxValues = 100000;                  // graph inputs/outputs kept (a sanity bound)
constexpr size_t kMaxDims = 64;                        // dimensions kept per tensor
constexpr size_t kMaxString = 4096;                    // characters kept per name

// Thrown inside the walk; turned into IoError with the file name at the top.
struct FramingError {
  std::string message;
};

// A bounded view of protobuf bytes. Every read checks the bytes left.
class Reader {
 public:
  Reader(const uint8_t* data, size_t begin, size_t end) : data_(data), pos_(begin), end_(end) {}
  bool atEnd() const { return pos_ >= end_; }
  size_t pos() const { return pos_; }

  uint64_t varint(const char* what) {
    uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos_ >= end_) throw FramingError{str("truncated varint (", what, ") at offset ", pos_)};
      const uint8_t b = data_[pos_++];
      value |= static_cast<uint64_t>(b & 0x7f) << shift;
      if ((b & 0x80) == 0) return value;
    }
    throw FramingError{str("varint longer than 10 bytes (", what, ") at offset ", pos_)};
  }

  // Reads a field key; returns false at the end of the message.
  bool key(uint64_t* field, int* wire) {
    if (atEnd()) return false;
    const size_t at = pos_;
    const uint64_t k = varint("field key");
    *field = k >> 3;
    *wire = static_cast<int>(k & 7);
    if (*field == 0) throw FramingError{str("field number 0 at offset ", at)};
    if (*wire == 3 || *wire == 4 || *wire > 5)
      throw FramingError{str("invalid wire type ", *wire, " for field ", *field, " at offset ", at)};
    return true;
  }

  // For a length-delimited field: the [begin, end) of its payload, checked against the bytes left.
  std::pair<size_t, size_t> span(uint64_t field, const char* what) {
    const size_t at = pos_;
    const uint64_t len = varint("length");
    if (len > end_ - pos_)
      throw FramingError{str("truncated: field ", field, " (", what, ") at offset ", at, " declares ", len,
                             " bytes but only ", end_ - pos_, " remain")};
    const size_t b = pos_;
    pos_ += static_cast<size_t>(len);
    return {b, pos_};
  }

  void skip(uint64_t field, int wire) {
    switch (wire) {
      case 0: varint("value"); break;
      case 1: advance(8, field); break;
      case 5: advance(4, field); break;
      case 2: span(field, "bytes"); break;
      default: throw FramingError{str("invalid wire type ", wire)};
    }
  }

  std::string string(uint64_t field, const char* what) {
    const auto [b, e] = span(field, what);
    const size_t n = std::min(e - b, kMaxString);
    return std::string(reinterpret_cast<const char*>(data_ + b), n);
  }

  const uint8_t* data() const { return data_; }

 private:
  void advance(size_t n, uint64_t field) {
    if (n > end_ - pos_) throw FramingError{str("truncated fixed-size field ", field, " at offset ", pos_)};
    pos_ += n;
  }
  const uint8_t* data_;
  size_t pos_, end_;
};

void expectWire(int wire, int expected, uint64_t field, const char* what, size_t at) {
  if (wire != expected)
    throw FramingError{str("field ", field, " (", what, ") has wire type ", wire, ", expected ", expected,
                           " (offset ", at, ")")};
}

// TensorShapeProto.Dimension: dim_value = 1 (varint), dim_param = 2 (string).
int64_t parseDimension(Reader r) {
  int64_t value = -1;
  uint64_t f;
  int w;
  while (r.key(&f, &w)) {
    if (f == 1 && w == 0) {
      value = static_cast<int64_t>(r.varint("dim_value"));
    } else {
      r.skip(f, w);
    }
  }
  return value;
}

// TypeProto { tensor_type = 1 { elem_type = 1, shape = 2 { dim = 1 } } }.
std::vector<int64_t> parseType(Reader r) {
  std::vector<int64_t> dims;
  uint64_t f;
  int w;
  while (r.key(&f, &w)) {
    if (f != 1 || w != 2) {
      r.skip(f, w);
      continue;
    }
    const auto [tb, te] = r.span(f, "tensor_type");
    Reader tensor(r.data(), tb, te);
    uint64_t tf;
    int tw;
    while (tensor.key(&tf, &tw)) {
      if (tf != 2 || tw != 2) {
        tensor.skip(tf, tw);
        continue;
      }
      const auto [sb, se] = tensor.span(tf, "shape");
      Reader shape(r.data(), sb, se);
      uint64_t sf;
      int sw;
      while (shape.key(&sf, &sw)) {
        if (sf != 1 || sw != 2) {
          shape.skip(sf, sw);
          continue;
        }
        const auto [db, de] = shape.span(sf, "dim");
        if (dims.size() < kMaxDims) dims.push_back(parseDimension(Reader(r.data(), db, de)));
      }
    }
  }
  return dims;
}

// ValueInfoProto { name = 1, type = 2 }.
OnnxValueInfo parseValueInfo(Reader r) {
  OnnxValueInfo info;
  uint64_t f;
  int w;
  while (r.key(&f, &w)) {
    if (f == 1 && w == 2) {
      info.name = r.string(f, "name");
    } else if (f == 2 && w == 2) {
      const auto [b, e] = r.span(f, "type");
      info.dims = parseType(Reader(r.data(), b, e));
    } else {
      r.skip(f, w);
    }
  }
  return info;
}

// TensorProto: name = 8.
std::string parseTensorName(Reader r) {
  uint64_t f;
  int w;
  std::string name;
  while (r.key(&f, &w)) {
    if (f == 8 && w == 2)
      name = r.string(f, "name");
    else
      r.skip(f, w);
  }
  return name;
}

// GraphProto: initializer = 5, input = 11, output = 12.
void parseGraph(Reader r, OnnxModelInfo* info) {
  std::vector<OnnxValueInfo> inputs;
  std::set<std::string> initializers;
  uint64_t f;
  int w;
  while (r.key(&f, &w)) {
    if (w == 2 && (f == 11 || f == 12)) {
      const auto [b, e] = r.span(f, f == 11 ? "graph input" : "graph output");
      OnnxValueInfo v = parseValueInfo(Reader(r.data(), b, e));
      auto& list = f == 11 ? inputs : info->outputs;
      if (list.size() < kMaxValues) list.push_back(std::move(v));
    } else if (w == 2 && f == 5) {
      const auto [b, e] = r.span(f, "initializer");
      if (initializers.size() < kMaxValues) initializers.insert(parseTensorName(Reader(r.data(), b, e)));
    } else {
      r.skip(f, w);
    }
  }
  // Before IR version 4 the initializers were listed among the inputs too.
  for (auto& v : inputs)
    if (!initializers.count(v.name)) info->inputs.push_back(std::move(v));
}

OnnxModelInfo inspect(const uint8_t* data, size_t size) {
  OnnxModelInfo info;
  info.bytes = size;
  if (size == 0) throw FramingError{"empty file"};
  if (data[0] != 0x08)
    throw FramingError{str("not an ONNX model: it does not start with the ir_version field (byte 0x08), first byte is 0x",
                           "0123456789abcdef"[data[0] >> 4], "0123456789abcdef"[data[0] & 15])};
  Reader r(data, 0, size);
  bool have_graph = false, have_opset = false;
  size_t graph_begin = 0, graph_end = 0;
  uint64_t f;
  int w;
  while (true) {
    const size_t at = r.pos();
    if (!r.key(&f, &w)) break;
    if (f == 1) {
      expectWire(w, 0, f, "ir_version", at);
      info.ir_version = static_cast<int64_t>(r.varint("ir_version"));
    } else if (f == 2 && w == 2) {
      info.producer = r.string(f, "producer_name");
    } else if (f == 7) {
      expectWire(w, 2, f, "graph", at);
      std::tie(graph_begin, graph_end) = r.span(f, "graph");
      have_graph = true;
    } else if (f == 8 && w == 2) {
      r.span(f, "opset_import");
      have_opset = true;
    } else {
      r.skip(f, w);
    }
  }
  // ONNX IR versions are small integers (10 in 2024); anything else is random bytes.
  if (info.ir_version < 1 || info.ir_version > 100)
    throw FramingError{str("not an ONNX model: implausible ir_version ", info.ir_version)};
  if (!have_graph) throw FramingError{"not an ONNX model: no graph (field 7)"};
  // Required since IR version 3; it is written after the graph, so a file cut after its
  // graph is caught here.
  if (!have_opset && info.ir_version >= 3) throw FramingError{"truncated or not an ONNX model: no opset_import (field 8)"};
  parseGraph(Reader(data, graph_begin, graph_end), &info);
  return info;
}

}  // namespace

OnnxModelInfo inspectOnnxBytes(const std::string& bytes, const std::string& what) {
  if (bytes.size() > kMaxProtobufBytes)
    throw IoError(str("model '", what, "': ", bytes.size(), " bytes, larger than protobuf's 2 GiB limit"));
  try {
    return inspect(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  } catch (const FramingError& e) {
    const bool plain = e.message.rfind("not an ONNX", 0) == 0 || e.message.rfind("truncated", 0) == 0 ||
                       e.message.rfind("empty", 0) == 0;
    throw IoError(str("model '", what, "' (", bytes.size(), " bytes): ",
                      plain ? "" : "not an ONNX model (broken protobuf framing): ", e.message));
  }
}

OnnxModelInfo inspectOnnxFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw IoError(str("model '", path, "': cannot open (missing or unreadable)"));
  const std::streamoff size = in.tellg();
  if (size < 0) throw IoError(str("model '", path, "': cannot read its size (not a regular file?)"));
  if (static_cast<uint64_t>(size) > kMaxProtobufBytes)
    throw IoError(str("model '", path, "': ", size, " bytes, larger than protobuf's 2 GiB limit"));
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (size > 0 && !in.read(&bytes[0], size)) throw IoError(str("model '", path, "': read error"));
  return inspectOnnxBytes(bytes, path);
}

std::string shapeToString(const std::vector<int64_t>& dims) {
  std::string s = "[";
  for (size_t i = 0; i < dims.size(); ++i) {
    if (i) s += ", ";
    s += dims[i] < 0 ? std::string("?") : std::to_string(dims[i]);
  }
  return s + "]";
}

YoloSegLayout checkYoloSegOutputs(const std::vector<std::vector<int64_t>>& shapes, const std::string& what) {
  std::string all;
  for (const auto& s : shapes) all += (all.empty() ? "" : ", ") + shapeToString(s);
  const std::string expected = "a YOLOv8-seg model has 2 outputs, detections [1, 4+C+M, N] and mask prototypes [1, M, H, W]";
  if (shapes.size() != 2)
    throw DataError(str("model '", what, "': ", shapes.size(), " output(s) {", all, "}; ", expected));
  int det = -1, proto = -1;
  for (int i = 0; i < 2; ++i) {
    if (shapes[i].size() == 3) det = i;
    if (shapes[i].size() == 4) proto = i;
  }
  if (det < 0 || proto < 0)
    throw DataError(str("model '", what, "': outputs {", all, "} are not one 3-D and one 4-D tensor; ", expected));
  const auto& d = shapes[det];
  const auto& p = shapes[proto];
  auto known = [](int64_t v) { return v >= 0; };
  if ((known(d[0]) && d[0] != 1) || (known(p[0]) && p[0] != 1))
    throw DataError(str("model '", what, "': outputs {", all, "} do not have batch size 1"));
  for (size_t k = 1; k < 4; ++k)
    if ((k < 3 && d[k] == 0) || p[k] == 0)
      throw DataError(str("model '", what, "': outputs {", all, "} have an empty dimension"));
  YoloSegLayout layout;
  layout.detections_output = det;
  layout.num_masks = known(p[1]) ? static_cast<int>(p[1]) : 0;
  layout.proto_height = known(p[2]) ? static_cast<int>(p[2]) : 0;
  layout.proto_width = known(p[3]) ? static_cast<int>(p[3]) : 0;
  layout.num_anchors = known(d[2]) ? static_cast<int>(d[2]) : 0;
  if (known(d[1]) && known(p[1])) {
    const int64_t classes = d[1] - 4 - p[1];
    if (classes < 1)
      throw DataError(str("model '", what, "': detections ", shapeToString(d), " have ", d[1],
                          " rows, which leave no class scores beside 4 box values and the ", p[1],
                          " mask coefficients of the prototypes ", shapeToString(p), "; ", expected));
    layout.num_classes = static_cast<int>(classes);
  }
  return layout;
}

}  // namespace plslam
