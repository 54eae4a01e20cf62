# Every dependency comes from a Debian package (see scripts in .ci/ and tools/setup.sh).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs features2d calib3d video line_descriptor ximgproc dnn)
find_package(Threads REQUIRED)

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
