#include "colmap_ext/mvs/mat.h"

#include <algorithm>
#include <limits>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Generous bounds that keep every size product far from overflow.
constexpr size_t kMaxDimension = 1u << 20;
constexpr size_t kMaxDepth = 1u << 12;
// Three numbers below kMaxDimension and three '&' fit easily.
constexpr size_t kMaxHeaderBytes = 64;

}  // namespace

MatHeader ReadMatHeader(const std::string& path) {
  std::ifstream file = OpenBinaryInput(path);
  char buffer[kMaxHeaderBytes];
  file.read(buffer, kMaxHeaderBytes);
  const size_t num_read = static_cast<size_t>(file.gcount());

  MatHeader header;
  size_t values[3] = {0, 0, 0};
  size_t pos = 0;
  for (int i = 0; i < 3; ++i) {
    const size_t begin = pos;
    size_t value = 0;
    while (pos < num_read && buffer[pos] >= '0' && buffer[pos] <= '9' &&
           pos - begin < 10) {
      value = value * 10 + static_cast<size_t>(buffer[pos] - '0');
      ++pos;
    }
    THROW_CHECK(pos > begin && pos < num_read && buffer[pos] == '&',
                "Bad Mat header in " << path
                                     << " (expected \"<width>&<height>&"
                                        "<depth>&\")");
    ++pos;
    values[i] = value;
  }
  header.width = values[0];
  header.height = values[1];
  header.depth = values[2];
  header.data_offset = pos;
  THROW_CHECK(header.width > 0 && header.height > 0 && header.depth > 0,
              "Bad Mat header in " << path << ": sizes must be > 0, got "
                                   << header.width << "&" << header.height
                                   << "&" << header.depth << "&");
  THROW_CHECK(header.width <= kMaxDimension && header.height <= kMaxDimension &&
                  header.depth <= kMaxDepth,
              "Bad Mat header in " << path << ": implausible size "
                                   << header.width << "&" << header.height
                                   << "&" << header.depth << "&");
  return header;
}

template <typename T>
Mat<T>::Mat(size_t width, size_t height, size_t depth)
    : width_(width), height_(height), depth_(depth) {
  THROW_CHECK(width > 0 && height > 0 && depth > 0,
              "Mat sizes must be > 0, got " << width << "x" << height << "x"
                                            << depth);
  data_.assign(width * height * depth, T(0));
}

template <typename T>
void Mat<T>::Fill(T value) {
  std::fill(data_.begin(), data_.end(), value);
}

template <typename T>
void Mat<T>::Read(const std::string& path) {
  const MatHeader header = ReadMatHeader(path);
  const size_t num_values = header.width * header.height * header.depth;
  const size_t expected_size = header.data_offset + num_values * sizeof(T);
  std::ifstream file = OpenBinaryInput(path);
  file.seekg(0, std::ios::end);
  const size_t file_size = static_cast<size_t>(file.tellg());
  THROW_CHECK(file_size == expected_size,
              "Mat file " << path << " has " << file_size << " bytes, but its "
                          << header.width << "&" << header.height << "&"
                          << header.depth << "& header needs "
                          << expected_size << " (" << sizeof(T)
                          << "-byte values)");
  std::vector<T> data(num_values);
  file.seekg(static_cast<std::streamoff>(header.data_offset));
  file.read(reinterpret_cast<char*>(data.data()),
            static_cast<std::streamsize>(num_values * sizeof(T)));
  THROW_CHECK(file.good(), "Cannot read Mat data from " << path);
  width_ = header.width;
  height_ = header.height;
  depth_ = header.depth;
  data_ = std::move(data);
}

template <typename T>
void Mat<T>::Write(const std::string& path) const {
  THROW_CHECK(!data_.empty(), "Cannot write an empty Mat to " << path);
  WriteFileAtomically(path, [&](std::ostream& stream) {
    stream << width_ << "&" << height_ << "&" << depth_ << "&";
    WriteBinaryArray(stream, data_.data(), data_.size());
  });
}

template class Mat<float>;
template class Mat<int32_t>;

}  // namespace colmap_lidar
