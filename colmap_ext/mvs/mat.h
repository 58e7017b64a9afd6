// COLMAP's dense-map container (mvs/mat.h) and its file format
// (colmap-formats.md 4.3): an ASCII header "<width>&<height>&<depth>&" with no
// newline, then width * height * depth raw little-endian values. The storage
// is planar (channel-major): element (row, col, slice) is at index
// slice * width * height + row * width + col, in memory and in the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glog/logging.h>

namespace colmap_lidar {

// The header of a Mat file; `data_offset` is the byte after the third '&'.
struct MatHeader {
  size_t width = 0;
  size_t height = 0;
  size_t depth = 0;
  size_t data_offset = 0;
};

// Reads only the header; throws colmap_lidar::Error naming the path when the
// file is missing or the header is not three positive integers each followed
// by '&'.
MatHeader ReadMatHeader(const std::string& path);

template <typename T>
class Mat {
 public:
  Mat() = default;
  // Zero-filled; all sizes must be > 0 (throws otherwise).
  Mat(size_t width, size_t height, size_t depth);

  size_t GetWidth() const { return width_; }
  size_t GetHeight() const { return height_; }
  size_t GetDepth() const { return depth_; }
  size_t GetNumValues() const { return data_.size(); }
  bool IsEmpty() const { return data_.empty(); }

  // Unchecked in release builds (DCHECK), like COLMAP's Mat.
  T Get(size_t row, size_t col, size_t slice = 0) const {
    return data_[Index(row, col, slice)];
  }
  void Set(size_t row, size_t col, size_t slice, T value) {
    data_[Index(row, col, slice)] = value;
  }
  void Set(size_t row, size_t col, T value) { Set(row, col, 0, value); }
  void Fill(T value);

  // Planar data, see the file comment.
  const std::vector<T>& GetData() const { return data_; }
  std::vector<T>& GetData() { return data_; }

  // Throws colmap_lidar::Error naming the path on a missing file, a bad
  // header, or a file size other than header + width*height*depth*sizeof(T)
  // (COLMAP does not check the size; we do, so that a truncated or
  // wrongly-typed file never goes unnoticed).
  void Read(const std::string& path);
  // Writes atomically; throws when the matrix is empty (COLMAP's reader
  // rejects zero sizes) or the file cannot be written.
  void Write(const std::string& path) const;

 private:
  size_t Index(size_t row, size_t col, size_t slice) const {
    DCHECK_LT(row, height_);
    DCHECK_LT(col, width_);
    DCHECK_LT(slice, depth_);
    return slice * width_ * height_ + row * width_ + col;
  }

  size_t width_ = 0;
  size_t height_ = 0;
  size_t depth_ = 0;
  std::vector<T> data_;
};

using MatF = Mat<float>;

// Free-function forms of Mat::Read / Mat::Write.
template <typename T>
Mat<T> ReadMat(const std::string& path) {
  Mat<T> mat;
  mat.Read(path);
  return mat;
}

template <typename T>
void WriteMat(const std::string& path, const Mat<T>& mat) {
  mat.Write(path);
}

extern template class Mat<float>;
extern template class Mat<int32_t>;

}  // namespace colmap_lidar
