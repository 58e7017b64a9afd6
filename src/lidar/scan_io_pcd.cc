// PCD scans of scan_io.h, through PCL, behind our own header check.
#include "src/lidar/scan_io.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <unistd.h>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"
#include "src/lidar/scan_io_internal.h"

namespace colmap_lidar {
namespace {

// Bytes of one scalar of a PCL datatype; 0 for an unknown datatype.
size_t PclScalarSize(const uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8:
    case pcl::PCLPointField::UINT8:
      return 1;
    case pcl::PCLPointField::INT16:
    case pcl::PCLPointField::UINT16:
      return 2;
    case pcl::PCLPointField::INT32:
    case pcl::PCLPointField::UINT32:
    case pcl::PCLPointField::FLOAT32:
      return 4;
    case pcl::PCLPointField::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

// One scalar of a PCL field as double.
double ReadPclScalar(const uint8_t* data, const uint8_t datatype,
                     const std::string& field, const std::string& path) {
  auto load = [data](auto value) {
    std::memcpy(&value, data, sizeof(value));
    return static_cast<double>(value);
  };
  switch (datatype) {
    case pcl::PCLPointField::INT8:
      return load(int8_t{});
    case pcl::PCLPointField::UINT8:
      return load(uint8_t{});
    case pcl::PCLPointField::INT16:
      return load(int16_t{});
    case pcl::PCLPointField::UINT16:
      return load(uint16_t{});
    case pcl::PCLPointField::INT32:
      return load(int32_t{});
    case pcl::PCLPointField::UINT32:
      return load(uint32_t{});
    case pcl::PCLPointField::FLOAT32:
      return load(float{});
    case pcl::PCLPointField::FLOAT64:
      return load(double{});
    default:
      THROW_ERROR("PCD file " << path << ": field '" << field
                              << "' has unsupported PCL datatype "
                              << static_cast<int>(datatype));
  }
}

const pcl::PCLPointField* FindPclField(const pcl::PCLPointCloud2& cloud,
                                       const std::string& name) {
  for (const pcl::PCLPointField& field : cloud.fields) {
    if (field.name == name) {
      return &field;
    }
  }
  return nullptr;
}

}  // namespace

namespace scan_io_internal {

// Validates a PCD header before PCL sees the file: PCL 1.13 crashes
// (segmentation fault) on some malformed headers instead of failing.
// Returns the POINTS count.
size_t CheckPcdHeader(const std::string& path) {
  size_t header_bytes = 0;
  const std::vector<std::vector<std::string>> lines =
      ReadHeaderLines(path, "DATA", &header_bytes);
  // PCL's header parser stops at the first line that is neither empty, nor
  // a comment, nor a keyword line; fields it has not seen by then stay unset
  // and it crashes reading the body. It also takes every keyword line as it
  // comes: a repeated line overrides the earlier one, POINTS sizes its buffer
  // from the fields seen so far, and TYPE reads the sizes of the last SIZE.
  // Only accept headers that both parsers read the same way: every line up
  // to DATA is empty, starts with '#', or starts with a keyword followed by a
  // blank; each keyword at most once and in the order of the PCD 0.7
  // specification (which PCL's writer follows).
  {
    static const char* const kKeywords[] = {
        "VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
        "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
    constexpr int kNumKeywords = sizeof(kKeywords) / sizeof(kKeywords[0]);
    int last_rank = -1;
    std::ifstream file(path, std::ios::binary);
    std::string line;
    for (size_t i = 0; i < lines.size() && std::getline(file, line); ++i) {
      if (line.empty() || line[0] == '#') {
        continue;
      }
      THROW_CHECK(line.compare(0, 7, "COLUMNS") != 0,
                  "PCD file " << path << ": line " << i + 1
                              << " is a COLUMNS line (PCD before 0.7), "
                                 "not supported: use FIELDS");
      int rank = -1;
      for (int k = 0; k < kNumKeywords; ++k) {
        const size_t length = std::strlen(kKeywords[k]);
        if (line.compare(0, length, kKeywords[k]) == 0 &&
            line.size() > length &&
            (line[length] == ' ' || line[length] == '\t')) {
          rank = k;
        }
      }
      THROW_CHECK(rank >= 0, "Cannot parse the header of PCD file "
                                 << path << ": unexpected line " << i + 1);
      // A carriage return splits a token for PCL but not for us.
      THROW_CHECK(line.find('\r') == std::string::npos ||
                      line.find('\r') + 1 == line.size(),
                  "Cannot parse the header of PCD file "
                      << path << ": carriage return inside line " << i + 1);
      THROW_CHECK(rank > last_rank,
                  "Cannot parse the header of PCD file "
                      << path << ": " << kKeywords[rank] << " on line "
                      << i + 1
                      << " repeated or out of order (PCD 0.7 order: VERSION, "
                         "FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, "
                         "VIEWPOINT, POINTS, DATA)");
      last_rank = rank;
    }
    // PCL's parser does not stop at DATA: it goes on reading lines as header
    // lines, skipping empty and comment lines, until one starts with no
    // keyword. A keyword there would redefine the cloud after our checks
    // (fuzz_pcd: a SIZE or POINTS line in the data overflowed PCL's buffer),
    // so the first such line of the data must not start with one. Binary
    // data is split at its newline bytes exactly as PCL does.
    file.clear();
    file.seekg(static_cast<std::streamoff>(header_bytes));
    while (std::getline(file, line)) {
      if (line.empty()) {
        continue;
      }
      // PCL's first token: after leading white space, up to the next.
      const char* kSpace = " \t\n\v\f\r";
      const size_t begin = line.find_first_not_of(kSpace);
      const std::string token =
          begin == std::string::npos
              ? std::string()
              : line.substr(begin, line.find_first_of(kSpace, begin) - begin);
      if (!token.empty() && token[0] == '#') {
        continue;
      }
      for (const char* keyword :
           {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE", "COUNT", "WIDTH",
            "HEIGHT", "VIEWPOINT", "POINTS", "DATA"}) {
        THROW_CHECK(token.compare(0, std::strlen(keyword), keyword) != 0,
                    "Cannot parse PCD file "
                        << path << ": the data after the DATA line starts "
                                   "with a header keyword ("
                        << keyword << "), which PCL would read as header");
      }
      break;
    }
  }
  std::map<std::string, std::vector<std::string>> entries;
  for (const std::vector<std::string>& words : lines) {
    if (!words.empty() && words[0][0] != '#') {
      entries[words[0]].assign(words.begin() + 1, words.end());
    }
  }
  for (const char* key : {"FIELDS", "SIZE", "TYPE", "WIDTH", "HEIGHT",
                          "POINTS", "DATA"}) {
    THROW_CHECK(entries.count(key) > 0 && !entries[key].empty(),
                "Cannot parse the header of PCD file " << path << ": no "
                                                       << key << " line");
  }
  const std::vector<std::string>& fields = entries["FIELDS"];
  const std::vector<std::string>& sizes = entries["SIZE"];
  THROW_CHECK(sizes.size() == fields.size() &&
                  entries["TYPE"].size() == fields.size() &&
                  (entries.count("COUNT") == 0 ||
                   entries["COUNT"].size() == fields.size()),
              "Cannot parse the header of PCD file "
                  << path << ": FIELDS, SIZE, TYPE and COUNT differ in length");
  size_t point_bytes = 0;
  size_t point_elements = 0;
  // Bounds that keep every product below far from overflow: PCL stores
  // WIDTH and HEIGHT as uint32, and no field has more than 2^20 elements.
  constexpr long long kMaxFieldCount = 1 << 20;
  constexpr long long kMaxExtent = 0xFFFFFFFFLL;
  for (size_t i = 0; i < fields.size(); ++i) {
    const long long count =
        entries.count("COUNT") ? ParseInt(entries["COUNT"][i],
                                          "COUNT of " + path)
                               : 1;
    const long long size = ParseInt(sizes[i], "SIZE of " + path);
    THROW_CHECK(count >= 1 && count <= kMaxFieldCount &&
                    (size == 1 || size == 2 || size == 4 || size == 8),
                "PCD file " << path << ": invalid SIZE or COUNT of field '"
                            << fields[i] << "'");
    // The combinations PCL maps to a data type (pcl::getFieldType); any
    // other gives PCL's field no size, and the records no longer match.
    const std::string type = StringToLower(entries["TYPE"][i]);
    THROW_CHECK(((type == "i" || type == "u") && size != 0) ||
                    (type == "f" && (size == 4 || size == 8)),
                "PCD file " << path << ": field '" << fields[i]
                            << "' has TYPE '" << entries["TYPE"][i]
                            << "' with SIZE " << size
                            << " (expected I or U of 1, 2, 4 or 8 bytes, F of "
                               "4 or 8)");
    point_bytes += static_cast<size_t>(size * count);
    point_elements += static_cast<size_t>(count);
  }
  const long long width = ParseInt(entries["WIDTH"][0], "WIDTH of " + path);
  const long long height = ParseInt(entries["HEIGHT"][0], "HEIGHT of " + path);
  const long long num_points =
      ParseInt(entries["POINTS"][0], "POINTS of " + path);
  THROW_CHECK(width >= 0 && height >= 0 && width <= kMaxExtent &&
                  height <= kMaxExtent,
              "PCD file " << path << ": invalid WIDTH " << width
                          << " or HEIGHT " << height);
  THROW_CHECK(num_points >= 0 &&
                  static_cast<unsigned long long>(num_points) ==
                      static_cast<unsigned long long>(width) *
                      static_cast<unsigned long long>(height),
              "PCD file " << path << ": POINTS " << num_points
                          << " differs from WIDTH x HEIGHT");
  const std::string data = StringToLower(entries["DATA"][0]);
  THROW_CHECK(data == "ascii" || data == "binary" ||
                  data == "binary_compressed",
              "PCD file " << path << ": unknown DATA type '" << data << "'");
  const uintmax_t file_bytes = std::filesystem::file_size(path);
  const uintmax_t body_bytes =
      file_bytes > header_bytes ? file_bytes - header_bytes : 0;
  // The data must be able to hold the points before PCL sizes its buffer
  // from the header: an ASCII value takes at least one byte.
  if (data == "ascii") {
    THROW_CHECK(static_cast<uintmax_t>(num_points) <=
                    body_bytes / std::max<size_t>(1, point_elements),
                "PCD file " << path << " is truncated: " << body_bytes
                            << " data bytes for " << num_points
                            << " ASCII points");
  } else if (data == "binary") {
    THROW_CHECK(static_cast<uintmax_t>(num_points) <=
                    body_bytes / std::max<size_t>(1, point_bytes),
                "PCD file " << path << " is truncated: " << body_bytes
                            << " data bytes for " << num_points
                            << " points of " << point_bytes << " bytes");
  } else if (data == "binary_compressed") {
    THROW_CHECK(body_bytes >= 8,
                "PCD file " << path << " is truncated (no compressed data)");
    // PCL trusts the two sizes that open the compressed data (it crashes on
    // an uncompressed size of 0 and reads past the file for a compressed
    // size beyond it), so check them here: the uncompressed size must be
    // what the header describes, the compressed bytes must be in the file,
    // and LZF cannot expand by more than 88 (a 3-byte back reference
    // yields at most 264 bytes), which also bounds PCL's allocation.
    uint32_t sizes_in_file[2] = {0, 0};
    std::ifstream file(path, std::ios::binary);
    file.seekg(static_cast<std::streamoff>(header_bytes));
    file.read(reinterpret_cast<char*>(sizes_in_file), sizeof(sizes_in_file));
    THROW_CHECK(file.good(), "PCD file " << path
                                         << " is truncated (no compressed "
                                            "data sizes)");
    const uint64_t compressed_size = sizes_in_file[0];
    const uint64_t uncompressed_size = sizes_in_file[1];
    const uint64_t expected_size =
        static_cast<uint64_t>(num_points) * static_cast<uint64_t>(point_bytes);
    THROW_CHECK(uncompressed_size == expected_size &&
                    compressed_size <= body_bytes - 8 &&
                    uncompressed_size <= 88 * compressed_size,
                "PCD file " << path << ": compressed data of "
                            << compressed_size << " bytes (" << body_bytes - 8
                            << " in the file) that expand to "
                            << uncompressed_size << " bytes, but "
                            << num_points << " points of " << point_bytes
                            << " bytes need " << expected_size);
  }
  return static_cast<size_t>(num_points);
}

// The PCD VIEWPOINT (sensor origin and orientation) is not applied: PCL
// itself leaves the points in the file's frame, and our scans are defined
// in the LIDAR frame.
LidarScan ReadPcdScan(const std::string& path) {
  THROW_CHECK(CheckPcdHeader(path) > 0,
              "LIDAR scan " << path << " has no points");
  pcl::PCLPointCloud2 cloud;
  pcl::PCDReader reader;
  // PCL's header parser indexes its token lists with .at(), so a header
  // that CheckPcdHeader accepts can still make it throw std::out_of_range
  // (found by fuzz_pcd); report that as the file's fault, not a crash.
  int read_status = -1;
  try {
    read_status = reader.read(path, cloud);
  } catch (const std::exception& e) {
    THROW_ERROR("Cannot parse PCD file " << path << ": " << e.what());
  }
  THROW_CHECK(read_status >= 0, "Cannot parse PCD file "
                                    << path << " (see PCL's message above)");
  const pcl::PCLPointField* xyz[3] = {FindPclField(cloud, "x"),
                                      FindPclField(cloud, "y"),
                                      FindPclField(cloud, "z")};
  for (int axis = 0; axis < 3; ++axis) {
    THROW_CHECK(xyz[axis] != nullptr, "PCD file " << path << " has no field '"
                                                  << "xyz"[axis] << "'");
  }
  const pcl::PCLPointField* intensity = FindPclField(cloud, "intensity");
  if (intensity == nullptr) {
    intensity = FindPclField(cloud, "reflectance");
  }
  const pcl::PCLPointField* ring = FindPclField(cloud, "ring");

  const size_t num_points =
      static_cast<size_t>(cloud.width) * static_cast<size_t>(cloud.height);
  THROW_CHECK(cloud.data.size() >=
                  static_cast<size_t>(cloud.row_step) * cloud.height &&
                  cloud.row_step >=
                      static_cast<size_t>(cloud.point_step) * cloud.width,
              "PCD file " << path << " has inconsistent point data");
  for (const pcl::PCLPointField* field : {xyz[0], xyz[1], xyz[2], intensity,
                                          ring}) {
    // The whole first scalar must lie in the record, not only its start.
    THROW_CHECK(field == nullptr ||
                    (PclScalarSize(field->datatype) > 0 &&
                     static_cast<size_t>(field->offset) +
                             PclScalarSize(field->datatype) <=
                         cloud.point_step),
                "PCD file " << path << ": field '" << field->name
                            << "' lies outside the point record or has an "
                               "unsupported type");
  }

  LidarScan scan;
  scan.points.resize(num_points);
  if (intensity != nullptr) {
    scan.intensities.resize(num_points);
  }
  if (ring != nullptr) {
    scan.rings.resize(num_points);
  }
  size_t index = 0;
  for (uint32_t row = 0; row < cloud.height; ++row) {
    for (uint32_t col = 0; col < cloud.width; ++col, ++index) {
      const uint8_t* record = cloud.data.data() +
                              static_cast<size_t>(row) * cloud.row_step +
                              static_cast<size_t>(col) * cloud.point_step;
      for (int axis = 0; axis < 3; ++axis) {
        scan.points[index][axis] = static_cast<float>(
            ReadPclScalar(record + xyz[axis]->offset, xyz[axis]->datatype,
                          xyz[axis]->name, path));
      }
      if (intensity != nullptr) {
        scan.intensities[index] = static_cast<float>(
            ReadPclScalar(record + intensity->offset, intensity->datatype,
                          intensity->name, path));
      }
      if (ring != nullptr) {
        scan.rings[index] = ToRing(ReadPclScalar(record + ring->offset,
                                                 ring->datatype, "ring", path),
                                   index, path);
      }
    }
  }
  return scan;
}

}  // namespace scan_io_internal

void WriteLidarScanPcd(const std::string& path, const LidarScan& scan,
                       const PcdFormat format) {
  THROW_CHECK(!scan.HasIntensities() || scan.intensities.size() == scan.size(),
              "Cannot write " << path << ": intensity count differs from "
                              << "point count");
  THROW_CHECK(!scan.HasRings() || scan.rings.size() == scan.size(),
              "Cannot write " << path << ": ring count differs from point "
                              << "count");
  pcl::PCLPointCloud2 cloud;
  auto add_field = [&cloud](const std::string& name, uint8_t datatype,
                            uint32_t size) {
    pcl::PCLPointField field;
    field.name = name;
    field.offset = cloud.point_step;
    field.datatype = datatype;
    field.count = 1;
    cloud.fields.push_back(field);
    cloud.point_step += size;
  };
  cloud.point_step = 0;
  add_field("x", pcl::PCLPointField::FLOAT32, 4);
  add_field("y", pcl::PCLPointField::FLOAT32, 4);
  add_field("z", pcl::PCLPointField::FLOAT32, 4);
  if (scan.HasIntensities()) {
    add_field("intensity", pcl::PCLPointField::FLOAT32, 4);
  }
  if (scan.HasRings()) {
    add_field("ring", pcl::PCLPointField::UINT16, 2);
  }
  cloud.width = static_cast<uint32_t>(scan.size());
  cloud.height = 1;
  cloud.is_dense = true;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.resize(cloud.row_step);
  for (size_t i = 0; i < scan.size(); ++i) {
    uint8_t* record = cloud.data.data() + i * cloud.point_step;
    std::memcpy(record, scan.points[i].data(), 12);
    size_t offset = 12;
    if (scan.HasIntensities()) {
      std::memcpy(record + offset, &scan.intensities[i], 4);
      offset += 4;
    }
    if (scan.HasRings()) {
      std::memcpy(record + offset, &scan.rings[i], 2);
    }
  }

  // PCL writes in place, so write beside the target and rename.
  const std::string temp_path =
      path + ".tmp." + std::to_string(::getpid());
  pcl::PCDWriter writer;
  const Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  const Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  int result = -1;
  switch (format) {
    case PcdFormat::kAscii:
      // 9 significant digits make float32 values round-trip exactly.
      result = writer.writeASCII(temp_path, cloud, origin, orientation, 9);
      break;
    case PcdFormat::kBinary:
      result = writer.writeBinary(temp_path, cloud, origin, orientation);
      break;
    case PcdFormat::kBinaryCompressed:
      result =
          writer.writeBinaryCompressed(temp_path, cloud, origin, orientation);
      break;
  }
  std::error_code error;
  if (result < 0) {
    std::filesystem::remove(temp_path, error);
    THROW_ERROR("Cannot write PCD file " << path
                                         << " (see PCL's message above)");
  }
  std::filesystem::rename(temp_path, path, error);
  if (error) {
    const std::string reason = error.message();
    std::filesystem::remove(temp_path, error);
    THROW_ERROR("Cannot write PCD file " << path << ": " << reason);
  }
}

}  // namespace colmap_lidar
