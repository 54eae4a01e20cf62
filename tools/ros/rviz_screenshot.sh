#!/usr/bin/env bash
# A picture of the node at work, without a screen: plays a bag into plslam_ros and takes a
# screenshot of rviz (tools/ros/plslam.rviz) under Xvfb once the maps while running have
# caught up. Everything talks on 127.0.0.1 (its own rosmaster on a free port).
#
#   tools/ros/rviz_screenshot.sh BAG OUT.png [SECONDS_AFTER_PLAY]
#
# BAG in TUM's layout (`plslam record --bag B --fake FOLDER --fake-speed 0` makes one from a
# folder). Needs, besides tools/setup.sh's packages: apt-get install rviz xvfb imagemagick
# python3-rosbag. The bag is played at half speed and the maps thread runs at nice 0, so a
# loaded 2-core machine drops fewer frames and the last dense update lands before the picture.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bag="$1" png="$2" settle="${3:-60}"
work="$(mktemp -d)"
port="$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
display=":$((90 + RANDOM % 100))"
export ROS_MASTER_URI="http://127.0.0.1:$port" ROS_IP=127.0.0.1
pids=()
cleanup() { kill "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true; }
trap cleanup EXIT
rosmaster --core -p "$port" >"$work/master.log" 2>&1 & pids+=($!)
Xvfb "$display" -screen 0 1400x900x24 >"$work/xvfb.log" 2>&1 & pids+=($!)
printf 'dense:\n  live_nice: 0\n' >"$work/config.yaml"
sleep 3
"$root/build/plslam_ros" camera/color/image_raw:=/camera/rgb/image_color \
  camera/aligned_depth_to_color/image_raw:=/camera/depth/image camera/color/camera_info:=/camera/rgb/camera_info \
  _out:="$work/out" _config:="$work/config.yaml" __name:=plslam >"$work/node.log" 2>&1 &
node=$!
DISPLAY="$display" LIBGL_ALWAYS_SOFTWARE=1 rviz -d "$root/tools/ros/plslam.rviz" >"$work/rviz.log" 2>&1 & pids+=($!)
sleep 8
rosbag play -q -r 0.5 "$bag" >"$work/play.log" 2>&1
sleep "$settle"
DISPLAY="$display" import -window root "$png"
kill -INT "$node"
wait "$node" || true
echo "wrote $png (node outputs and logs in $work)"
