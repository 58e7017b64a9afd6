// Clean-up after interrupted runs. AtomicFileWriter, StagedDirectory and
// StagedFiles (file.h) write under temporary names "<final path>.tmp-<pid>-<n>"
// and remove them when they fail; a process killed by a signal it cannot
// catch (SIGKILL, the OOM killer, a power cut) leaves them behind. They are
// never taken for output (nothing reads a temporary name), but a killed
// stage can leave the size of its output (the dense stage: a copy of every
// undistorted image).
#pragma once

#include <string>
#include <vector>

namespace colmap_lidar {

// Whether `name` (a file or folder name, no directory) has the form of a
// temporary of file.h, and if so the pid of the process that made it.
bool ParseTemporaryName(const std::string& name, long* pid);

// Removes the temporaries under `dir` (its direct entries, or the whole tree
// when `recursive`) whose process no longer runs and whose name starts with
// `name_prefix` (e.g. "dense." for those of <dir>/dense), files and folders alike,
// and returns their paths (one INFO line each). Those of running processes are kept: they may be
// another run's work in progress. Errors (e.g. permissions) leave the entry
// in place and are logged; `dir` missing is not an error.
std::vector<std::string> RemoveStaleTemporaries(
    const std::string& dir, bool recursive, const std::string& name_prefix = "");

}  // namespace colmap_lidar
