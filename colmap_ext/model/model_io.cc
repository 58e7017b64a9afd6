#include "colmap_ext/model/model_io.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

// Minimum sizes of one record, to reject absurd counts of a corrupt file
// before allocating.
constexpr size_t kMinCameraBytes = 4 + 4 + 8 + 8;
constexpr size_t kMinImageBytes = 4 + 7 * 8 + 4 + 1 + 8;
constexpr size_t kPoint2DBytes = 8 + 8 + 8;
constexpr size_t kMinPoint3DBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr size_t kTrackElementBytes = 4 + 4;
constexpr size_t kMinLine3DBytes = 8 + 6 * 8 + 8 + 8;

// Text files print doubles like colmap (std::ostream precision 17).
constexpr int kTextPrecision = 17;

const char* const kModelFileNames[] = {"cameras", "images", "points3D",
                                       "lines3D"};

std::string FormatExtension(ModelFormat format) {
  return format == ModelFormat::kBinary ? ".bin" : ".txt";
}

// A whole binary file in memory with a read cursor; every failure names the
// file and the byte offset.
class BinaryFileReader {
 public:
  explicit BinaryFileReader(const std::string& path)
      : path_(path), data_(ReadTextFile(path)) {}

  template <typename T>
  T Read(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    CheckAvailable(sizeof(T), what);
    T value;
    std::memcpy(&value, data_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }

  double ReadFinite(const char* what) {
    const double value = Read<double>(what);
    THROW_CHECK(std::isfinite(value), path_ << ": non-finite " << what
                                            << " at byte "
                                            << offset_ - sizeof(double));
    return value;
  }

  std::string ReadNulTerminated(const char* what) {
    const size_t end = data_.find('\0', offset_);
    THROW_CHECK(end != std::string::npos,
                path_ << ": truncated file, unterminated " << what
                      << " at byte " << offset_);
    std::string value = data_.substr(offset_, end - offset_);
    offset_ = end + 1;
    return value;
  }

  // Rejects a count of records that cannot fit in the rest of the file.
  uint64_t ReadCount(size_t min_record_bytes, const char* what) {
    const uint64_t count = Read<uint64_t>(what);
    THROW_CHECK(count <= Remaining() / min_record_bytes,
                path_ << ": truncated or corrupt file, " << what << " " << count
                      << " at byte " << offset_ - 8 << " needs at least "
                      << count * min_record_bytes << " more bytes, "
                      << Remaining() << " left");
    return count;
  }

  size_t Remaining() const { return data_.size() - offset_; }
  size_t offset() const { return offset_; }
  const std::string& path() const { return path_; }

  void CheckEnd() const {
    THROW_CHECK(Remaining() == 0, path_ << ": " << Remaining()
                                        << " unexpected trailing bytes at byte "
                                        << offset_);
  }

 private:
  void CheckAvailable(size_t num_bytes, const char* what) const {
    THROW_CHECK(Remaining() >= num_bytes,
                path_ << ": truncated file, cannot read " << what << " at byte "
                      << offset_ << " (file has " << data_.size() << " bytes)");
  }

  std::string path_;
  std::string data_;
  size_t offset_ = 0;
};

// Text file tokens: one entry per non-empty line with its 1-based number.
struct TextLine {
  int number = 0;
  std::string text;
};

std::vector<std::string> Tokenize(const std::string& line) {
  std::vector<std::string> tokens;
  std::istringstream stream(line);
  std::string token;
  while (stream >> token) {
    tokens.push_back(token);
  }
  return tokens;
}

// Parsing with messages of the form "<path>:<line>: bad <what> '<token>'".
class TextParser {
 public:
  TextParser(const std::string& path, int line_number)
      : path_(path), line_number_(line_number) {}

  std::string Where() const {
    std::ostringstream where;
    where << path_ << ":" << line_number_;
    return where.str();
  }

  double Double(const std::string& token, const char* what) const {
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(token.c_str(), &end);
    // ERANGE on underflow (denormals) still gives the right value.
    const bool overflow = errno == ERANGE && std::abs(value) > 1.0;
    THROW_CHECK(!token.empty() && end == token.c_str() + token.size() &&
                    !overflow && std::isfinite(value),
                Where() << ": bad " << what << " '" << token << "'");
    return value;
  }

  uint64_t UInt(const std::string& token, uint64_t max_value,
                const char* what) const {
    char* end = nullptr;
    errno = 0;
    const unsigned long long value = std::strtoull(token.c_str(), &end, 10);
    THROW_CHECK(!token.empty() && token[0] != '-' && token[0] != '+' &&
                    end == token.c_str() + token.size() && errno != ERANGE &&
                    value <= max_value,
                Where() << ": bad " << what << " '" << token << "'");
    return value;
  }

 private:
  const std::string& path_;
  int line_number_;
};

// Non-comment, non-empty lines (trimmed), as colmap's text readers see them.
std::vector<TextLine> ReadDataLines(const std::string& path) {
  std::istringstream content(ReadTextFile(path));
  std::vector<TextLine> lines;
  std::string line;
  int number = 0;
  while (std::getline(content, line)) {
    ++number;
    line = StringTrim(line);
    if (line.empty() || line[0] == '#') {
      continue;
    }
    lines.push_back({number, line});
  }
  return lines;
}

// Leaves bytes of an already unit quaternion untouched (colmap wrote it
// normalised; renormalising could change the last bit).
Eigen::Quaterniond NormalizedQuaternion(double w, double x, double y, double z,
                                        const std::string& where) {
  Eigen::Quaterniond q(w, x, y, z);
  const double squared_norm = q.squaredNorm();
  THROW_CHECK(squared_norm > 0, where << ": zero quaternion");
  if (std::abs(squared_norm - 1.0) > 1e-12) {
    q.normalize();
  }
  return q;
}

void CheckCamera(const Camera& camera, const std::string& where) {
  try {
    camera.Check();
  } catch (const Error& error) {
    THROW_ERROR(where << ": " << error.what());
  }
}

void CheckImageName(const Image& image, ModelFormat format,
                    const std::string& path) {
  THROW_CHECK(
      image.name.find('\0') == std::string::npos,
      path << ": image " << image.image_id << " has a NUL byte in its name");
  if (format == ModelFormat::kText) {
    // colmap splits on spaces and takes the last token as the name.
    THROW_CHECK(!image.name.empty() &&
                    image.name.find_first_of(" \t\r\n") == std::string::npos,
                path << ": image " << image.image_id << " name '" << image.name
                     << "' is empty or has white space, which colmap's text "
                        "format cannot store; write binary");
  }
}

std::ostringstream TextStream() {
  std::ostringstream stream;
  stream.precision(kTextPrecision);
  return stream;
}

// Observations = points2D with a 3D point, as colmap counts them.
size_t NumObservations(const Reconstruction& reconstruction) {
  size_t num_observations = 0;
  for (const Image& image : reconstruction.images) {
    for (const Point2D& point2D : image.points2D) {
      if (point2D.point3D_id != kInvalidPoint3DId) {
        ++num_observations;
      }
    }
  }
  return num_observations;
}

void WriteText(const std::string& path, const std::string& content) {
  WriteFileAtomically(
      path, [&](std::ostream& stream) { stream << content; },
      /*binary=*/true);
}

void RemoveFileIfExists(const std::string& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
  THROW_CHECK(
      !ec, "Cannot remove stale model file " << path << ": " << ec.message());
}

}  // namespace

////////////////////////////////////////////////////////////////////////////////
// Folder level.
////////////////////////////////////////////////////////////////////////////////

bool ExistsModel(const std::string& dir) {
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const std::string ext = FormatExtension(format);
    if (ExistsFile(JoinPaths(dir, "cameras" + ext)) &&
        ExistsFile(JoinPaths(dir, "images" + ext)) &&
        ExistsFile(JoinPaths(dir, "points3D" + ext))) {
      return true;
    }
  }
  return false;
}

ModelFormat DetectModelFormat(const std::string& dir) {
  THROW_CHECK(ExistsDir(dir), "Model folder does not exist: " << dir);
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const std::string ext = FormatExtension(format);
    if (ExistsFile(JoinPaths(dir, "cameras" + ext)) &&
        ExistsFile(JoinPaths(dir, "images" + ext)) &&
        ExistsFile(JoinPaths(dir, "points3D" + ext))) {
      return format;
    }
  }
  THROW_ERROR("No COLMAP model in " << dir
                                    << ": cameras, images and points3D "
                                       "files (all .bin or all .txt) needed");
}

Reconstruction ReadReconstruction(const std::string& dir) {
  const ModelFormat format = DetectModelFormat(dir);
  const std::string ext = FormatExtension(format);
  const std::string other_ext =
      FormatExtension(format == ModelFormat::kBinary ? ModelFormat::kText
                                                     : ModelFormat::kBinary);
  Reconstruction reconstruction;
  const std::string lines_path = JoinPaths(dir, "lines3D" + ext);
  if (format == ModelFormat::kBinary) {
    ReadCamerasBinary(JoinPaths(dir, "cameras.bin"), &reconstruction);
    ReadImagesBinary(JoinPaths(dir, "images.bin"), &reconstruction);
    ReadPoints3DBinary(JoinPaths(dir, "points3D.bin"), &reconstruction);
    if (ExistsFile(lines_path)) {
      ReadLines3DBinary(lines_path, &reconstruction);
    }
  } else {
    ReadCamerasText(JoinPaths(dir, "cameras.txt"), &reconstruction);
    ReadImagesText(JoinPaths(dir, "images.txt"), &reconstruction);
    ReadPoints3DText(JoinPaths(dir, "points3D.txt"), &reconstruction);
    if (ExistsFile(lines_path)) {
      ReadLines3DText(lines_path, &reconstruction);
    }
  }
  const std::string other_lines_path = JoinPaths(dir, "lines3D" + other_ext);
  if (!ExistsFile(lines_path) && ExistsFile(other_lines_path)) {
    LOG(WARNING) << "Ignoring " << other_lines_path << ": the model in " << dir
                 << " is read in " << ext << " format";
  }
  LOG(INFO) << "Read model " << dir << " (" << ext
            << "): " << reconstruction.cameras.size() << " cameras, "
            << reconstruction.images.size() << " images, "
            << reconstruction.points3D.size() << " points, "
            << reconstruction.lines3D.size() << " lines";
  return reconstruction;
}

void WriteReconstruction(const std::string& dir,
                         const Reconstruction& reconstruction,
                         ModelFormat format) {
  reconstruction.CheckConsistency();
  CreateDirIfNotExists(dir);
  const std::string ext = FormatExtension(format);
  const std::string other_ext =
      FormatExtension(format == ModelFormat::kBinary ? ModelFormat::kText
                                                     : ModelFormat::kBinary);
  const std::string lines_path = JoinPaths(dir, "lines3D" + ext);
  if (format == ModelFormat::kBinary) {
    WriteCamerasBinary(JoinPaths(dir, "cameras.bin"), reconstruction);
    WriteImagesBinary(JoinPaths(dir, "images.bin"), reconstruction);
    WritePoints3DBinary(JoinPaths(dir, "points3D.bin"), reconstruction);
    if (!reconstruction.lines3D.empty()) {
      WriteLines3DBinary(lines_path, reconstruction);
    }
  } else {
    WriteCamerasText(JoinPaths(dir, "cameras.txt"), reconstruction);
    WriteImagesText(JoinPaths(dir, "images.txt"), reconstruction);
    WritePoints3DText(JoinPaths(dir, "points3D.txt"), reconstruction);
    if (!reconstruction.lines3D.empty()) {
      WriteLines3DText(lines_path, reconstruction);
    }
  }
  // Only now that the new model is complete: drop files that would hide it
  // (a .bin set wins over .txt) or go stale.
  if (reconstruction.lines3D.empty()) {
    RemoveFileIfExists(lines_path);
  }
  for (const char* name : kModelFileNames) {
    RemoveFileIfExists(JoinPaths(dir, name + other_ext));
  }
  LOG(INFO) << "Wrote model " << dir << " (" << ext
            << "): " << reconstruction.cameras.size() << " cameras, "
            << reconstruction.images.size() << " images, "
            << reconstruction.points3D.size() << " points, "
            << reconstruction.lines3D.size() << " lines";
}

////////////////////////////////////////////////////////////////////////////////
// Binary readers.
////////////////////////////////////////////////////////////////////////////////

void ReadCamerasBinary(const std::string& path,
                       Reconstruction* reconstruction) {
  BinaryFileReader reader(path);
  std::map<camera_t, Camera> cameras;
  std::vector<camera_t> order;
  const uint64_t num_cameras = reader.ReadCount(kMinCameraBytes, "num_cameras");
  for (uint64_t i = 0; i < num_cameras; ++i) {
    Camera camera;
    camera.camera_id = reader.Read<uint32_t>("camera_id");
    const int32_t model_id = reader.Read<int32_t>("model_id");
    THROW_CHECK(ExistsCameraModelWithId(model_id),
                path << ": camera " << camera.camera_id
                     << " has unknown camera model id " << model_id);
    camera.model_id = static_cast<CameraModelId>(model_id);
    camera.width = reader.Read<uint64_t>("width");
    camera.height = reader.Read<uint64_t>("height");
    camera.params.resize(CameraModelNumParams(camera.model_id));
    for (double& param : camera.params) {
      param = reader.ReadFinite("camera parameter");
    }
    // Cameras in a model always have a trusted focal length (colmap sets
    // prior_focal_length only in the database); keep the default.
    CheckCamera(camera, path);
    THROW_CHECK(cameras.emplace(camera.camera_id, camera).second,
                path << ": duplicate camera id " << camera.camera_id);
    order.push_back(camera.camera_id);
  }
  reader.CheckEnd();
  reconstruction->cameras = std::move(cameras);
  reconstruction->camera_file_order = std::move(order);
}

void ReadImagesBinary(const std::string& path, Reconstruction* reconstruction) {
  BinaryFileReader reader(path);
  std::vector<Image> images;
  std::set<image_t> image_ids;
  const uint64_t num_images = reader.ReadCount(kMinImageBytes, "num_images");
  images.reserve(num_images);
  for (uint64_t i = 0; i < num_images; ++i) {
    Image image;
    image.image_id = reader.Read<uint32_t>("image_id");
    std::ostringstream where;
    where << path << ": image " << image.image_id;
    double q[4];
    for (double& value : q) {
      value = reader.ReadFinite("quaternion");
    }
    image.cam_from_world.rotation =
        NormalizedQuaternion(q[0], q[1], q[2], q[3], where.str());
    for (int k = 0; k < 3; ++k) {
      image.cam_from_world.translation(k) = reader.ReadFinite("translation");
    }
    image.camera_id = reader.Read<uint32_t>("camera_id");
    image.name = reader.ReadNulTerminated("image name");
    const uint64_t num_points2D =
        reader.ReadCount(kPoint2DBytes, "num_points2D");
    image.points2D.resize(num_points2D);
    for (Point2D& point2D : image.points2D) {
      point2D.xy.x() = reader.ReadFinite("point2D x");
      point2D.xy.y() = reader.ReadFinite("point2D y");
      point2D.point3D_id = reader.Read<uint64_t>("point3D_id");
    }
    THROW_CHECK(image_ids.insert(image.image_id).second,
                path << ": duplicate image id " << image.image_id);
    images.push_back(std::move(image));
  }
  reader.CheckEnd();
  reconstruction->images = std::move(images);
}

void ReadPoints3DBinary(const std::string& path,
                        Reconstruction* reconstruction) {
  BinaryFileReader reader(path);
  std::map<point3D_t, Point3D> points3D;
  std::vector<point3D_t> order;
  const uint64_t num_points = reader.ReadCount(kMinPoint3DBytes, "num_points");
  order.reserve(num_points);
  for (uint64_t i = 0; i < num_points; ++i) {
    const point3D_t point3D_id = reader.Read<uint64_t>("point3D_id");
    THROW_CHECK(point3D_id != kInvalidPoint3DId,
                path << ": invalid point3D id at byte " << reader.offset() - 8);
    Point3D point3D;
    for (int k = 0; k < 3; ++k) {
      point3D.xyz(k) = reader.ReadFinite("point3D coordinate");
    }
    for (int k = 0; k < 3; ++k) {
      point3D.color(k) = reader.Read<uint8_t>("color");
    }
    point3D.error = reader.ReadFinite("error");
    const uint64_t track_length =
        reader.ReadCount(kTrackElementBytes, "track_length");
    point3D.track.resize(track_length);
    for (TrackElement& element : point3D.track) {
      element.image_id = reader.Read<uint32_t>("track image_id");
      element.point2D_idx = reader.Read<uint32_t>("track point2D_idx");
    }
    THROW_CHECK(points3D.emplace(point3D_id, std::move(point3D)).second,
                path << ": duplicate point3D id " << point3D_id);
    order.push_back(point3D_id);
  }
  reader.CheckEnd();
  reconstruction->points3D = std::move(points3D);
  reconstruction->point3D_file_order = std::move(order);
}

void ReadLines3DBinary(const std::string& path,
                       Reconstruction* reconstruction) {
  BinaryFileReader reader(path);
  std::map<line3D_t, Line3D> lines3D;
  const uint64_t num_lines = reader.ReadCount(kMinLine3DBytes, "num_lines");
  for (uint64_t i = 0; i < num_lines; ++i) {
    const line3D_t line3D_id = reader.Read<uint64_t>("line3D_id");
    THROW_CHECK(line3D_id != kInvalidLine3DId,
                path << ": invalid line3D id at byte " << reader.offset() - 8);
    Line3D line3D;
    for (int k = 0; k < 3; ++k) {
      line3D.start_in_world(k) = reader.ReadFinite("line start");
    }
    for (int k = 0; k < 3; ++k) {
      line3D.end_in_world(k) = reader.ReadFinite("line end");
    }
    line3D.error = reader.ReadFinite("error");
    const uint64_t track_length =
        reader.ReadCount(kTrackElementBytes, "track_length");
    line3D.track.resize(track_length);
    for (LineTrackElement& element : line3D.track) {
      element.image_id = reader.Read<uint32_t>("track image_id");
      element.line2D_idx = reader.Read<uint32_t>("track line2D_idx");
    }
    THROW_CHECK(lines3D.emplace(line3D_id, std::move(line3D)).second,
                path << ": duplicate line3D id " << line3D_id);
  }
  reader.CheckEnd();
  reconstruction->lines3D = std::move(lines3D);
}

////////////////////////////////////////////////////////////////////////////////
// Text readers.
////////////////////////////////////////////////////////////////////////////////

void ReadCamerasText(const std::string& path, Reconstruction* reconstruction) {
  std::map<camera_t, Camera> cameras;
  std::vector<camera_t> order;
  for (const TextLine& line : ReadDataLines(path)) {
    const TextParser parser(path, line.number);
    const std::vector<std::string> tokens = Tokenize(line.text);
    THROW_CHECK(tokens.size() >= 4,
                parser.Where() << ": expected CAMERA_ID MODEL WIDTH HEIGHT "
                                  "PARAMS[], got '"
                               << line.text << "'");
    Camera camera;
    camera.camera_id = static_cast<camera_t>(
        parser.UInt(tokens[0], kInvalidCameraId - 1, "camera id"));
    camera.model_id = CameraModelNameToId(tokens[1]);
    THROW_CHECK(camera.model_id != CameraModelId::kInvalid,
                parser.Where()
                    << ": unknown camera model '" << tokens[1] << "'");
    camera.width =
        parser.UInt(tokens[2], std::numeric_limits<uint64_t>::max(), "width");
    camera.height =
        parser.UInt(tokens[3], std::numeric_limits<uint64_t>::max(), "height");
    for (size_t i = 4; i < tokens.size(); ++i) {
      camera.params.push_back(parser.Double(tokens[i], "camera parameter"));
    }
    CheckCamera(camera, parser.Where());
    THROW_CHECK(cameras.emplace(camera.camera_id, camera).second,
                parser.Where() << ": duplicate camera id " << camera.camera_id);
    order.push_back(camera.camera_id);
  }
  reconstruction->cameras = std::move(cameras);
  reconstruction->camera_file_order = std::move(order);
}

void ReadImagesText(const std::string& path, Reconstruction* reconstruction) {
  // The points line follows its image line even when empty, so this reads
  // raw lines instead of ReadDataLines.
  std::istringstream content(ReadTextFile(path));
  std::vector<Image> images;
  std::set<image_t> image_ids;
  std::string line;
  int number = 0;
  while (std::getline(content, line)) {
    ++number;
    line = StringTrim(line);
    if (line.empty() || line[0] == '#') {
      continue;
    }
    const TextParser parser(path, number);
    const std::vector<std::string> tokens = Tokenize(line);
    THROW_CHECK(tokens.size() == 10,
                parser.Where() << ": expected IMAGE_ID QW QX QY QZ TX TY TZ "
                                  "CAMERA_ID NAME (10 fields, no spaces in "
                                  "the name), got "
                               << tokens.size() << " fields");
    Image image;
    image.image_id = static_cast<image_t>(
        parser.UInt(tokens[0], kInvalidImageId - 1, "image id"));
    double q[4];
    for (int k = 0; k < 4; ++k) {
      q[k] = parser.Double(tokens[1 + k], "quaternion");
    }
    image.cam_from_world.rotation =
        NormalizedQuaternion(q[0], q[1], q[2], q[3], parser.Where());
    for (int k = 0; k < 3; ++k) {
      image.cam_from_world.translation(k) =
          parser.Double(tokens[5 + k], "translation");
    }
    image.camera_id = static_cast<camera_t>(
        parser.UInt(tokens[8], kInvalidCameraId - 1, "camera id"));
    image.name = tokens[9];

    std::string points_line;
    THROW_CHECK(std::getline(content, points_line),
                parser.Where() << ": truncated file, missing the POINTS2D "
                                  "line of image "
                               << image.image_id);
    ++number;
    const TextParser points_parser(path, number);
    const std::vector<std::string> point_tokens =
        Tokenize(StringTrim(points_line));
    THROW_CHECK(point_tokens.size() % 3 == 0,
                points_parser.Where()
                    << ": POINTS2D of image " << image.image_id
                    << " is not X Y POINT3D_ID triplets");
    image.points2D.resize(point_tokens.size() / 3);
    for (size_t i = 0; i < image.points2D.size(); ++i) {
      Point2D& point2D = image.points2D[i];
      point2D.xy.x() = points_parser.Double(point_tokens[3 * i], "point2D x");
      point2D.xy.y() =
          points_parser.Double(point_tokens[3 * i + 1], "point2D y");
      const std::string& id_token = point_tokens[3 * i + 2];
      point2D.point3D_id =
          id_token == "-1" ? kInvalidPoint3DId
                           : points_parser.UInt(id_token, kInvalidPoint3DId - 1,
                                                "point3D id");
    }
    THROW_CHECK(image_ids.insert(image.image_id).second,
                parser.Where() << ": duplicate image id " << image.image_id);
    images.push_back(std::move(image));
  }
  reconstruction->images = std::move(images);
}

void ReadPoints3DText(const std::string& path, Reconstruction* reconstruction) {
  std::map<point3D_t, Point3D> points3D;
  std::vector<point3D_t> order;
  for (const TextLine& line : ReadDataLines(path)) {
    const TextParser parser(path, line.number);
    const std::vector<std::string> tokens = Tokenize(line.text);
    THROW_CHECK(tokens.size() >= 8 && tokens.size() % 2 == 0,
                parser.Where() << ": expected POINT3D_ID X Y Z R G B ERROR "
                                  "and (IMAGE_ID POINT2D_IDX) pairs");
    const point3D_t point3D_id =
        parser.UInt(tokens[0], kInvalidPoint3DId - 1, "point3D id");
    Point3D point3D;
    for (int k = 0; k < 3; ++k) {
      point3D.xyz(k) = parser.Double(tokens[1 + k], "coordinate");
    }
    for (int k = 0; k < 3; ++k) {
      point3D.color(k) =
          static_cast<uint8_t>(parser.UInt(tokens[4 + k], 255, "color"));
    }
    point3D.error = parser.Double(tokens[7], "error");
    for (size_t i = 8; i < tokens.size(); i += 2) {
      TrackElement element;
      element.image_id = static_cast<image_t>(
          parser.UInt(tokens[i], kInvalidImageId - 1, "track image id"));
      element.point2D_idx = static_cast<point2D_t>(parser.UInt(
          tokens[i + 1], kInvalidPoint2DIdx - 1, "track point2D idx"));
      point3D.track.push_back(element);
    }
    THROW_CHECK(points3D.emplace(point3D_id, std::move(point3D)).second,
                parser.Where() << ": duplicate point3D id " << point3D_id);
    order.push_back(point3D_id);
  }
  reconstruction->points3D = std::move(points3D);
  reconstruction->point3D_file_order = std::move(order);
}

void ReadLines3DText(const std::string& path, Reconstruction* reconstruction) {
  std::map<line3D_t, Line3D> lines3D;
  for (const TextLine& line : ReadDataLines(path)) {
    const TextParser parser(path, line.number);
    const std::vector<std::string> tokens = Tokenize(line.text);
    THROW_CHECK(tokens.size() >= 8 && tokens.size() % 2 == 0,
                parser.Where() << ": expected LINE3D_ID SX SY SZ EX EY EZ "
                                  "ERROR and (IMAGE_ID LINE2D_IDX) pairs");
    const line3D_t line3D_id =
        parser.UInt(tokens[0], kInvalidLine3DId - 1, "line3D id");
    Line3D line3D;
    for (int k = 0; k < 3; ++k) {
      line3D.start_in_world(k) = parser.Double(tokens[1 + k], "line start");
      line3D.end_in_world(k) = parser.Double(tokens[4 + k], "line end");
    }
    line3D.error = parser.Double(tokens[7], "error");
    for (size_t i = 8; i < tokens.size(); i += 2) {
      LineTrackElement element;
      element.image_id = static_cast<image_t>(
          parser.UInt(tokens[i], kInvalidImageId - 1, "track image id"));
      element.line2D_idx = static_cast<uint32_t>(
          parser.UInt(tokens[i + 1], std::numeric_limits<uint32_t>::max(),
                      "track line2D idx"));
      line3D.track.push_back(element);
    }
    THROW_CHECK(lines3D.emplace(line3D_id, std::move(line3D)).second,
                parser.Where() << ": duplicate line3D id " << line3D_id);
  }
  reconstruction->lines3D = std::move(lines3D);
}

////////////////////////////////////////////////////////////////////////////////
// Binary writers.
////////////////////////////////////////////////////////////////////////////////

void WriteCamerasBinary(const std::string& path,
                        const Reconstruction& reconstruction) {
  AtomicFileWriter writer(path);
  std::ostream& stream = writer.stream();
  WriteBinary<uint64_t>(stream, reconstruction.cameras.size());
  for (const camera_t camera_id : reconstruction.CameraIdsInWriteOrder()) {
    const Camera& camera = reconstruction.cameras.at(camera_id);
    CheckCamera(camera, path);
    WriteBinary<uint32_t>(stream, camera_id);
    WriteBinary<int32_t>(stream, static_cast<int32_t>(camera.model_id));
    WriteBinary<uint64_t>(stream, camera.width);
    WriteBinary<uint64_t>(stream, camera.height);
    WriteBinaryArray(stream, camera.params.data(), camera.params.size());
  }
  writer.Commit();
}

void WriteImagesBinary(const std::string& path,
                       const Reconstruction& reconstruction) {
  AtomicFileWriter writer(path);
  std::ostream& stream = writer.stream();
  WriteBinary<uint64_t>(stream, reconstruction.images.size());
  for (const Image& image : reconstruction.images) {
    CheckImageName(image, ModelFormat::kBinary, path);
    WriteBinary<uint32_t>(stream, image.image_id);
    const Eigen::Quaterniond& q = image.cam_from_world.rotation;
    const double qvec[4] = {q.w(), q.x(), q.y(), q.z()};
    WriteBinaryArray(stream, qvec, 4);
    WriteBinaryArray(stream, image.cam_from_world.translation.data(), 3);
    WriteBinary<uint32_t>(stream, image.camera_id);
    stream.write(image.name.c_str(), image.name.size() + 1);
    WriteBinary<uint64_t>(stream, image.points2D.size());
    for (const Point2D& point2D : image.points2D) {
      WriteBinary<double>(stream, point2D.xy.x());
      WriteBinary<double>(stream, point2D.xy.y());
      WriteBinary<uint64_t>(stream, point2D.point3D_id);
    }
  }
  writer.Commit();
}

void WritePoints3DBinary(const std::string& path,
                         const Reconstruction& reconstruction) {
  AtomicFileWriter writer(path);
  std::ostream& stream = writer.stream();
  WriteBinary<uint64_t>(stream, reconstruction.points3D.size());
  for (const point3D_t point3D_id : reconstruction.Point3DIdsInWriteOrder()) {
    const Point3D& point3D = reconstruction.points3D.at(point3D_id);
    WriteBinary<uint64_t>(stream, point3D_id);
    WriteBinaryArray(stream, point3D.xyz.data(), 3);
    WriteBinaryArray(stream, point3D.color.data(), 3);
    WriteBinary<double>(stream, point3D.error);
    WriteBinary<uint64_t>(stream, point3D.track.size());
    for (const TrackElement& element : point3D.track) {
      WriteBinary<uint32_t>(stream, element.image_id);
      WriteBinary<uint32_t>(stream, element.point2D_idx);
    }
  }
  writer.Commit();
}

void WriteLines3DBinary(const std::string& path,
                        const Reconstruction& reconstruction) {
  AtomicFileWriter writer(path);
  std::ostream& stream = writer.stream();
  WriteBinary<uint64_t>(stream, reconstruction.lines3D.size());
  for (const auto& [line3D_id, line3D] : reconstruction.lines3D) {
    WriteBinary<uint64_t>(stream, line3D_id);
    WriteBinaryArray(stream, line3D.start_in_world.data(), 3);
    WriteBinaryArray(stream, line3D.end_in_world.data(), 3);
    WriteBinary<double>(stream, line3D.error);
    WriteBinary<uint64_t>(stream, line3D.track.size());
    for (const LineTrackElement& element : line3D.track) {
      WriteBinary<uint32_t>(stream, element.image_id);
      WriteBinary<uint32_t>(stream, element.line2D_idx);
    }
  }
  writer.Commit();
}

////////////////////////////////////////////////////////////////////////////////
// Text writers: the same headers and formatting as colmap's.
////////////////////////////////////////////////////////////////////////////////

void WriteCamerasText(const std::string& path,
                      const Reconstruction& reconstruction) {
  std::ostringstream text = TextStream();
  text << "# Camera list with one line of data per camera:\n"
       << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
       << "# Number of cameras: " << reconstruction.cameras.size() << "\n";
  for (const camera_t camera_id : reconstruction.CameraIdsInWriteOrder()) {
    const Camera& camera = reconstruction.cameras.at(camera_id);
    CheckCamera(camera, path);
    text << camera_id << " " << camera.ModelName() << " " << camera.width << " "
         << camera.height;
    for (const double param : camera.params) {
      text << " " << param;
    }
    text << "\n";
  }
  WriteText(path, text.str());
}

void WriteImagesText(const std::string& path,
                     const Reconstruction& reconstruction) {
  const double mean_observations =
      reconstruction.images.empty()
          ? 0.0
          : static_cast<double>(NumObservations(reconstruction)) /
                static_cast<double>(reconstruction.images.size());
  std::ostringstream text = TextStream();
  text << "# Image list with two lines of data per image:\n"
       << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
       << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
       << "# Number of images: " << reconstruction.images.size()
       << ", mean observations per image: " << mean_observations << "\n";
  for (const Image& image : reconstruction.images) {
    CheckImageName(image, ModelFormat::kText, path);
    const Eigen::Quaterniond& q = image.cam_from_world.rotation;
    const Eigen::Vector3d& t = image.cam_from_world.translation;
    text << image.image_id << " " << q.w() << " " << q.x() << " " << q.y()
         << " " << q.z() << " " << t.x() << " " << t.y() << " " << t.z() << " "
         << image.camera_id << " " << image.name << "\n";
    bool first = true;
    for (const Point2D& point2D : image.points2D) {
      text << (first ? "" : " ") << point2D.xy.x() << " " << point2D.xy.y()
           << " ";
      if (point2D.point3D_id == kInvalidPoint3DId) {
        text << -1;
      } else {
        text << point2D.point3D_id;
      }
      first = false;
    }
    text << "\n";
  }
  WriteText(path, text.str());
}

void WritePoints3DText(const std::string& path,
                       const Reconstruction& reconstruction) {
  size_t track_sum = 0;
  for (const auto& entry : reconstruction.points3D) {
    track_sum += entry.second.track.size();
  }
  const double mean_track_length =
      reconstruction.points3D.empty()
          ? 0.0
          : static_cast<double>(track_sum) /
                static_cast<double>(reconstruction.points3D.size());
  std::ostringstream text = TextStream();
  text << "# 3D point list with one line of data per point:\n"
       << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, "
          "POINT2D_IDX)\n"
       << "# Number of points: " << reconstruction.points3D.size()
       << ", mean track length: " << mean_track_length << "\n";
  for (const point3D_t point3D_id : reconstruction.Point3DIdsInWriteOrder()) {
    const Point3D& point3D = reconstruction.points3D.at(point3D_id);
    text << point3D_id << " " << point3D.xyz.x() << " " << point3D.xyz.y()
         << " " << point3D.xyz.z() << " " << static_cast<int>(point3D.color(0))
         << " " << static_cast<int>(point3D.color(1)) << " "
         << static_cast<int>(point3D.color(2)) << " " << point3D.error;
    for (const TrackElement& element : point3D.track) {
      text << " " << element.image_id << " " << element.point2D_idx;
    }
    text << "\n";
  }
  WriteText(path, text.str());
}

void WriteLines3DText(const std::string& path,
                      const Reconstruction& reconstruction) {
  size_t track_sum = 0;
  for (const auto& entry : reconstruction.lines3D) {
    track_sum += entry.second.track.size();
  }
  const double mean_track_length =
      reconstruction.lines3D.empty()
          ? 0.0
          : static_cast<double>(track_sum) /
                static_cast<double>(reconstruction.lines3D.size());
  std::ostringstream text = TextStream();
  text << "# 3D line list with one line of data per line (colmap-lidar):\n"
       << "#   LINE3D_ID, SX, SY, SZ, EX, EY, EZ, ERROR, TRACK[] as "
          "(IMAGE_ID, LINE2D_IDX)\n"
       << "# Number of lines: " << reconstruction.lines3D.size()
       << ", mean track length: " << mean_track_length << "\n";
  for (const auto& [line3D_id, line3D] : reconstruction.lines3D) {
    text << line3D_id;
    for (int k = 0; k < 3; ++k) {
      text << " " << line3D.start_in_world(k);
    }
    for (int k = 0; k < 3; ++k) {
      text << " " << line3D.end_in_world(k);
    }
    text << " " << line3D.error;
    for (const LineTrackElement& element : line3D.track) {
      text << " " << element.image_id << " " << element.line2D_idx;
    }
    text << "\n";
  }
  WriteText(path, text.str());
}

}  // namespace colmap_lidar
