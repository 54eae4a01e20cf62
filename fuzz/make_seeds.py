#!/usr/bin/env python3
"""Writes the small seed corpora of the fuzz targets into fuzz/corpus/<target>/.

Run it again after changing it; crash inputs found by fuzzing are added by hand
(as fuzz/corpus/<target>/crash-<what>) and are never overwritten by this script.
The map_file seeds (tiny_map: serializeMap of a hand-made two-keyframe map, 1.9 kB;
tiny_map_sections: its five sections in the target's 'S' mode) are not written here.
"""
import os
import pathlib

root = pathlib.Path(__file__).resolve().parent
corpus = root / "corpus"


def put(target, name, data):
    d = corpus / target
    d.mkdir(parents=True, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    (d / name).write_bytes(data)


# ---------------------------------------------------------------- TUM / ICL lists
# Byte 0: bit 0 = ICL associations layout, bit 1 = max_frames 3. Parts split by "\n---\n".
rgb = "# colour images\n# file: 'x'\n# timestamp filename\n1305031102.175304 rgb/1305031102.175304.png\n1305031102.211214 rgb/1305031102.211214.png\n1305031102.243211 rgb/1305031102.243211.png\n"
depth = "# depth maps\n1305031102.160407 depth/1305031102.160407.png\n1305031102.226738 depth/1305031102.226738.png\n1305031102.262886 depth/1305031102.262886.png\n"
masks = "1305031102.175304 masks/000000.png\n1305031102.243211 masks/000002.png\n"
gt = "# ground truth\n1305031102.1758 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n1305031102.2258 1.3303 0.6256 1.6464 0.6579 0.6161 -0.2932 -0.3189\n"
put("tum_list", "tum_lists", "\x00" + rgb + "\n---\n" + depth)
put("tum_list", "tum_lists_masks_gt", "\x02" + rgb + "\n---\n" + depth + "\n---\n" + masks + "\n---\n" + gt)
put("tum_list", "tum_crlf_commas", "\x00" + rgb.replace("\n", "\r\n").replace(" ", ",") + "\n---\n" + depth.replace(" ", "\t"))
put("tum_list", "tum_unsorted_duplicates", "\x00" + "2.0 rgb/b.png\n1.0 rgb/a.png\n1.0 rgb/a2.png\n" + "\n---\n" + "1.01 d/a.png\n2.01 d/b.png\n")
put("tum_list", "icl_depth_first", "\x01" + "0 depth/0.png 0 rgb/0.png\n1 depth/1.png 1 rgb/1.png\n" + "\n---\n" + "0 0 0 0 0 0 0 1\n")
put("tum_list", "icl_rgb_first", "\x01" + "0.033 rgb/0.png 0.033 depth/0.png\n")

# ---------------------------------------------------------------- trajectories
put("trajectory", "tum", "# timestamp tx ty tz qx qy qz qw\n" + gt.split("\n", 1)[1])
put("trajectory", "odd_lines", "1.0 0 0 0 0 0 0 1\n1.0 1 1 1 0 0 0 1\nnan 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 0\n3e0,1,2,3,0,0,0,1\r\n2.5\t1 2 3 0 0 0 1 extra\n")

# ---------------------------------------------------------------- camera files
calib = root.parent / "calib"
for f in sorted(calib.glob("*.xml")):
    put("camera_file", f.stem, f.read_bytes())
put("camera_file", "visp_with_distortion",
    "<?xml version=\"1.0\"?>\n<root><camera><name>c</name><image_width>640</image_width><image_height>480</image_height>"
    "<model><type>perspectiveProjWithDistortion</type><px>500</px><py>500</py><u0>320</u0><v0>240</v0><kud>0.1</kud><kdu>-0.1</kdu></model>"
    "</camera></root>\n")
put("camera_file", "bom_references_doctype",
    "\ufeff<?xml version='1.0'?><!DOCTYPE root><root a='>'><!-- c --><camera><name>a&amp;&lt;&#x3c;&#38;</name>"
    "<image_width>&#54;40</image_width><image_height>480</image_height><?pi x?>"
    "<model><type><![CDATA[perspectiveProjWithoutDistortion]]></type><px>500</px><py>500</py><u0>320</u0><v0>240</v0></model>"
    "</camera></root>\n")

# ---------------------------------------------------------------- run configuration
put("config", "sections",
    "%YAML 1.2\n---\n# plslam run configuration\nsystem:\n  sequential: true\n  use_lines: false\n  mapping_queue: 4\n"
    "tracker:\n  min_inliers: 20\n  ratio: 0.8  # comment\n  max_depth_m: 6.5\n"
    "dynamic:\n  enabled: 'off'\n  yolo_confidence: \"0.4\"\nmapper:\n  ba_max_time_s: 0.2\n  local_ba: yes\n")
put("config", "bad_constructs", "tracker:\n  min_inliers: [1, 2]\n  - x\nmapper: &a\n  b: *a\n")

# ---------------------------------------------------------------- class names
put("class_list", "names", "person\nbicycle\ncar\nmotorbike\ndog\n")
put("class_list", "bom_crlf", "\ufeffperson\r\n  chair  \r\ncouch\r\n\r\n\r\n")
put("class_list", "blank_inside", "person\n\ncar\n")


# ---------------------------------------------------------------- ONNX framing
def varint(v):
    out = bytearray()
    while True:
        b = v & 0x7F
        v >>= 7
        out.append(b | (0x80 if v else 0))
        if not v:
            return bytes(out)


def fvar(f, v):
    return varint(f << 3) + varint(v)


def fbytes(f, b):
    if isinstance(b, str):
        b = b.encode()
    return varint((f << 3) | 2) + varint(len(b)) + b


def value_info(name, dims):
    shape = b"".join(fbytes(1, fvar(1, d) if d >= 0 else fbytes(2, "batch")) for d in dims)
    tensor = fvar(1, 1) + fbytes(2, shape)
    return fbytes(1, name) + fbytes(2, fbytes(1, tensor))


def model(outputs):
    graph = b""
    for name, _ in outputs:
        graph += fbytes(1, fbytes(1, "images") + fbytes(2, name) + fbytes(3, name + "_node") + fbytes(4, "Identity"))
    graph += fbytes(2, "seed")
    graph += fbytes(5, fbytes(8, "w") + fvar(2, 1))  # an initializer
    graph += fbytes(11, value_info("images", [1, 3, 320, 320]))
    for name, dims in outputs:
        graph += fbytes(12, value_info(name, dims))
    return fvar(1, 8) + fbytes(2, "pytorch") + fbytes(7, graph) + fbytes(8, fvar(2, 13))


put("onnx", "yolov8_seg_layout", model([("output0", [1, 116, 2100]), ("output1", [1, 32, 80, 80])]))
put("onnx", "symbolic_batch", model([("output1", [-1, 32, 80, 80]), ("output0", [-1, 116, 2100])]))
put("onnx", "detection_only", model([("output0", [1, 84, 8400])]))
