// The input encoding of fuzz_database: a sequence of rows, each a table byte
// (kTableNames index, modulo their count) followed by that table's fields in
// column order. Integers are 8 bytes little-endian, reals 8 bytes
// (IEEE double), texts and blobs a 2-byte little-endian length and the bytes
// (length 0xFFFF = NULL). A truncated input reads as zeros. The seed writer
// (make_seeds.cc) encodes rows of real databases with the same functions.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

namespace colmap_lidar {
namespace fuzz {

enum DbTable : uint8_t {
  kDbCameras = 0,
  kDbImages,
  kDbKeypoints,
  kDbDescriptors,
  kDbMatches,
  kDbTwoViewGeometries,
  kDbLidarScans,
  kDbLineSegments,
  kDbLineMatches,
  kDbLineTracks,
  kDbNumTables,
};

constexpr uint16_t kDbNullLength = 0xFFFF;

class DbInputReader {
 public:
  DbInputReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  bool AtEnd() const { return pos_ >= size_; }

  uint8_t Byte() {
    return pos_ < size_ ? data_[pos_++] : 0;
  }
  int64_t Int() {
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) {
      value |= static_cast<uint64_t>(Byte()) << (8 * i);
    }
    return static_cast<int64_t>(value);
  }
  double Real() {
    const int64_t bits = Int();
    double value;
    std::memcpy(&value, &bits, sizeof(value));
    return value;
  }
  // False for NULL.
  bool Bytes(std::string* bytes) {
    const uint16_t length =
        static_cast<uint16_t>(Byte() | (static_cast<uint16_t>(Byte()) << 8));
    bytes->clear();
    if (length == kDbNullLength) {
      return false;
    }
    for (uint16_t i = 0; i < length && pos_ < size_; ++i) {
      bytes->push_back(static_cast<char>(data_[pos_++]));
    }
    return true;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

class DbInputWriter {
 public:
  void Table(DbTable table) { bytes_.push_back(static_cast<char>(table)); }
  void Byte(uint8_t value) { bytes_.push_back(static_cast<char>(value)); }
  void Int(int64_t value) {
    const uint64_t bits = static_cast<uint64_t>(value);
    for (int i = 0; i < 8; ++i) {
      bytes_.push_back(static_cast<char>((bits >> (8 * i)) & 0xFF));
    }
  }
  void Real(double value) {
    int64_t bits;
    std::memcpy(&bits, &value, sizeof(bits));
    Int(bits);
  }
  void Bytes(const void* data, size_t size) {
    const uint16_t length = static_cast<uint16_t>(size);
    bytes_.push_back(static_cast<char>(length & 0xFF));
    bytes_.push_back(static_cast<char>(length >> 8));
    bytes_.append(static_cast<const char*>(data), length);
  }
  void Null() {
    bytes_.push_back(static_cast<char>(0xFF));
    bytes_.push_back(static_cast<char>(0xFF));
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

}  // namespace fuzz
}  // namespace colmap_lidar
