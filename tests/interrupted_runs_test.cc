// Interrupted runs (issue 18): the real build/colmap-lidar
// automatic_reconstructor is killed with SIGKILL at a random point inside
// each of its stages in turn, then run again with the same command line. The
// re-run must resume (skip the stages marked done, redo the killed one) and
// leave the workspace as an uninterrupted run leaves it.
//
// How: a reference run goes one stage at a time (`--stages :S`, each run
// resuming the earlier stages). Before stage S its workspace is copied; on
// the copy a run is killed inside S (a random 5-75 % of S's reference time
// after S's start line) and then run again. The copy and the reference must
// then hold the same files (no temporary left behind) with the same bytes,
// except:
//   - the stage records and the logs (pipeline/, *.log): they hold times;
//   - sfm: database.db and sparse/. Stock colmap's matching seeds its RANSAC
//     from the clock: two uninterrupted runs of this scene differ by up to
//     0.3 mm and 0.0006 deg. The refined poses must agree within 2 mm and
//     0.01 deg, over the same images;
//   - report: report/ shows the stage times; index.html must be complete.
// Every other stage is deterministic given its input (PatchMatch, the LIDAR
// fusion, stereo_fusion with its default single thread, the mesher, the
// evaluation), so its outputs must be identical.
// After each kill: S is not marked done, the earlier marks are intact, and no
// process (stock colmap, python) is left running in the workspace.
//
// The kill points come from a seed printed by the test; rerun one with
// COLMAP_LIDAR_KILL_SEED=<seed>.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The stages of a synthetic recording with priors (no odometry), in order.
const std::vector<std::string> kStages = {
    "synthesize", "import", "sfm",      "dense",    "patch_match",
    "fusion",     "mesh",   "evaluate", "report"};

// A small scene (10 frames, 640x360, a light LIDAR and survey; the evaluation
// without the LIDAR-only Poisson baseline): about 100 s uninterrupted.
std::vector<std::string> SceneArguments() {
  return {"--AutomaticReconstruction.num_threads", "2",
          "--AutomaticReconstruction.evaluate_lidar_baseline", "0",
          "--Synthesis.num_frames", "10",
          "--Synthesis.path_fraction", "0.1",
          "--Synthesis.image_width", "640",
          "--Synthesis.image_height", "360",
          "--Synthesis.supersampling", "1",
          "--Synthesis.lidar_columns", "512",
          "--Synthesis.survey_angular_step_deg", "0.4",
          "--Synthesis.survey_max_points", "200000",
          "--Synthesis.write_depth_maps", "false"};
}

std::vector<std::string> PipelineArguments(const std::string& workspace,
                                           const std::string& last_stage) {
  std::vector<std::string> args = {
      JoinPaths(testing::BinaryDir(), "colmap-lidar"),
      "automatic_reconstructor", "--workspace_path", workspace,
      "--AutomaticReconstruction.stages", ":" + last_stage};
  for (const std::string& arg : SceneArguments()) {
    args.push_back(arg);
  }
  return args;
}

// Starts `args` with stdout and stderr appended to `log_path`.
pid_t Start(const std::vector<std::string>& args, const std::string& log_path) {
  std::vector<char*> argv;
  for (const std::string& arg : args) {
    argv.push_back(const_cast<char*>(arg.c_str()));
  }
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd < 0 || ::dup2(fd, STDOUT_FILENO) < 0 ||
        ::dup2(fd, STDERR_FILENO) < 0) {
      ::_exit(126);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

int WaitExitCode(const pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) == -1 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Runs `args` to the end; returns the exit code.
int RunToEnd(const std::vector<std::string>& args, const std::string& log_path) {
  return WaitExitCode(Start(args, log_path));
}

std::string MarkPath(const std::string& workspace, const std::string& stage) {
  return JoinPaths(workspace, "pipeline/" + stage + ".done");
}

double StageWallSeconds(const std::string& workspace,
                        const std::string& stage) {
  std::ifstream file(MarkPath(workspace, stage));
  std::string key;
  double value = 0.0;
  while (file >> key) {
    if (key == "wall_seconds" && file >> value) {
      return value;
    }
    std::getline(file, key);
  }
  return -1.0;
}

// Pids of the processes whose command line mentions `text`, this one and
// its children excepted (zombies have an empty command line).
std::vector<pid_t> ProcessesMentioning(const std::string& text) {
  std::vector<pid_t> pids;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    std::ifstream cmdline(entry.path() / "cmdline", std::ios::binary);
    std::string line((std::istreambuf_iterator<char>(cmdline)),
                     std::istreambuf_iterator<char>());
    std::replace(line.begin(), line.end(), '\0', ' ');
    const pid_t pid = std::stoi(name);
    if (pid != ::getpid() && line.find(text) != std::string::npos) {
      pids.push_back(pid);
    }
  }
  return pids;
}

// Files under `dir` (relative paths, sorted).
std::vector<std::string> ListFiles(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) {
      files.push_back(fs::relative(entry.path(), dir).string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string Join(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) {
    text += (text.empty() ? "" : ", ") + item;
  }
  return text;
}

bool SameBytes(const std::string& path1, const std::string& path2) {
  if (fs::file_size(path1) != fs::file_size(path2)) {
    return false;
  }
  std::ifstream file1(path1, std::ios::binary);
  std::ifstream file2(path2, std::ios::binary);
  std::vector<char> buffer1(1 << 20);
  std::vector<char> buffer2(1 << 20);
  while (file1 && file2) {
    file1.read(buffer1.data(), buffer1.size());
    file2.read(buffer2.data(), buffer2.size());
    if (file1.gcount() != file2.gcount() ||
        !std::equal(buffer1.begin(), buffer1.begin() + file1.gcount(),
                    buffer2.begin())) {
      return false;
    }
  }
  return true;
}

// Whether a file may differ between an uninterrupted and a resumed run, for
// a workspace whose last stage is `stage` (see the top of the file).
bool MayDiffer(const std::string& file, const std::string& stage) {
  if (StringStartsWith(file, "pipeline/") || StringEndsWith(file, ".log")) {
    return true;
  }
  const bool after_sfm = std::find(kStages.begin(), kStages.end(), stage) >=
                         std::find(kStages.begin(), kStages.end(), "sfm");
  if (after_sfm &&
      (file == "database.db" || StringStartsWith(file, "sparse/"))) {
    // Only the sfm stage's own run is compared in these; later stages
    // read them from the same copy.
    return stage == "sfm";
  }
  return stage == "report" && StringStartsWith(file, "report/");
}

void ExpectSameWorkspace(const std::string& reference,
                         const std::string& resumed,
                         const std::string& stage) {
  const std::vector<std::string> reference_files = ListFiles(reference);
  const std::vector<std::string> resumed_files = ListFiles(resumed);
  std::vector<std::string> missing;
  std::vector<std::string> extra;
  std::set_difference(reference_files.begin(), reference_files.end(),
                      resumed_files.begin(), resumed_files.end(),
                      std::back_inserter(missing));
  std::set_difference(resumed_files.begin(), resumed_files.end(),
                      reference_files.begin(), reference_files.end(),
                      std::back_inserter(extra));
  EXPECT_TRUE(missing.empty())
      << stage << ": missing after the resumed run: "
      << Join(missing);
  EXPECT_TRUE(extra.empty())
      << stage << ": left behind by the killed run: "
      << Join(extra);
  int num_compared = 0;
  for (const std::string& file : reference_files) {
    if (MayDiffer(file, stage) ||
        !std::binary_search(resumed_files.begin(), resumed_files.end(),
                            file)) {
      continue;
    }
    ++num_compared;
    EXPECT_TRUE(SameBytes(JoinPaths(reference, file), JoinPaths(resumed, file)))
        << stage << ": " << file << " differs from the uninterrupted run's";
  }
  LOG(INFO) << stage << ": " << num_compared << " of " << reference_files.size()
            << " files identical to the uninterrupted run's";

  if (stage == "sfm") {
    const Reconstruction expected =
        ReadReconstruction(JoinPaths(reference, "sparse/refined"));
    const Reconstruction actual =
        ReadReconstruction(JoinPaths(resumed, "sparse/refined"));
    ASSERT_EQ(actual.images.size(), expected.images.size());
    double max_position_m = 0.0;
    double max_rotation_deg = 0.0;
    for (const Image& image : expected.images) {
      const Image* other = actual.FindImageByName(image.name);
      ASSERT_NE(other, nullptr) << image.name;
      max_position_m =
          std::max(max_position_m,
                   (image.ProjectionCenter() - other->ProjectionCenter()).norm());
      max_rotation_deg = std::max(
          max_rotation_deg,
          image.cam_from_world.rotation.angularDistance(
              other->cam_from_world.rotation) *
              180.0 / M_PI);
    }
    LOG(INFO) << "sfm: resumed poses within " << max_position_m << " m, "
              << max_rotation_deg << " deg of the uninterrupted run's";
    EXPECT_LT(max_position_m, 0.002);
    EXPECT_LT(max_rotation_deg, 0.01);
  }
  if (stage == "report") {
    const std::string html =
        ReadTextFile(JoinPaths(resumed, "report/index.html"));
    EXPECT_NE(html.find("</html>"), std::string::npos);
  }
}

TEST(InterruptedRuns, KilledInEveryStageResumesToTheSameResult) {
  unsigned seed = std::random_device()();
  if (const char* env = std::getenv("COLMAP_LIDAR_KILL_SEED")) {
    seed = static_cast<unsigned>(std::stoul(env));
  }
  LOG(INFO) << "kill points from seed " << seed
            << " (COLMAP_LIDAR_KILL_SEED to repeat)";
  std::mt19937 random(seed);

  const std::string dir = testing::CreateTestDir();
  const std::string reference = JoinPaths(dir, "reference");
  const std::string copy = JoinPaths(dir, "interrupted");
  const std::string reference_log = JoinPaths(dir, "reference.log");
  for (size_t s = 0; s < kStages.size(); ++s) {
    const std::string& stage = kStages[s];
    // The workspace before `stage`, and a snapshot of it for the retries.
    const std::string before = JoinPaths(dir, "before");
    fs::remove_all(copy);
    fs::remove_all(before);
    if (ExistsDir(reference)) {
      fs::copy(reference, copy, fs::copy_options::recursive);
      fs::copy(reference, before, fs::copy_options::recursive);
    }
    ASSERT_EQ(RunToEnd(PipelineArguments(reference, stage), reference_log), 0)
        << stage << ": the uninterrupted run failed; see " << reference_log;
    const double stage_seconds = StageWallSeconds(reference, stage);
    ASSERT_GT(stage_seconds, 0.0) << stage;

    // Killed inside the stage; a kill that comes after the stage ended is
    // retried on a fresh copy of the workspace before the stage (not of
    // the reference, which holds the stage's outputs: resumed from them,
    // the stage ends at once and every retry comes too late; a reference
    // run slowed by other tests made that happen) with a shorter delay.
    const std::string log = JoinPaths(dir, stage + ".log");
    bool killed_inside = false;
    double max_fraction = 0.75;
    for (int attempt = 0; attempt < 4 && !killed_inside; ++attempt) {
      if (attempt > 0) {
        fs::remove_all(copy);
        if (ExistsDir(before)) {
          fs::copy(before, copy, fs::copy_options::recursive);
        }
        max_fraction *= 0.3;
      }
      const double delay_s =
          std::uniform_real_distribution<double>(0.05 * max_fraction / 0.75,
                                                 max_fraction)(random) *
          stage_seconds;
      const std::streamoff log_start =
          ExistsFile(log) ? static_cast<std::streamoff>(fs::file_size(log)) : 0;
      const pid_t pid = Start(PipelineArguments(copy, stage), log);
      const std::string start_line =
          "automatic_reconstructor: stage " + stage + " ...";
      const auto deadline = Clock::now() + std::chrono::minutes(5);
      bool started = false;
      while (!started && Clock::now() < deadline) {
        std::ifstream file(log);
        file.seekg(log_start);
        const std::string text((std::istreambuf_iterator<char>(file)),
                               std::istreambuf_iterator<char>());
        started = text.find(start_line) != std::string::npos;
        if (!started) {
          std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
      }
      ASSERT_TRUE(started) << stage << ": no start line in " << log;
      std::this_thread::sleep_for(std::chrono::duration<double>(delay_s));
      ASSERT_EQ(::kill(pid, SIGKILL), 0);
      const int exit_code = WaitExitCode(pid);
      killed_inside = exit_code == 128 + SIGKILL &&
                      !ExistsFile(MarkPath(copy, stage));
      LOG(INFO) << stage << ": killed " << delay_s << " s after its start ("
                << stage_seconds << " s uninterrupted)"
                << (killed_inside ? "" : ", after it had ended; again");
    }
    ASSERT_TRUE(killed_inside) << stage << ": every kill came too late";
    for (size_t earlier = 0; earlier < s; ++earlier) {
      EXPECT_TRUE(ExistsFile(MarkPath(copy, kStages[earlier])))
          << kStages[earlier] << " lost its mark in a kill inside " << stage;
    }
    // Stock colmap and python die with the run that started them.
    std::vector<pid_t> left = ProcessesMentioning(copy);
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    while (!left.empty() && Clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      left = ProcessesMentioning(copy);
    }
    EXPECT_TRUE(left.empty()) << stage << ": " << left.size()
                              << " processes still run in the workspace";
    for (const pid_t pid : left) {
      ::kill(pid, SIGKILL);
    }

    // The same command again resumes and finishes the stage.
    const size_t resumed_log_start = fs::file_size(log);
    ASSERT_EQ(RunToEnd(PipelineArguments(copy, stage), log), 0)
        << stage << ": the resumed run failed; see " << log;
    const std::string resumed_log =
        ReadTextFile(log).substr(resumed_log_start);
    for (size_t earlier = 0; earlier < s; ++earlier) {
      EXPECT_NE(resumed_log.find("stage " + kStages[earlier] + " was done"),
                std::string::npos)
          << stage << ": the resumed run did not skip " << kStages[earlier];
    }
    ExpectSameWorkspace(reference, copy, stage);
    if (stage == "import") {
      // Recorded relative to the workspace, so that a copy (this one) uses
      // its own images and resumes from any working directory.
      EXPECT_EQ(StringTrim(ReadTextFile(
                    JoinPaths(copy, "pipeline/image_path.txt"))),
                "images");
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace colmap_lidar
