// The configuration keys of local mapping (mapper.): one line per field; the doc string is
// the field's documentation.
#include "core/option_table.h"
#include "mapping/line_reconstruction.h"
#include "mapping/local_mapper.h"
#include "optim/bundle_adjuster.h"
#include "optim/measurement.h"

namespace plslam {

void bindLocalMapperOptions(OptionTable* t, LocalMapperOptions* o) {
  LocalMapperOptions& m = *o;
  t->bind("mapper.local_ba", &m.local_ba, "run the local bundle adjustment");
  t->bind("mapper.ba_keyframes", &m.ba_keyframes, "keyframes optimised together in local BA");
  t->bind("mapper.ba_fixed_keyframes", &m.ba_fixed_keyframes, "further keyframes held fixed around them");
  t->bind("mapper.cull_found_ratio", &m.cull_found_ratio, "landmarks found in fewer predicted frames than this are culled");
  t->bind("mapper.cull_single_after", &m.cull_single_after, "points seen by one keyframe are culled this many keyframes later");
  t->bind("mapper.cull_min_visible", &m.cull_min_visible, "the found ratio is judged once a landmark was predicted this often");
  t->bind("mapper.min_covisible_points", &m.min_covisible_points, "shared points that make two keyframes covisible (local BA window)");
  bindBundleAdjusterOptions(t, "mapper.ba_", &m.ba);
  bindMeasurementModel(t, "mapper.", "in local BA", &m.ba.model);
  bindLineFitOptions(t, "mapper.line_", &m.line_fit);
}

}  // namespace plslam
