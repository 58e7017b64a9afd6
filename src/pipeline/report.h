// The report stage of automatic_reconstructor (and `colmap-lidar report`):
// a self-contained HTML page with the stage timings, pose errors against
// the ground truth and against stock COLMAP, precision / recall / F per
// threshold for each meshed method, trajectories from above, error
// histograms, line overlays and renderings of the meshes coloured by error,
// plus every figure as a PNG. The plotting is report.py (matplotlib, from
// Debian's python3-matplotlib), compiled into this library and written to
// <output>/report.py on each run, so the binary needs no source tree.
#pragma once

#include <string>

namespace colmap_lidar {

struct ReportOptions {
  // Python 3 with numpy and matplotlib: a path or a name on PATH. Debian's
  // own interpreter by default, where apt installs python3-numpy and
  // python3-matplotlib (a python3 earlier on PATH, e.g. pyenv's, may lack
  // them).
  std::string python_binary = "/usr/bin/python3";
  // Log of the Python run; empty: <output>/report.log.
  std::string log_path = "";

  bool Check() const;
};

struct ReportSummary {
  std::string html_path;
  int num_figures = 0;
};

// Reads <workspace>/pipeline/stages.json, <workspace>/eval/*,
// <workspace>/database.db (see report.py) and writes
// <output_path>/index.html and the PNGs. Throws colmap_lidar::Error naming
// the interpreter when it is missing, or quoting the end of the log when the
// script fails.
ReportSummary WriteReport(const std::string& workspace_path,
                          const std::string& dataset_path,
                          const std::string& output_path,
                          const ReportOptions& options);

// The text of report.py.
const char* ReportScript();

}  // namespace colmap_lidar
