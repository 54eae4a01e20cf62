// Checks of a model file before OpenCV is asked to load it, so that a wrong file gives a
// clear typed error naming it rather than an OpenCV assertion deep in the importer.
//
// inspectOnnx*() walks the protobuf framing of an ONNX ModelProto without a protobuf
// library: the top-level fields (ir_version, field 1, a varint, comes first; the graph is
// field 7) with every length checked against the bytes left, then, inside the graph, the
// declared inputs and outputs with their shapes. The walk is bounded (fixed nesting, no
// recursion on the data) and never reads past the buffer, whatever the bytes.
//
// checkYoloSegOutputs() checks output shapes against the YOLOv8-seg layout:
// two outputs, detections [1, 4 + C + M, N] and mask prototypes [1, M, H, W].
//
// Thread safety: free functions without shared state.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace plslam {

/// A graph input or output as the ONNX file declares it.
struct OnnxValueInfo {
  std::string name;
  std::vector<int64_t> dims;  ///< -1 where the dimension is symbolic or not given
};

/// What the ONNX framing says about a model.
struct OnnxModelInfo {
  int64_t ir_version = 0;
  std::string producer;                ///< producer_name (may be empty)
  std::vector<OnnxValueInfo> inputs;   ///< graph inputs that are not initializers
  std::vector<OnnxValueInfo> outputs;  ///< graph outputs
  size_t bytes = 0;                    ///< size of the file / buffer
};

/// Reads `path` and inspects it. Throws IoError naming the file when it is missing,
/// unreadable, empty, larger than protobuf's 2 GiB, or not an ONNX model (wrong framing,
/// truncated, no graph) with the offset where the framing breaks.
OnnxModelInfo inspectOnnxFile(const std::string& path);

/// The same on bytes in memory; `what` names them in messages.
OnnxModelInfo inspectOnnxBytes(const std::string& bytes, const std::string& what);

/// The YOLOv8-seg output layout.
struct YoloSegLayout {
  int detections_output = 0;  ///< index of the [1, 4+C+M, N] output in the given list
  int num_classes = 0;        ///< C
  int num_masks = 0;          ///< M (mask coefficients per detection = prototype channels)
  int num_anchors = 0;        ///< N (candidate boxes)
  int proto_height = 0;       ///< H of the prototypes
  int proto_width = 0;        ///< W of the prototypes
};

/// Checks output shapes (e.g. from a forward pass) against the YOLOv8-seg layout; the two
/// outputs may come in either order. A dimension -1 (unknown) is not checked, and the
/// corresponding layout field is then 0. Throws DataError naming `what`, the shapes and
/// the problem.
YoloSegLayout checkYoloSegOutputs(const std::vector<std::vector<int64_t>>& shapes, const std::string& what);

/// "[1, 116, 2100]" (-1 printed as '?').
std::string shapeToString(const std::vector<int64_t>& dims);

}  // namespace plslam
