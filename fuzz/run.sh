#!/usr/bin/env bash
# Runs the libFuzzer targets built in build-fuzz (cmake --preset fuzz && cmake --build --preset fuzz).
#
#   fuzz/run.sh [SECONDS] [TARGET...]     default: 20 s each, every target
#
# Each target starts from its committed seeds (fuzz/corpus/<target>/, read-only here) and
# writes what it discovers to build-fuzz/fuzz-work/<target>/ (not committed). A crash
# leaves build-fuzz/fuzz-work/<target>/crash-* and makes the script fail; copy the input
# into fuzz/corpus/<target>/ with the fix, so tests/reliability replays it from then on.
#   PLSLAM_FUZZ_BUILD   build folder (default: build-fuzz)
#   PLSLAM_FUZZ_RUNS    when set: that many inputs per target from a fixed random seed, in a
#                       fresh work folder, instead of SECONDS: the same inputs every time (CI,
#                       so that a red run points at a change, not at luck)
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${PLSLAM_FUZZ_BUILD:-$root/build-fuzz}"
seconds="${1:-20}"
shift || true
targets=("$@")
if ((${#targets[@]} == 0)); then
  for exe in "$build"/fuzz/fuzz_*; do
    [ -x "$exe" ] && targets+=("$(basename "$exe" | sed 's/^fuzz_//')")
  done
fi
if ((${#targets[@]} == 0)); then
  echo "fuzz/run.sh: no fuzz targets in $build/fuzz (cmake --preset fuzz && cmake --build --preset fuzz)" >&2
  exit 1
fi
# Third-party leaks at exit are not ours; the parsers' own leaks are found by ASan in the
# corpus replay (tests/reliability) as well.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$root/tests/reliability/sanitizers/lsan.supp:print_suppressions=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
status=0
printf "%-12s %10s %8s %8s %s\n" target executions exec/s corpus result
for t in "${targets[@]}"; do
  exe="$build/fuzz/fuzz_$t"
  work="$build/fuzz-work/$t"
  mkdir -p "$work"
  log="$work/last-run.log"
  if [ -n "${PLSLAM_FUZZ_RUNS:-}" ]; then
    rm -rf "$work" && mkdir -p "$work"
    budget=(-runs="$PLSLAM_FUZZ_RUNS" -seed=1)
  else
    budget=(-max_total_time="$seconds")
  fi
  "$exe" "${budget[@]}" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -artifact_prefix="$work/" "$work" "$root/fuzz/corpus/$t" >"$log" 2>&1
  rc=$?
  # The last stats line: a crashed run prints its final stats twice (sanitizer stop, then
  # libFuzzer's own crash handler), so adding them up would double the figures.
  runs=$(grep -E "^stat::number_of_executed_units" "$log" | awk '{s=$2} END {print s+0}')
  speed=$(grep -E "^stat::average_exec_per_sec" "$log" | awk '{s=$2} END {print s+0}')
  corpus=$(find "$work" -maxdepth 1 -type f ! -name '*.log' ! -name 'crash-*' ! -name 'leak-*' ! -name 'timeout-*' ! -name 'oom-*' | wc -l)
  result=ok
  if [ $rc -ne 0 ]; then
    result="FAILED (exit $rc): see $log"
    status=1
  fi
  printf "%-12s %10s %8s %8s %s\n" "$t" "$runs" "$speed" "$corpus" "$result"
done
exit $status
