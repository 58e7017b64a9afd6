// File-system helpers and little-endian binary I/O. Every writer of a
// workspace file goes through AtomicFileWriter or StagedDirectory so that an
// interrupted or failed run never leaves a half-written file behind.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

// COLMAP's binary formats are little-endian; we only build for such hosts.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "colmap-lidar assumes a little-endian host");

bool ExistsFile(const std::string& path);
bool ExistsDir(const std::string& path);
// Throws colmap_lidar::Error naming `what` and the path when missing.
void CheckFileExists(const std::string& path, const std::string& what);
void CheckDirExists(const std::string& path, const std::string& what);
// Creates the folder and its parents; throws on failure.
void CreateDirIfNotExists(const std::string& path);
std::string JoinPaths(const std::string& a, const std::string& b);
// Reads a whole file; throws colmap_lidar::Error naming the path on failure.
std::string ReadTextFile(const std::string& path);

// Opens a file for binary reading; throws naming the path on failure.
std::ifstream OpenBinaryInput(const std::string& path);

template <typename T>
T ReadBinary(std::istream& stream) {
  static_assert(std::is_trivially_copyable_v<T>);
  T value;
  stream.read(reinterpret_cast<char*>(&value), sizeof(T));
  THROW_CHECK(stream.good(), "Unexpected end of binary data");
  return value;
}

template <typename T>
void ReadBinaryArray(std::istream& stream, T* data, size_t count) {
  static_assert(std::is_trivially_copyable_v<T>);
  stream.read(reinterpret_cast<char*>(data), sizeof(T) * count);
  THROW_CHECK(stream.good() || (count == 0),
              "Unexpected end of binary data");
}

template <typename T>
void WriteBinary(std::ostream& stream, const T& value) {
  static_assert(std::is_trivially_copyable_v<T>);
  stream.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
void WriteBinaryArray(std::ostream& stream, const T* data, size_t count) {
  static_assert(std::is_trivially_copyable_v<T>);
  stream.write(reinterpret_cast<const char*>(data), sizeof(T) * count);
}

// Writes `path` atomically: the content goes to a temporary file in the same
// folder, which replaces `path` by rename() only when Commit() succeeds. If
// the writer is destroyed without Commit() (an exception), the temporary is
// removed and `path` keeps its previous content.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::string& path, bool binary = true);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  std::ostream& stream() { return stream_; }
  // Flushes, checks the stream and renames; throws naming the path.
  void Commit();

 private:
  std::string path_;
  std::string temp_path_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Convenience: AtomicFileWriter around a callback.
void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& write,
                         bool binary = true);

// A folder built under a temporary name beside its final place and moved
// there by Commit(); destroyed without Commit(), the temporary is removed.
// Commit() replaces an existing folder of the same name.
class StagedDirectory {
 public:
  explicit StagedDirectory(const std::string& final_path);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  // Where to write the content now.
  const std::string& path() const { return temp_path_; }
  void Commit();

 private:
  std::string final_path_;
  std::string temp_path_;
  bool committed_ = false;
};

// A set of file copies that land together: Copy() writes each file under a
// temporary name beside its destination; Commit() renames them all into
// place. Destroyed without Commit(), the temporaries are removed and no
// destination was touched. Used by importers, whose database changes commit
// in between the two steps.
class StagedFiles {
 public:
  StagedFiles() = default;
  ~StagedFiles();
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;

  // Creates the destination's folder if needed; throws naming both paths.
  void Copy(const std::string& source_path, const std::string& target_path);
  size_t NumStaged() const { return staged_.size(); }
  void Commit();

 private:
  // (temporary path, final path)
  std::vector<std::pair<std::string, std::string>> staged_;
  bool committed_ = false;
};

// True when both paths name the same existing file.
bool IsSameFile(const std::string& path1, const std::string& path2);
// True when both files exist and have identical bytes.
bool FilesHaveSameContent(const std::string& path1, const std::string& path2);

}  // namespace colmap_lidar
