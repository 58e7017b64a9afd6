// Byte images of messages between the ranks of one MPI job
// (process_group.h). The ranks run the same executable on the same
// architecture: plain values, no byte-order conversion.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

class ByteWriter {
 public:
  explicit ByteWriter(std::string* bytes) : bytes_(bytes) {}

  template <typename T>
  void Value(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_->append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  // `count` values from `values`.
  template <typename T>
  void Values(const T* values, size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_->append(reinterpret_cast<const char*>(values), count * sizeof(T));
  }
  // Its size (uint64), then its bytes.
  void String(const std::string& value) {
    Value<uint64_t>(value.size());
    bytes_->append(value);
  }

 private:
  std::string* bytes_;
};

// Throws colmap_lidar::Error when a read goes past the end.
class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}

  bool AtEnd() const { return pos_ == bytes_.size(); }
  size_t Remaining() const { return bytes_.size() - pos_; }

  template <typename T>
  T Value() {
    T value;
    Values(&value, 1);
    return value;
  }
  template <typename T>
  void Values(T* values, size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    THROW_CHECK(count <= Remaining() / sizeof(T),
                "truncated message between MPI ranks");
    std::memcpy(values, bytes_.data() + pos_, count * sizeof(T));
    pos_ += count * sizeof(T);
  }
  std::string String() {
    const uint64_t size = Value<uint64_t>();
    THROW_CHECK(size <= Remaining(), "truncated message between MPI ranks");
    std::string value = bytes_.substr(pos_, size);
    pos_ += size;
    return value;
  }

 private:
  const std::string& bytes_;
  size_t pos_ = 0;
};

}  // namespace colmap_lidar
