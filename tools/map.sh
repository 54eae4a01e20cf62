#!/usr/bin/env bash
# The main job: installs what is missing, builds, then maps.
#   tools/map.sh                         the embedded default: a synthetic sequence, ATE printed, outputs in maps/
#   tools/map.sh --dataset DIR --calib FILE [plslam run options]   a TUM-format folder
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/tools/setup.sh"
build_dir="${PLSLAM_BUILD_DIR:-$root/build}"
plslam="$build_dir/plslam"

if ! "$plslam" --help 2>/dev/null | grep -q "^  run "; then
  echo "plslam is built ($plslam), but the mapping run (plslam run) has not landed yet." >&2
  echo "Available now: $plslam --help" >&2
  exit 3
fi

if [ $# -eq 0 ]; then
  data="$root/maps/synthetic_static"
  if [ ! -f "$data/rgb.txt" ]; then
    "$plslam" synth --scene static --frames 300 --out "$data"
  fi
  out="$root/maps/synthetic_static_run"
  "$plslam" run --dataset "$data" --calib "$data/camera.xml" --out "$out"
  "$plslam" eval --gt "$data/groundtruth.txt" --est "$out/trajectory.txt" --plot "$out/trajectory.png"
  echo "outputs: $out"
else
  "$plslam" run "$@"
fi
