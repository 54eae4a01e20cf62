#!/usr/bin/env python3
"""Per-frame times of a run, block by block: how the cost of a frame changes along a long run.

usage: tools/frames_by_block.py RUN_OUT [BLOCK_FRAMES]

Reads RUN_OUT/frames.csv (written by `plslam run`) and prints, for each block of
BLOCK_FRAMES frames (default 1000), the median and 95th percentile of the tracking time
and the medians of the projection search, the dynamic check and LSD, in ms, the median
size of the local map searched (points and lines: the search's work, whatever the
machine's speed), and the keyframes mapped by the block's end. Then the ratio the long-run figure of issue 16 asks
for: the median tracking time of the last BLOCK_FRAMES frames over that of frames 500 to
1500. Standard library only.
"""
import csv
import statistics
import sys


def column(rows, key):
    return [float(r[key]) for r in rows if r[key] not in ("", None)]


def count_median(rows, key):
    """The median of a count column, or "-" in a frames.csv written before the column existed."""
    if key not in rows[0]:
        return "-"
    return "%d" % statistics.median(column(rows, key))


def p95(values):
    values = sorted(values)
    return values[min(len(values) - 1, int(round(0.95 * (len(values) - 1))))]


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    block = int(sys.argv[2]) if len(sys.argv) == 3 else 1000
    with open(sys.argv[1] + "/frames.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("no frames in " + sys.argv[1] + "/frames.csv")
    print("frames | tracking median | p95 | search median | dynamic median | lsd median | local map points | lines"
          " | keyframes at the end")
    for start in range(0, len(rows), block):
        part = rows[start:start + block]
        tracking = column(part, "tracking_ms")
        print("%d-%d | %.1f | %.1f | %.1f | %.1f | %.1f | %s | %s | %s" % (
            start, start + len(part) - 1, statistics.median(tracking), p95(tracking),
            statistics.median(column(part, "search_ms")), statistics.median(column(part, "dynamic_ms")),
            statistics.median(column(part, "lsd_ms")), count_median(part, "local_points"),
            count_median(part, "local_lines"), part[-1]["keyframes_before"]))
    if len(rows) >= 1500 + block:
        early = statistics.median(column(rows[500:1500], "tracking_ms"))
        late = statistics.median(column(rows[-block:], "tracking_ms"))
        print("tracking median, last %d frames / frames 500-1500: %.1f / %.1f = %.2f" % (block, late, early, late / early))


if __name__ == "__main__":
    main()
