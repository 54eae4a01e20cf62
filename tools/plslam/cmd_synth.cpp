// plslam synth: render a synthetic RGB-D scene with exact ground truth into a TUM-style
// folder (layout documented in src/synth/dataset.h) and/or a preview contact sheet.
#include <chrono>
#include <cstdio>
#include <iostream>

#include "progress_line.h"
#include "args.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "synth/dataset.h"
#include "synth/scene.h"

namespace plslam::cli {

namespace {

int runSynth(int argc, char** argv) {
  Args args("synth", "Render a synthetic RGB-D scene (colour, depth, instance masks, exact ground truth).");
  args.option("scene", "static, dynamic, loop, crowded, fast or loop_walkers", "static")
      .option("frames", "number of frames at 30 Hz [default: 300; loop, loop_walkers: 450, one lap]")
      .option("out", "output folder (TUM layout: rgb/ depth/ masks/ rgb.txt depth.txt masks.txt groundtruth.txt ...)")
      .option("laps", "loop scene: laps round the room over the frames (e.g. --frames 5000 --laps 11 for a long run)", "1")
      .option("seed", "seed of the textures and the noise", "1")
      .flag("no-noise", "exact depth: no depth noise, no dropouts, no colour noise")
      .flag("twin-shelf", "add copies of the shelf's boxes and books (same textures) on the floor by the south wall, in another layout")
      .option("max-rotation", "fast scene: peak rotation rate of the bursts, deg/s", "180")
      .option("exposure-ms", "fast scene: exposure time centred on each stamp (motion blur)", "12")
      .flag("no-blur", "fast scene: sharp images (colour at the stamp only)")
      .flag("no-gain", "fast scene: constant exposure gain")
      .option("width", "image width (the focal length scales with it)", "640")
      .option("height", "image height", "480")
      .option("depth-offset-ms", "depth stamps = colour stamps + this many milliseconds", "0")
      .option("threads", "frames rendered in parallel (the output does not depend on it)", "2")
      .option("preview", "also write a contact sheet PNG (3 frames: colour, depth, masks)")
      .epilog(
          "At least one of --out and --preview is needed. The same options and seed give\n"
          "byte-identical files. Example:\n"
          "  plslam synth --scene dynamic --frames 300 --out /tmp/dyn --preview /tmp/dyn.png\n"
          "  plslam synth --scene fast --out /tmp/fast    (blurred, varying gain; --no-blur --no-gain to separate them)");
  if (!args.parse(argc, argv)) return 0;
  if (!args.has("out") && !args.has("preview")) throw ConfigError("plslam synth: give --out DIR and/or --preview FILE.png");

  const synth::SceneKind kind = synth::parseSceneKind(args.str("scene"));
  synth::SceneOptions opt;
  opt.frames = args.has("frames") ? args.integer("frames", 1, 1000000) : synth::defaultFrameCount(kind);
  const std::string seed_text = args.str("seed");
  try {
    size_t used = 0;
    opt.seed = std::stoull(seed_text, &used);
    if (used != seed_text.size() || seed_text[0] == '-') throw std::invalid_argument(seed_text);
  } catch (const std::exception&) {
    throw ConfigError("plslam synth: --seed expects a non-negative whole number, got '" + seed_text + "'");
  }
  opt.width = args.integer("width", 16, 8192);
  opt.height = args.integer("height", 16, 8192);
  opt.noise.enabled = !args.has("no-noise");
  opt.twin_shelf = args.has("twin-shelf");
  opt.laps = args.integer("laps", 1, 10000);
  if (opt.laps != 1 && kind != synth::SceneKind::kLoop) throw ConfigError("plslam synth: --laps is for the loop scene");
  for (const char* fast_only : {"max-rotation", "exposure-ms", "no-blur", "no-gain"})
    if (args.has(fast_only) && kind != synth::SceneKind::kFast)
      throw ConfigError(str("plslam synth: --", fast_only, " is for the fast scene"));
  opt.fast.max_rotation_deg_s = args.number("max-rotation");
  opt.fast.exposure_ms = args.number("exposure-ms");
  opt.fast.motion_blur = !args.has("no-blur");
  opt.fast.gain = !args.has("no-gain");
  const synth::Scene scene = synth::makeScene(kind, opt);

  if (args.has("out")) {
    synth::DatasetOptions dopt;
    dopt.depth_offset_ns = static_cast<TimeNs>(args.number("depth-offset-ms") * 1e6);
    dopt.threads = args.integer("threads", 1, 64);
    const auto start = std::chrono::steady_clock::now();
    ProgressLine line("synth");
    dopt.progress = [&](int done, int total) {
      if (done % 10 != 0 && done != total) return;
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      line.update("%s: frame %d/%d (%.1f s, %.0f ms/frame)", synth::sceneKindName(kind), done, total, s,
                  1000.0 * s / done);
    };
    synth::writeDataset(scene, args.str("out"), dopt);
    line.done();
    std::cout << "wrote " << opt.frames << " frames of the '" << synth::sceneKindName(kind) << "' scene to "
              << args.str("out") << "\n";
  }
  if (args.has("preview")) {
    synth::writePreview(scene, args.str("preview"));
    std::cout << "wrote preview " << args.str("preview") << "\n";
  }
  return 0;
}

}  // namespace

Command makeSynthCommand() {
  return {"synth", "render a synthetic RGB-D scene with ground truth (static, dynamic, loop, crowded, fast)", runSynth};
}

}  // namespace plslam::cli
