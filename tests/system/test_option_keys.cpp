// Every field of SystemOptions, the struct a configuration file sets, has a key (issue 21):
// the bytes its default construction writes are all covered by the fields bindOptions binds,
// except the fields listed here that a run sets from elsewhere, each with its reason. A new
// option field without a key fails this test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/option_table.h"
#include "synth/scene.h"
#include "system/system.h"

using namespace plslam;

namespace {

// The bytes of an S that its default construction writes (fields, not padding): S built
// twice, over memory filled with 0x00 and with 0xff; the written bytes come out equal.
// Padding, and a std::string's pointer to its own buffer, differ. A scalar field without an
// initialiser would be missed (it is not written either); -Weffc++ style reviews catch those.
// This file is compiled with -fno-lifetime-dse (GCC), so the fills are not dropped as stores
// before the object's lifetime.
template <typename S>
std::vector<bool> writtenBytes() {
  alignas(S) unsigned char zeros[sizeof(S)];
  alignas(S) unsigned char ones[sizeof(S)];
  std::memset(zeros, 0x00, sizeof(S));
  std::memset(ones, 0xff, sizeof(S));
  S* a = new (zeros) S;
  S* b = new (ones) S;
  std::vector<bool> written(sizeof(S));
  for (size_t i = 0; i < sizeof(S); ++i) written[i] = zeros[i] == ones[i];
  a->~S();
  b->~S();
  return written;
}

// SystemOptions' members, to name where an unbound byte lies.
std::vector<std::pair<std::string, FieldSpan>> members(const SystemOptions& o) {
  return {{"sequential", fieldSpan(&o.sequential)},
          {"use_lines", fieldSpan(&o.use_lines)},
          {"mapping_queue", fieldSpan(&o.mapping_queue)},
          {"background_nice", fieldSpan(&o.background_nice)},
          {"features", fieldSpan(&o.features)},
          {"tracker", fieldSpan(&o.tracker)},
          {"mapper", fieldSpan(&o.mapper)},
          {"dynamic", fieldSpan(&o.dynamic)},
          {"segmenter", fieldSpan(&o.segmenter)},
          {"dense", fieldSpan(&o.dense)},
          {"use_loop", fieldSpan(&o.use_loop)},
          {"loop", fieldSpan(&o.loop)},
          {"refine_frames", fieldSpan(&o.refine_frames)},
          {"refine_after_keyframes", fieldSpan(&o.refine_after_keyframes)},
          {"refine_after_frames", fieldSpan(&o.refine_after_frames)},
          {"camera_to_base", fieldSpan(&o.camera_to_base)},
          {"depth_correction", fieldSpan(&o.depth_correction)}};
}

// "tracker + 312..319" for each run of unbound written bytes.
std::string describe(const std::vector<bool>& unbound, const SystemOptions& o) {
  const auto* base = reinterpret_cast<const unsigned char*>(&o);
  std::ostringstream out;
  for (size_t i = 0; i < unbound.size();) {
    if (!unbound[i]) {
      ++i;
      continue;
    }
    size_t end = i;
    while (end + 1 < unbound.size() && unbound[end + 1]) ++end;
    std::string where = "SystemOptions";
    size_t from = 0;
    for (const auto& [name, span] : members(o)) {
      const size_t at = static_cast<size_t>(static_cast<const unsigned char*>(span.at) - base);
      if (i >= at && i < at + span.size) where = name, from = at;
    }
    out << "\n  " << where << " + " << i - from << ".." << end - from;
    i = end + 1;
  }
  return out.str();
}

}  // namespace

TEST(OptionKeys, EveryFieldOfTheRunOptionsHasAKey) {
  std::vector<bool> unbound = writtenBytes<SystemOptions>();
  SystemOptions o;
  OptionTable table;
  bindOptions(&table, &o);
  const auto* base = reinterpret_cast<const unsigned char*>(&o);
  auto cover = [&](const FieldSpan& field) {
    const auto* at = static_cast<const unsigned char*>(field.at);
    ASSERT_TRUE(at >= base && at + field.size <= base + sizeof(o)) << "a key bound to a field outside the options";
    for (size_t i = 0; i < field.size; ++i) unbound[static_cast<size_t>(at - base) + i] = false;
  };
  const std::vector<FieldSpan> bound = table.boundFields();
  ASSERT_GT(bound.size(), 100u);
  for (const FieldSpan& field : bound) cover(field);

  // Set by a run from elsewhere, not by a key of their own:
  cover(fieldSpan(&o.dense.T_base_cam));         // read from the file of calibration.camera_to_base
  cover(fieldSpan(&o.segmenter.replay_labels));  // the replay folder's labels
  cover(fieldSpan(&o.features.use_lines));       // System copies system.use_lines into these three
  cover(fieldSpan(&o.tracker.use_lines));
  cover(fieldSpan(&o.mapper.use_lines));
  cover(fieldSpan(&o.tracker.localization_only));  // --localize, the node's localize service
  cover(fieldSpan(&o.segmenter.yolo.threads));     // only 0 is accepted (OpenCV 4.6 has no per-network limit)
  cover(fieldSpan(&o.dynamic.delaunay.motion));    // the dynamic filter gives the graph its check's options
  for (const MeasurementModel* model : {&o.tracker.optimizer.model, &o.mapper.ba.model, &o.loop.ba.model})
    cover(fieldSpan(&model->scale_factor));        // System copies features.orb_scale_factor into the solvers


  EXPECT_EQ(std::count(unbound.begin(), unbound.end(), true), 0)
      << "fields of SystemOptions without a configuration key (member + byte offsets in it; find the field with "
         "offsetof and bind it in src/system/system_options.cpp):"
      << describe(unbound, o);
}

// What the check above rests on: an int and a bool field are seen as written, the padding
// between a bool and the next int is not (were the fills dropped, it would be by chance).
TEST(OptionKeys, WrittenBytesAreTheFieldsNotThePadding) {
  const std::vector<bool> written = writtenBytes<SystemOptions>();
  SystemOptions o;
  const auto offset = [&](const void* field) {
    return static_cast<size_t>(static_cast<const unsigned char*>(field) - reinterpret_cast<const unsigned char*>(&o));
  };
  for (size_t i = 0; i < sizeof(int); ++i) EXPECT_TRUE(written[offset(&o.tracker.min_inliers) + i]) << "an int field";
  EXPECT_TRUE(written[offset(&o.use_lines)]) << "a bool field";
  const size_t padding_from = offset(&o.use_lines) + 1, padding_to = offset(&o.mapping_queue);
  ASSERT_LT(padding_from, padding_to) << "SystemOptions' layout changed: pick another padding";
  for (size_t i = padding_from; i < padding_to; ++i) EXPECT_FALSE(written[i]) << "padding byte " << i;
}

// The effective configuration a run writes (toYaml) reads back as the same configuration:
// every key's written text parses as its own value (enumerations, lists, seeds included),
// and keys nest in no way the reader refuses.
TEST(OptionKeys, TheEffectiveConfigurationReadsBackUnchanged) {
  SystemOptions o;
  OptionTable table;
  bindOptions(&table, &o);
  table.set("loop.global_ba_linear_solver", "sparse_schur", "test.yaml");
  table.set("loop.semantic_generic_classes", "chair, potted plant", "test.yaml");
  table.set("dynamic.motion_seed", "7", "test.yaml");
  table.set("dynamic.motion_chi2_3d", "20", "test.yaml");
  table.set("mapper.line_max_samples", "40", "test.yaml");
  table.set("tracker.pose_min_inliers", "12", "test.yaml");
  EXPECT_EQ(o.loop.ba.linear_solver, BundleAdjusterOptions::LinearSolver::kSparseSchur);
  EXPECT_EQ(o.loop.semantic.generic_classes, (std::vector<std::string>{"chair", "potted plant"}));
  EXPECT_EQ(o.dynamic.motion.seed, 7u);
  EXPECT_EQ(o.dynamic.motion.chi2_3d, 20.0);
  EXPECT_EQ(o.mapper.line_fit.max_samples, 40);
  EXPECT_EQ(o.tracker.optimizer.min_inliers, 12);
  const std::string written = table.toYaml("effective");

  SystemOptions p;
  OptionTable read;
  bindOptions(&read, &p);
  read.apply(parseYamlSubset(written, "effective.yaml"), "effective.yaml");
  EXPECT_EQ(read.toYaml("effective"), written);
  EXPECT_EQ(p.loop.ba.linear_solver, BundleAdjusterOptions::LinearSolver::kSparseSchur);
  EXPECT_EQ(p.loop.semantic.generic_classes, o.loop.semantic.generic_classes);
}

// The solvers weigh a keypoint by its pyramid level: the scale between levels is the ORB
// pyramid's, not a second setting that could disagree with it.
TEST(OptionKeys, TheSolversTakeThePyramidScaleOfTheFeatures) {
  SystemOptions o;
  o.sequential = true;
  o.use_loop = false;
  o.dense.enabled = false;
  o.features.orb.scale_factor = 1.5f;
  const System slam(synth::syntheticCamera(320, 240), o);
  EXPECT_EQ(slam.options().tracker.optimizer.model.scale_factor, 1.5);
  EXPECT_EQ(slam.options().mapper.ba.model.scale_factor, 1.5);
  EXPECT_EQ(slam.options().loop.ba.model.scale_factor, 1.5);
  SystemOptions defaults;
  defaults.sequential = true;
  defaults.use_loop = false;
  defaults.dense.enabled = false;
  const System plain(synth::syntheticCamera(320, 240), defaults);
  EXPECT_EQ(plain.options().tracker.optimizer.model.scale_factor, 1.2);  // the double, not the float's 1.2000000477
}
