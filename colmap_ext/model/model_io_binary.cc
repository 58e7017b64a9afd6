// The binary formats of model_io.h: cameras/images/points3D.bin as colmap
// writes them, and our lines3D.bin.
#include "colmap_ext/model/model_io.h"

#include <cmath>
#include <cstring>
#include <set>
#include <sstream>

#include "colmap_ext/model/model_io_internal.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

using model_io_internal::CheckCamera;
using model_io_internal::CheckImageName;
using model_io_internal::NormalizedQuaternion;

// Minimum sizes of one record, to reject absurd counts of a corrupt file
// before allocating.
constexpr size_t kMinCameraBytes = 4 + 4 + 8 + 8;
constexpr size_t kMinImageBytes = 4 + 7 * 8 + 4 + 1 + 8;
constexpr size_t kPoint2DBytes = 8 + 8 + 8;
constexpr size_t kMinPoint3DBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr size_t kTrackElementBytes = 4 + 4;
constexpr size_t kMinLine3DBytes = 8 + 6 * 8 + 8 + 8;

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

}  // namespace

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

}  // namespace colmap_lidar
