#include "colmap_ext/util/file.h"

#include "colmap_ext/util/stale_temporaries.h"

#include <atomic>
#include <chrono>
#include <sstream>

#include <unistd.h>

namespace colmap_lidar {
namespace fs = std::filesystem;

namespace {

// A name that no concurrent writer in this or another process uses.
std::string TemporarySibling(const std::string& path) {
  static std::atomic<uint64_t> counter{0};
  std::ostringstream name;
  name << path << ".tmp-" << ::getpid() << "-" << counter++;
  return name.str();
}

}  // namespace

bool ExistsFile(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

bool ExistsDir(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

void CheckFileExists(const std::string& path, const std::string& what) {
  THROW_CHECK(ExistsFile(path), what << ": file does not exist: " << path);
}

void CheckDirExists(const std::string& path, const std::string& what) {
  THROW_CHECK(ExistsDir(path), what << ": folder does not exist: " << path);
}

void CreateDirIfNotExists(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  THROW_CHECK(!ec && ExistsDir(path),
              "Cannot create folder " << path << ": " << ec.message());
}

std::string JoinPaths(const std::string& a, const std::string& b) {
  return (fs::path(a) / fs::path(b)).string();
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  THROW_CHECK(file.is_open(), "Cannot open " << path);
  std::ostringstream content;
  content << file.rdbuf();
  THROW_CHECK(!file.bad(), "Cannot read " << path);
  return content.str();
}

std::ifstream OpenBinaryInput(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  THROW_CHECK(file.is_open(), "Cannot open " << path);
  return file;
}

AtomicFileWriter::AtomicFileWriter(const std::string& path, bool binary)
    : path_(path), temp_path_(TemporarySibling(path)) {
  stream_.open(temp_path_, binary ? std::ios::binary | std::ios::trunc
                                  : std::ios::trunc);
  THROW_CHECK(stream_.is_open(), "Cannot open " << temp_path_
                                                << " for writing " << path);
}

AtomicFileWriter::~AtomicFileWriter() {
  if (!committed_) {
    stream_.close();
    std::error_code ec;
    fs::remove(temp_path_, ec);
  }
}

void AtomicFileWriter::Commit() {
  stream_.flush();
  THROW_CHECK(stream_.good(), "Cannot write " << path_);
  stream_.close();
  std::error_code ec;
  fs::rename(temp_path_, path_, ec);
  THROW_CHECK(!ec, "Cannot rename " << temp_path_ << " to " << path_ << ": "
                                    << ec.message());
  committed_ = true;
}

void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& write,
                         bool binary) {
  AtomicFileWriter writer(path, binary);
  write(writer.stream());
  writer.Commit();
}

StagedDirectory::StagedDirectory(const std::string& final_path)
    : final_path_(fs::path(final_path).lexically_normal().string()) {
  while (!final_path_.empty() && final_path_.back() == '/') {
    final_path_.pop_back();
  }
  // What an earlier run, killed while building this folder, left beside it
  // ("<name>.tmp-*" and "<name>.old.tmp-*"; nothing else of the parent).
  const fs::path final_fs_path(final_path_);
  const std::string parent = final_fs_path.parent_path().string();
  RemoveStaleTemporaries(parent.empty() ? "." : parent, /*recursive=*/false,
                         final_fs_path.filename().string() + ".");
  temp_path_ = TemporarySibling(final_path_);
  CreateDirIfNotExists(temp_path_);
}

StagedDirectory::~StagedDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temp_path_, ec);
  }
}

void StagedDirectory::Commit() {
  std::error_code ec;
  if (ExistsDir(final_path_)) {
    // Move the old folder aside first so that the final rename is atomic and
    // the old content is only deleted once the new one is in place.
    const std::string old_path = TemporarySibling(final_path_ + ".old");
    fs::rename(final_path_, old_path, ec);
    THROW_CHECK(!ec, "Cannot replace " << final_path_ << ": " << ec.message());
    fs::rename(temp_path_, final_path_, ec);
    if (ec) {
      std::error_code restore_ec;
      fs::rename(old_path, final_path_, restore_ec);
      THROW_ERROR("Cannot rename " << temp_path_ << " to " << final_path_
                                   << ": " << ec.message());
    }
    fs::remove_all(old_path, ec);
  } else {
    fs::rename(temp_path_, final_path_, ec);
    THROW_CHECK(!ec, "Cannot rename " << temp_path_ << " to " << final_path_
                                      << ": " << ec.message());
  }
  committed_ = true;
}

StagedFiles::~StagedFiles() {
  if (!committed_) {
    for (const auto& [temp_path, final_path] : staged_) {
      std::error_code ec;
      fs::remove(temp_path, ec);
    }
  }
}

void StagedFiles::Copy(const std::string& source_path,
                       const std::string& target_path) {
  THROW_CHECK(!committed_, "StagedFiles: Copy() after Commit()");
  const std::string parent = fs::path(target_path).parent_path().string();
  if (!parent.empty()) {
    CreateDirIfNotExists(parent);
  }
  const std::string temp_path = TemporarySibling(target_path);
  std::error_code ec;
  fs::copy_file(source_path, temp_path, fs::copy_options::overwrite_existing,
                ec);
  if (ec) {
    // Its own error code: the copy's error is the one to report.
    std::error_code remove_ec;
    fs::remove(temp_path, remove_ec);
    THROW_ERROR("Cannot copy " << source_path << " to " << target_path << ": "
                               << ec.message());
  }
  staged_.emplace_back(temp_path, target_path);
}

void StagedFiles::Commit() {
  for (const auto& [temp_path, final_path] : staged_) {
    std::error_code ec;
    fs::rename(temp_path, final_path, ec);
    THROW_CHECK(!ec, "Cannot rename " << temp_path << " to " << final_path
                                      << ": " << ec.message());
  }
  committed_ = true;
}

bool IsSameFile(const std::string& path1, const std::string& path2) {
  std::error_code ec;
  return fs::equivalent(path1, path2, ec) && !ec;
}

bool FilesHaveSameContent(const std::string& path1, const std::string& path2) {
  if (!ExistsFile(path1) || !ExistsFile(path2)) {
    return false;
  }
  std::error_code ec1, ec2;
  if (fs::file_size(path1, ec1) != fs::file_size(path2, ec2) || ec1 || ec2) {
    return false;
  }
  return ReadTextFile(path1) == ReadTextFile(path2);
}

}  // namespace colmap_lidar
