// The text formats of model_io.h: cameras/images/points3D.txt as colmap
// writes them, and our lines3D.txt.
#include "colmap_ext/model/model_io.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>

#include "colmap_ext/model/model_io_internal.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

using model_io_internal::CheckCamera;
using model_io_internal::CheckImageName;
using model_io_internal::NormalizedQuaternion;

// Text files print doubles like colmap (std::ostream precision 17).
constexpr int kTextPrecision = 17;

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

}  // namespace

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
