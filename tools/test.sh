#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds incrementally, runs CTest.
# Tests that need ../shared (real TUM data, models) skip visibly when it is absent;
# point PLSLAM_SHARED_DIR elsewhere to use another copy.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/tools/setup.sh"
build_dir="${PLSLAM_BUILD_DIR:-$root/build}"
# A test that hangs fails after PLSLAM_TEST_TIMEOUT seconds (the longest, Soak, takes about two
# minutes) instead of holding CI until its own limit.
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" --timeout "${PLSLAM_TEST_TIMEOUT:-900}" "$@"
