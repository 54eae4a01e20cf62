# Every dependency comes from a Debian package (see scripts in .ci/ and tools/setup.sh).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs features2d calib3d video line_descriptor ximgproc dnn)
find_package(Threads REQUIRED)
find_package(ZLIB REQUIRED)  # CRC-32 of the map and vocabulary files (core/crc32.h)
find_package(pugixml REQUIRED)  # camera files (camera/camera_file.cpp)
find_package(nlohmann_json 3 REQUIRED)  # JSON outputs (core/json.h)
find_package(yaml-cpp REQUIRED)  # configuration, grid.yaml and camera-to-base files (core/yaml.h)

# find_package(VISP) rewrites CMAKE_CXX_FLAGS (it appends its own build flags): keep ours.
set(_plslam_saved_cxx_flags "${CMAKE_CXX_FLAGS}")
find_package(VISP REQUIRED COMPONENTS visp_core visp_vision visp_vs visp_robot visp_sensor visp_detection)
set(CMAKE_CXX_FLAGS "${_plslam_saved_cxx_flags}")
if(VISP_HAVE_REALSENSE2)
  message(STATUS "plslam: ViSP has RealSense support: live capture enabled")
else()
  message(STATUS "plslam: ViSP was built without librealsense2: `plslam live`/`record` will report that they are unavailable")
endif()

find_package(Ceres REQUIRED)

# Dense maps. PCL's headers are heavy (seconds and hundreds of MB per file): only the
# few dense/*.cpp files that write clouds include them.
find_package(PCL REQUIRED COMPONENTS common io filters)
find_package(octomap REQUIRED)

# Calibration targets and tag detection.
find_package(apriltag REQUIRED)

# ROS 1 (Debian's Noetic-era packages, no catkin workspace): the ros1 module (bag input),
# the plslam_ros node and their tests. AUTO builds them when the packages are there
# (tools/setup.sh installs them); plslam builds without them. roscpp, tf2_ros and
# message_filters come through pkg-config; rosbag's pkg-config and CMake files pull in
# Debian's pluginlib, which is ROS 2's (ament, its headers one level down in
# /usr/include/<name>/), so librosbag and what its headers include are found directly.
set(PLSLAM_WITH_ROS AUTO CACHE STRING "Build the ROS 1 parts (bag input, plslam_ros node): AUTO, ON or OFF")
set_property(CACHE PLSLAM_WITH_ROS PROPERTY STRINGS AUTO ON OFF)
set(PLSLAM_HAVE_ROS OFF)
if(NOT PLSLAM_WITH_ROS STREQUAL "OFF")
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(PLSLAM_ROS_PC QUIET IMPORTED_TARGET roscpp tf2_ros message_filters)
  endif()
  find_library(PLSLAM_ROSBAG_LIBRARY rosbag)
  find_library(PLSLAM_ROSBAG_STORAGE_LIBRARY rosbag_storage)
  set(_plslam_pluginlib_dirs "")
  foreach(p pluginlib class_loader rcutils rcpputils ament_index_cpp)
    find_path(PLSLAM_ROS_${p}_INCLUDE_DIR NAMES ${p} PATH_SUFFIXES ${p})
    list(APPEND _plslam_pluginlib_dirs ${PLSLAM_ROS_${p}_INCLUDE_DIR})
  endforeach()
  find_library(PLSLAM_CLASS_LOADER_LIBRARY class_loader)
  find_path(PLSLAM_ROS_MESSAGES_INCLUDE_DIR NAMES sensor_msgs/Image.h nav_msgs/Path.h)
  set(_plslam_ros_headers sensor_msgs/Image.h nav_msgs/Path.h geometry_msgs/PoseStamped.h visualization_msgs/Marker.h
      diagnostic_msgs/DiagnosticArray.h std_srvs/Trigger.h rosbag/bag.h)
  set(_plslam_ros_missing "")
  foreach(h ${_plslam_ros_headers})
    if(NOT EXISTS ${PLSLAM_ROS_MESSAGES_INCLUDE_DIR}/${h})
      list(APPEND _plslam_ros_missing ${h})
    endif()
  endforeach()
  if(PLSLAM_ROS_PC_FOUND AND PLSLAM_ROSBAG_LIBRARY AND PLSLAM_ROSBAG_STORAGE_LIBRARY AND PLSLAM_CLASS_LOADER_LIBRARY
     AND PLSLAM_ROS_pluginlib_INCLUDE_DIR AND NOT _plslam_ros_missing)
    set(PLSLAM_HAVE_ROS ON)
    add_library(plslam_ros_deps INTERFACE)
    target_link_libraries(plslam_ros_deps INTERFACE PkgConfig::PLSLAM_ROS_PC ${PLSLAM_ROSBAG_LIBRARY}
                          ${PLSLAM_ROSBAG_STORAGE_LIBRARY} ${PLSLAM_CLASS_LOADER_LIBRARY})
    target_include_directories(plslam_ros_deps SYSTEM INTERFACE ${_plslam_pluginlib_dirs})
    message(STATUS "plslam: ROS 1 found: bag input and the plslam_ros node are built")
  elseif(PLSLAM_WITH_ROS STREQUAL "ON")
    message(FATAL_ERROR "PLSLAM_WITH_ROS=ON but the ROS 1 development packages are incomplete (pkg-config roscpp "
                        "tf2_ros message_filters: ${PLSLAM_ROS_PC_FOUND}; librosbag: ${PLSLAM_ROSBAG_LIBRARY}; "
                        "missing headers: ${_plslam_ros_missing}): run tools/setup.sh")
  else()
    message(STATUS "plslam: ROS 1 not found: no bag input, no plslam_ros node (tools/setup.sh installs the packages)")
  endif()
endif()
