// The paper's method plot (`semap compare`): every simplification method on the same input, mesh size
// against accuracy (compare.md, compare.csv, compare.png).
#pragma once

#include <string>
#include <vector>

namespace semap::app {

struct CompareRequest {
  std::string config_path;             // --config FILE (empty = defaults)
  std::vector<std::string> overrides;  // --set section.key=value, applied after the file
  std::string path;
  std::string out = "semap_compare";
  std::string mode = "incremental";
  std::vector<std::string> methods;  // empty = all
  int frames = 0;
};

// Runs each method (incremental: one stream each, app/run/stream_run.h, each run's written mesh evaluated;
// single-frame: one batch map per frame, depth and labels shared) and writes compare.md, compare.csv and
// compare.png in request.out. Returns false when a method's run did not complete (logged; nothing written
// then); throws what a run, its configuration, its evaluation or an output file throws.
bool CompareMethods(const CompareRequest& request);

}  // namespace semap::app
