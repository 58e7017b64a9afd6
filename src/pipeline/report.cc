#include "src/pipeline/report.h"

#include <filesystem>

#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {

bool ReportOptions::Check() const {
  if (python_binary.empty()) {
    LOG(ERROR) << "Report.python_binary is empty";
    return false;
  }
  return true;
}

ReportSummary WriteReport(const std::string& workspace_path,
                          const std::string& dataset_path,
                          const std::string& output_path,
                          const ReportOptions& options) {
  THROW_CHECK(options.Check(), "Invalid report options");
  CheckDirExists(workspace_path, "workspace_path");
  const std::string python = FindExecutable(options.python_binary);
  THROW_CHECK(!python.empty(),
              "The Python interpreter '"
                  << options.python_binary
                  << "' of the report was not found; install Debian's "
                     "python3, python3-numpy and python3-matplotlib "
                     "(scripts/install_deps.sh) or pass python_binary");
  CreateDirIfNotExists(output_path);
  const std::string script_path = JoinPaths(output_path, "report.py");
  WriteFileAtomically(
      script_path,
      [](std::ostream& stream) { stream << ReportScript(); },
      /*binary=*/false);
  const std::string log_path = options.log_path.empty()
                                   ? JoinPaths(output_path, "report.log")
                                   : options.log_path;
  RunLoggedProcess({python, script_path, workspace_path, dataset_path,
                    output_path},
                   log_path, /*num_log_tail_lines=*/20, "report.py");

  ReportSummary summary;
  summary.html_path = JoinPaths(output_path, "index.html");
  CheckFileExists(summary.html_path, "the report page");
  for (const auto& entry : std::filesystem::directory_iterator(output_path)) {
    if (entry.is_regular_file() && entry.path().extension() == ".png") {
      ++summary.num_figures;
    }
  }
  return summary;
}

}  // namespace colmap_lidar
