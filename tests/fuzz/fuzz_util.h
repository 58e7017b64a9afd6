// Shared helpers of the libFuzzer targets in tests/fuzz (see README.md there).
//
// Most readers of outside data take a path, so a target writes the input
// bytes to a file in a private temporary folder and calls the reader on it.
// The contract under test: a reader returns or throws colmap_lidar::Error;
// it never crashes, hangs, reads out of bounds or throws anything else (an
// uncaught std::bad_alloc or std::out_of_range is reported by libFuzzer as a
// crash, on purpose: users should get a message that names the file).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace colmap_lidar {
namespace fuzz {

// Silences glog (below FATAL) and std::cout / std::cerr, which the readers
// and the option manager write to on every rejected input; libFuzzer and the
// sanitizers report through their own file descriptors. Creates the private
// temporary folder. Call from LLVMFuzzerInitialize.
void InitFuzzTarget();

// The private temporary folder of this process.
const std::string& TempDir();

// Writes `size` bytes to TempDir()/name (replacing it) and returns the path.
std::string WriteInput(const std::string& name, const uint8_t* data,
                       size_t size);
std::string WriteInput(const std::string& name, const std::string& content);

// Runs `read`; swallows colmap_lidar::Error (the reader refused the input),
// lets everything else through to libFuzzer.
template <typename Function>
void ExpectNoCrash(Function&& read);

// Splits the input at the first occurrence of `separator`: the part before
// goes to *first, the part after to *second (empty when there is none).
void SplitInput(const uint8_t* data, size_t size, const std::string& separator,
                std::string* first, std::string* second);

}  // namespace fuzz
}  // namespace colmap_lidar

#include "colmap_ext/util/logging.h"

template <typename Function>
void colmap_lidar::fuzz::ExpectNoCrash(Function&& read) {
  try {
    read();
  } catch (const ::colmap_lidar::Error&) {
  }
}
