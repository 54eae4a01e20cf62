// Camera files: ViSP XML (the vpXmlParserCamera format), so that ViSP tools read them,
// with one addition that ViSP's parser skips (it refuses unknown elements anywhere else):
// an <rgbd> element inside the camera's <additional_information> that carries what ViSP's
// model cannot, the Brown-Conrady distortion (OpenCV order) and the depth scale.
//
//   <root>
//     <camera> <name/> <image_width/> <image_height/>
//       <model> <type>perspectiveProjWithoutDistortion</type> <px/> <py/> <u0/> <v0/> </model>
//       <additional_information>
//         <rgbd> <depth_scale>5000</depth_scale>
//                <distortion> <k1/> <k2/> <p1/> <p2/> <k3/> </distortion> </rgbd>
//       </additional_information>
//     </camera>
//   </root>
//
// <px> and <py> are signed (see pinhole_camera.h): ICL-NUIM's <py>-480</py> is written as
// published. ViSP keeps the sign too (vpXmlParserCamera and vpCameraParameters accept a
// negative px or py, refusing only |p| < 1e-6, and vpMeterPixelConversion uses the sign), so
// no flip needs to be stored elsewhere. Zero and non-finite focal lengths are refused naming
// the file.
//
// A ViSP file without <rgbd> is accepted (depth scale 1000, the RealSense default, is
// assumed and logged); a perspectiveProjWithDistortion model maps kud to k1 (ViSP's
// kud is the radial coefficient from ideal to distorted coordinates, as Brown's k1).
#pragma once

#include <string>

#include "camera/pinhole_camera.h"

namespace plslam {

/// Reads and validates a camera file. `camera_name` selects one <camera> when the file
/// has several (empty: the first). Throws IoError / DataError naming the file.
PinholeCamera loadCameraFile(const std::string& path, const std::string& camera_name = "");
/// Parses file content (path is used only in messages).
PinholeCamera parseCameraFile(const std::string& content, const std::string& path, const std::string& camera_name = "");
/// Writes `camera` in the format above (atomically, see core/atomic_file.h).
void saveCameraFile(const std::string& path, const PinholeCamera& camera, const std::string& comment = "");

/// Throws DataError when an image of `width`x`height` from `what` does not fit `camera`.
void checkImageSize(const PinholeCamera& camera, int width, int height, const std::string& what);

}  // namespace plslam
