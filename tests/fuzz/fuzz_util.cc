#include "tests/fuzz/fuzz_util.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <streambuf>

#include <unistd.h>

#include <glog/logging.h>

namespace colmap_lidar {
namespace fuzz {
namespace {

// Discards everything written to it.
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

std::string MakeTempDir() {
  // /dev/shm when available: a fuzz run writes the input file millions of
  // times.
  std::string base = "/dev/shm";
  if (!std::filesystem::is_directory(base)) {
    const char* tmp = std::getenv("TMPDIR");
    base = tmp != nullptr ? tmp : "/tmp";
  }
  const std::string dir =
      base + "/colmap_lidar_fuzz_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

void InitFuzzTarget() {
  FLAGS_minloglevel = google::GLOG_FATAL;
  FLAGS_logtostderr = true;
  static NullBuffer null_buffer;
  std::cout.rdbuf(&null_buffer);
  std::cerr.rdbuf(&null_buffer);
  std::clog.rdbuf(&null_buffer);
  TempDir();
  // Remove the folder at exit; libFuzzer leaves through exit() after -runs
  // and -max_total_time.
  std::atexit([] {
    std::error_code error;
    std::filesystem::remove_all(TempDir(), error);
  });
}

const std::string& TempDir() {
  static const std::string dir = MakeTempDir();
  return dir;
}

std::string WriteInput(const std::string& name, const uint8_t* data,
                       size_t size) {
  const std::string path = TempDir() + "/" + name;
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(data),
             static_cast<std::streamsize>(size));
  file.close();
  if (!file) {
    std::abort();  // The harness itself failed (disk full?): stop loudly.
  }
  return path;
}

std::string WriteInput(const std::string& name, const std::string& content) {
  return WriteInput(name, reinterpret_cast<const uint8_t*>(content.data()),
                    content.size());
}

void SplitInput(const uint8_t* data, size_t size, const std::string& separator,
                std::string* first, std::string* second) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const size_t pos = input.find(separator);
  if (pos == std::string::npos) {
    *first = input;
    second->clear();
  } else {
    *first = input.substr(0, pos);
    *second = input.substr(pos + separator.size());
  }
}

}  // namespace fuzz
}  // namespace colmap_lidar
