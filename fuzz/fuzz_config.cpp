// The run configuration target: parseYamlSubset, then apply on the SystemOptions binding
// (bindOptions), then the effective configuration must read back as itself. Apart from
// fuzz_targets.cpp because it needs the whole system module.
#include <cstdlib>

#include "core/option_table.h"
#include "fuzz_targets.h"
#include "system/system.h"

namespace plslam::fuzz {

void config(const std::string& bytes) {
  const auto values = parseYamlSubset(bytes, "fuzz.yaml");
  SystemOptions options;
  OptionTable table;
  bindOptions(&table, &options);
  table.apply(values, "fuzz.yaml");
  // What `plslam run` writes as config.yaml must be accepted back and say the same.
  const std::string yaml = table.toYaml("fuzz");
  SystemOptions again;
  OptionTable table2;
  bindOptions(&table2, &again);
  table2.apply(parseYamlSubset(yaml, "fuzz-effective.yaml"), "fuzz-effective.yaml");
  if (table2.toYaml("fuzz") != yaml) std::abort();
}

}  // namespace plslam::fuzz
