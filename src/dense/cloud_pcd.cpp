// The only file of the module that includes PCL (its headers are heavy to compile): the PCD
// header and field layout come from PCL itself, so any PCL reads the file back.
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <cstring>

#include "dense/cloud_fusion.h"

namespace plslam {

std::string cloudToPcd(const std::vector<FusedPoint>& cloud) {
  using PointT = pcl::PointXYZRGBL;
  pcl::PointCloud<PointT> header_cloud;  // generateHeader reads only the size and layout
  header_cloud.width = static_cast<uint32_t>(cloud.size());
  header_cloud.height = 1;
  header_cloud.is_dense = true;
  std::string s = pcl::PCDWriter::generateHeader<PointT>(header_cloud, static_cast<int>(cloud.size()));
  s += "DATA binary\n";

  // Same record layout as PCDWriter::writeBinary: the named fields packed, padding dropped.
  std::vector<pcl::PCLPointField> fields;
  size_t record = 0;
  for (const pcl::PCLPointField& f : pcl::getFields<PointT>()) {
    if (f.name == "_") continue;
    fields.push_back(f);
    record += f.count * pcl::getFieldSize(f.datatype);
  }
  const size_t header = s.size();
  s.resize(header + record * cloud.size());
  char* out = s.data() + header;
  PointT q;
  for (const FusedPoint& p : cloud) {
    q.x = p.p_w.x();
    q.y = p.p_w.y();
    q.z = p.p_w.z();
    q.r = p.r;
    q.g = p.g;
    q.b = p.b;
    q.a = 255;
    q.label = static_cast<uint32_t>(p.class_id + 1);  // 0: no class
    for (const pcl::PCLPointField& f : fields) {
      const size_t n = f.count * pcl::getFieldSize(f.datatype);
      std::memcpy(out, reinterpret_cast<const char*>(&q) + f.offset, n);
      out += n;
    }
  }
  return s;
}

}  // namespace plslam
