// The paper's incremental table (`semap table`): each sequence streamed with O and with PS, accuracy, frame
// rate, completeness and mesh size beside the paper's figures (table.md, table.json, pictures per run).
#pragma once

#include <string>
#include <vector>

namespace semap::app {

struct TableRequest {
  std::string config_path;             // --config FILE (empty = defaults)
  std::vector<std::string> overrides;  // --set section.key=value, applied after the file
  std::vector<std::string> datasets;   // PATH or NAME=PATH
  std::string out = "semap_table";
  int frames = 0;
  double progress_s = 10.0;
};

// Runs every sequence with O and PS (exhaustive mode, app/run/stream_run.h, each run's written mesh
// evaluated) into request.out/NAME/METHOD, prints the table and writes table.md and table.json in
// request.out. Returns false when a run did not complete (no table then) or those two files could not be
// written (logged). Throws what a run, its configuration or its evaluation throws.
bool WriteIncrementalTable(const TableRequest& request);

}  // namespace semap::app
