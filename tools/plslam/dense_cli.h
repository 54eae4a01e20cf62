// The dense products from the command line, shared by `plslam run` (at the end of a run)
// and `plslam export` (from a saved map): a progress line on stderr, Ctrl-C stopping the
// build without leaving a partial file, and a summary of time, memory and file sizes.
#pragma once

#include <optional>
#include <string>

#include "core/map.h"
#include "dense/dense_products.h"

namespace plslam::cli {

/// Builds the selected products of `map` (seen by `camera`) in the map frame `given` (a
/// saved map's; null: found from the floor of the fused cloud) and writes them into `dir`.
/// Prints one line per step (time, peak resident memory) and per file (size) on stdout.
/// `used` (may be null) receives the map frame of the products, unless Ctrl-C came before
/// it was found. Returns false when Ctrl-C stopped it (then only dense_products.json,
/// marked cancelled, is written).
bool writeDenseMaps(const Map& map, const PinholeCamera& camera, const DenseOptions& options,
                    const DenseSelection& what, const std::string& dir, bool progress,
                    const MapFrame* given = nullptr, std::optional<MapFrame>* used = nullptr);

}  // namespace plslam::cli
