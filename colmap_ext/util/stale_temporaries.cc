#include "colmap_ext/util/stale_temporaries.h"

#include <cerrno>
#include <filesystem>
#include <system_error>

#include <signal.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace fs = std::filesystem;
namespace {

bool AllDigits(const std::string& text) {
  return !text.empty() && text.size() <= 18 &&
         text.find_first_not_of("0123456789") == std::string::npos;
}

bool ProcessIsGone(const long pid) {
  return pid > 0 && ::kill(static_cast<pid_t>(pid), 0) == -1 &&
         errno == ESRCH;
}

}  // namespace

bool ParseTemporaryName(const std::string& name, long* pid) {
  // "<final name>.tmp-<pid>-<counter>", with a non-empty final name.
  const size_t tag = name.rfind(".tmp-");
  if (tag == std::string::npos || tag == 0) {
    return false;
  }
  const std::string rest = name.substr(tag + 5);
  const size_t dash = rest.find('-');
  if (dash == std::string::npos || !AllDigits(rest.substr(0, dash)) ||
      !AllDigits(rest.substr(dash + 1))) {
    return false;
  }
  *pid = std::stol(rest.substr(0, dash));
  return true;
}

std::vector<std::string> RemoveStaleTemporaries(
    const std::string& dir, const bool recursive,
    const std::string& name_prefix) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    return {};
  }
  std::vector<fs::path> stale;
  const auto consider = [&stale,
                          &name_prefix](const fs::directory_entry& entry) {
    const std::string name = entry.path().filename().string();
    long pid = 0;
    if (name.compare(0, name_prefix.size(), name_prefix) == 0 &&
        ParseTemporaryName(name, &pid) &&
        ProcessIsGone(pid)) {
      stale.push_back(entry.path());
      return true;
    }
    return false;
  };
  if (recursive) {
    fs::recursive_directory_iterator it(
        dir, fs::directory_options::skip_permission_denied, ec);
    for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      if (consider(*it)) {
        // Its content goes with it.
        it.disable_recursion_pending();
      }
    }
  } else {
    fs::directory_iterator it(dir, ec);
    for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
      consider(*it);
    }
  }
  if (ec) {
    LOG(WARNING) << "Looking for temporaries of interrupted runs in " << dir
                 << ": " << ec.message();
  }
  std::vector<std::string> removed;
  for (const fs::path& path : stale) {
    std::error_code remove_ec;
    fs::remove_all(path, remove_ec);
    if (remove_ec) {
      LOG(WARNING) << "Cannot remove " << path.string()
                   << ", left by an interrupted run: " << remove_ec.message();
    } else {
      LOG(INFO) << "Removed " << path.string()
                << ", left by an interrupted run";
      removed.push_back(path.string());
    }
  }
  return removed;
}

}  // namespace colmap_lidar
