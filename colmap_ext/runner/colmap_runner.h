// Runs the stock `colmap` binary (Debian's colmap 3.8, see
// docs/colmap-formats.md) as a child process. We have no COLMAP headers or
// library, so every stock step (feature extraction, matching, mapping,
// fusion, Poisson meshing) goes through this runner.
//
// Contract: the binary is started directly (posix_spawn, no shell), each
// argument is one argv entry, so paths with spaces or quotes are safe. The
// child's stdout and stderr are appended to one log file, stdin is
// /dev/null. A non-zero exit code or a signal throws colmap_lidar::Error
// with the command line, the exit status and the end of this run's log.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace colmap_lidar {

struct ColmapRunnerOptions {
  // Path or name of the stock colmap binary. Empty: $COLMAP_BINARY when set,
  // else `colmap` on PATH. A name without '/' is looked up on PATH.
  std::string colmap_binary = "";

  // Log file that receives stdout and stderr of every run (appended, with a
  // "$ command line" header per run). Empty: a new file in the system temp
  // folder, created by the constructor.
  std::string log_path = "";

  // Number of trailing log lines quoted in the error message of a failed
  // run, >= 0.
  int num_log_tail_lines = 20;

  bool Check() const;
};

class ColmapRunner {
 public:
  // Resolves the binary (throws as FindColmapBinary) and the log file.
  explicit ColmapRunner(const ColmapRunnerOptions& options =
                            ColmapRunnerOptions());

  // Returns the absolute path of an executable colmap binary. `hint` is a
  // path, a name to search on PATH, or empty ($COLMAP_BINARY, then `colmap`
  // on PATH). Throws colmap_lidar::Error with installation advice when no
  // executable is found.
  static std::string FindColmapBinary(const std::string& hint);

  // The version from the first line of `colmap help`, e.g. "3.8" for
  // "COLMAP 3.8 -- Structure-from-Motion and Multi-View Stereo". Throws when
  // the binary fails or the line does not start with "COLMAP".
  std::string Version() const;

  // Runs `colmap <command> --key value ...` and waits. Keys may be given
  // with or without the leading "--". Throws colmap_lidar::Error on a
  // non-zero exit code or a signal (see the file comment).
  void Run(const std::string& command,
           const std::vector<std::pair<std::string, std::string>>& options)
      const;

  const std::string& binary_path() const { return binary_path_; }
  const std::string& log_path() const { return log_path_; }

 private:
  ColmapRunnerOptions options_;
  std::string binary_path_;
  std::string log_path_;
};

// The absolute path of an executable: `name` itself when it contains a '/',
// else the first match on PATH. Empty when there is none.
std::string FindExecutable(const std::string& name);

// Runs any program (args[0] an absolute or relative path, see
// FindExecutable) as ColmapRunner::Run runs colmap: no shell, stdin from
// /dev/null, stdout and stderr appended to `log_path` after a "$ command"
// header, one INFO line with the time. Throws colmap_lidar::Error naming
// `display_name`, the command line, the exit status and the last
// `num_log_tail_lines` lines of this run's log when it fails.
void RunLoggedProcess(const std::vector<std::string>& args,
                      const std::string& log_path, int num_log_tail_lines,
                      const std::string& display_name);

}  // namespace colmap_lidar
