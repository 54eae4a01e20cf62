#include "mapping_session.h"

#include "dense_cli.h"
#include "system/run_outputs.h"

namespace plslam::cli {

MappingSession::MappingSession(const PinholeCamera& camera, RunConfig* config, std::string out, bool dense)
    : camera_(camera),
      config_(config),
      out_(std::move(out)),
      dense_(dense),
      // A saved map keeps its own frame, so that its sessions share one map frame.
      frame_(config->map ? config->map->frame : std::nullopt),
      slam_(camera, config->options, config->map ? std::move(config->map->map) : Map()) {
  if (dense_) maps_ = makeLiveMaps(&slam_, out_, frame_ ? &*frame_ : nullptr);
}

void MappingSession::start() {
  slam_.start();
  if (maps_) maps_->start();
}

void MappingSession::stop() {
  if (maps_) maps_->stop();
  slam_.finish();
}

bool MappingSession::writeOutputs(Json stats_extra, const std::string& save_map, bool progress) {
  // The dense products first: the floor of their cloud gives the map frame of every output
  // unless a saved map or the maps while running already fixed it (the final products must
  // line up with what was written while running).
  if (maps_ && !frame_) frame_ = maps_->settledFrame();
  if (maps_) stats_extra.update(liveMapsStatsJson(maps_->stats()));
  bool dense_done = true;
  if (dense_ && !slam_.map().keyframes().empty())
    dense_done = writeDenseMaps(slam_.map(), camera_, config_->options.dense, {}, out_, progress,
                                frame_ ? &*frame_ : nullptr, &frame_);
  writeRunOutputs(out_, slam_, config_->config_yaml, stats_extra, save_map, frame_ ? &*frame_ : nullptr);
  return dense_done;
}

}  // namespace plslam::cli
