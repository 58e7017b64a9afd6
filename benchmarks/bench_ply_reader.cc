// Time to read one binary little-endian PLY of COLMAP's fused.ply layout
// (float x y z nx ny nz, uchar red green blue; 27-byte records) with our
// reader (colmap_ext/util/ply.h: ReadPly, the generic column reader, and
// ReadPlyPoints, the fused.ply reader) and with library readers: PCL 1.13's
// pcl::PLYReader (already linked by src/lidar) and, when CMake finds it,
// VTK 9's vtkPLYReader (Debian libvtk9-dev, pulled in by PCL). Issue 20:
// "measure PLY reading speed against the current reader before touching it".
//
// Before the timings, the executable prints a strictness table: which reader
// rejects (throws or reports an error) a truncated file, a header that
// over-claims the vertex count, and trailing bytes after the last vertex; and
// how many points a reader that accepts returns.
//
// The files are written once per process with our writer
// (WriteColmapPlyPoints) from points with a fixed seed, in a fresh folder
// under the system temp dir that is removed at exit.
// Run: build/benchmarks/bench_ply_reader (docs/benchmarks/ply_reader.md).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/console/print.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#ifdef COLMAP_LIDAR_BENCH_WITH_VTK
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#endif

#include "colmap_ext/util/ply.h"

namespace colmap_lidar {
namespace {

namespace fs = std::filesystem;

// The folder of the generated files, created on first use.
const fs::path& WorkDir() {
  static const fs::path dir = [] {
    const fs::path path = fs::temp_directory_path() /
                          ("bench_ply_reader_" + std::to_string(getpid()));
    fs::create_directories(path);
    return path;
  }();
  return dir;
}

std::vector<PlyPoint> MakePoints(size_t num_points) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> position(-50.0f, 50.0f);
  std::normal_distribution<float> gaussian(0.0f, 1.0f);
  std::uniform_int_distribution<int> color(0, 255);
  std::vector<PlyPoint> points(num_points);
  for (PlyPoint& point : points) {
    point.xyz = Eigen::Vector3f(position(rng), position(rng), position(rng));
    point.normal =
        Eigen::Vector3f(gaussian(rng), gaussian(rng), gaussian(rng))
            .normalized();
    point.rgb = {static_cast<uint8_t>(color(rng)),
                 static_cast<uint8_t>(color(rng)),
                 static_cast<uint8_t>(color(rng))};
  }
  return points;
}

// fused_<n>.ply, written once per size.
std::string PlyFile(size_t num_points) {
  static std::map<size_t, std::string> paths;
  auto it = paths.find(num_points);
  if (it == paths.end()) {
    const std::string path =
        (WorkDir() / ("fused_" + std::to_string(num_points) + ".ply"))
            .string();
    WriteColmapPlyPoints(path, MakePoints(num_points));
    it = paths.emplace(num_points, path).first;
  }
  return it->second;
}

// ---- Readers: each returns the number of points read, or -1 when it
// reports an error.

int64_t ReadOurs(const std::string& path) {
  try {
    return static_cast<int64_t>(ReadPly(path).NumVertices());
  } catch (const std::exception&) {
    return -1;
  }
}

int64_t ReadOursPoints(const std::string& path) {
  try {
    return static_cast<int64_t>(ReadPlyPoints(path).size());
  } catch (const std::exception&) {
    return -1;
  }
}

int64_t ReadPcl(const std::string& path) {
  pcl::PointCloud<pcl::PointXYZRGBNormal> cloud;
  pcl::PLYReader reader;
  if (reader.read(path, cloud) < 0) {
    return -1;
  }
  return static_cast<int64_t>(cloud.size());
}

#ifdef COLMAP_LIDAR_BENCH_WITH_VTK
void CountError(vtkObject*, unsigned long, void* client_data, void*) {
  ++*static_cast<int*>(client_data);
}

int64_t ReadVtk(const std::string& path) {
  int num_errors = 0;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetCallback(&CountError);
  on_error->SetClientData(&num_errors);
  vtkNew<vtkPLYReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, on_error);
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* output = reader->GetOutput();
  if (num_errors > 0 || reader->GetErrorCode() != 0 || output == nullptr) {
    return -1;
  }
  // Touch the attributes so that they are part of the measured read.
  if (output->GetPointData()->GetNormals() == nullptr) {
    return -1;
  }
  return static_cast<int64_t>(output->GetNumberOfPoints());
}
#endif

struct Reader {
  const char* name;
  std::function<int64_t(const std::string&)> read;
};

std::vector<Reader> Readers() {
  std::vector<Reader> readers = {
      {"ours ReadPly", &ReadOurs},
      {"ours ReadPlyPoints", &ReadOursPoints},
      {"PCL PLYReader", &ReadPcl},
  };
#ifdef COLMAP_LIDAR_BENCH_WITH_VTK
  readers.push_back({"VTK vtkPLYReader", &ReadVtk});
#endif
  return readers;
}

// ---- Strictness.

std::string ReadBytes(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  std::string bytes(fs::file_size(path), '\0');
  stream.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return bytes;
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream stream(path, std::ios::binary);
  stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// `bytes` with the "element vertex N" count replaced.
std::string WithVertexCount(const std::string& bytes, size_t old_count,
                            size_t new_count) {
  const std::string old_line = "element vertex " + std::to_string(old_count);
  const size_t pos = bytes.find(old_line);
  if (pos == std::string::npos) {
    std::cerr << "no '" << old_line << "' in the header\n";
    std::exit(EXIT_FAILURE);
  }
  return bytes.substr(0, pos) + "element vertex " +
         std::to_string(new_count) + bytes.substr(pos + old_line.size());
}

void PrintStrictnessTable() {
  constexpr size_t kNumPoints = 1000;
  constexpr size_t kRecordBytes = 27;
  const std::string good_path = PlyFile(kNumPoints);
  const std::string good = ReadBytes(good_path);
  struct Case {
    std::string name;
    std::string bytes;
  };
  const std::vector<Case> cases = {
      {"intact (1000 vertices)", good},
      {"truncated mid-record (last 13 bytes cut)",
       good.substr(0, good.size() - 13)},
      {"truncated by half the body",
       good.substr(0, good.size() - kNumPoints * kRecordBytes / 2)},
      {"header claims 1001 vertices, body has 1000",
       WithVertexCount(good, kNumPoints, kNumPoints + 1)},
      {"header claims 2000 vertices, body has 1000",
       WithVertexCount(good, kNumPoints, 2 * kNumPoints)},
      {"27 trailing bytes after the last vertex",
       good + std::string(kRecordBytes, '\x01')},
  };
  // The library readers print their own errors; keep the table readable.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
#ifdef COLMAP_LIDAR_BENCH_WITH_VTK
  vtkObject::GlobalWarningDisplayOff();
#endif
  const std::vector<Reader> readers = Readers();
  std::cout << "| file |";
  for (const Reader& reader : readers) {
    std::cout << " " << reader.name << " |";
  }
  std::cout << "\n|---|";
  for (size_t i = 0; i < readers.size(); ++i) {
    std::cout << "---|";
  }
  std::cout << "\n";
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string path =
        (WorkDir() / ("case_" + std::to_string(i) + ".ply")).string();
    WriteBytes(path, cases[i].bytes);
    std::cout << "| " << cases[i].name << " |";
    for (const Reader& reader : readers) {
      const int64_t num_read = reader.read(path);
      if (num_read < 0) {
        std::cout << " rejected |";
      } else {
        std::cout << " accepted, " << num_read << " points |";
      }
    }
    std::cout << "\n";
  }
  std::cout << std::endl;
  // PCL warns on every read that the file has no "curvature" field of
  // pcl::PointXYZRGBNormal; errors stay on for the timings.
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
#ifdef COLMAP_LIDAR_BENCH_WITH_VTK
  vtkObject::GlobalWarningDisplayOn();
#endif
}

// ---- Timings: one benchmark per reader, Arg = number of vertices.

void ReadBenchmark(benchmark::State& state,
                   int64_t (*read)(const std::string&)) {
  const size_t num_points = static_cast<size_t>(state.range(0));
  const std::string path = PlyFile(num_points);
  int64_t num_read = 0;
  for (auto _ : state) {
    num_read = read(path);
    benchmark::DoNotOptimize(num_read);
  }
  if (num_read != static_cast<int64_t>(num_points)) {
    state.SkipWithError("the reader returned a different point count");
    return;
  }
  state.SetBytesProcessed(static_cast<int64_t>(fs::file_size(path)) *
                         static_cast<int64_t>(state.iterations()));
}

// The floor: the file's bytes into memory, no parsing.
int64_t ReadFileBytes(const std::string& path) {
  const std::string bytes = ReadBytes(path);
  const size_t header_end = bytes.find("end_header\n");
  if (header_end == std::string::npos) {
    return -1;
  }
  return static_cast<int64_t>((bytes.size() - header_end - 11) / 27);
}

void BM_FileBytesOnly(benchmark::State& state) {
  ReadBenchmark(state, &ReadFileBytes);
}
void BM_OursReadPly(benchmark::State& state) { ReadBenchmark(state, &ReadOurs); }
void BM_OursReadPlyPoints(benchmark::State& state) {
  ReadBenchmark(state, &ReadOursPoints);
}
void BM_PclPlyReader(benchmark::State& state) {
  ReadBenchmark(state, &ReadPcl);
}
BENCHMARK(BM_FileBytesOnly)->Arg(200000)->Arg(2000000)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OursReadPly)->Arg(200000)->Arg(2000000)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OursReadPlyPoints)->Arg(200000)->Arg(2000000)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PclPlyReader)->Arg(200000)->Arg(2000000)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
#ifdef COLMAP_LIDAR_BENCH_WITH_VTK
void BM_VtkPlyReader(benchmark::State& state) {
  ReadBenchmark(state, &ReadVtk);
}
BENCHMARK(BM_VtkPlyReader)->Arg(200000)->Arg(2000000)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
#endif

}  // namespace
}  // namespace colmap_lidar

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) {
    return EXIT_FAILURE;
  }
  colmap_lidar::PrintStrictnessTable();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::filesystem::remove_all(colmap_lidar::WorkDir());
  return EXIT_SUCCESS;
}
