// Runs the real build/colmap-lidar executable: command dispatch, help,
// option errors and the INI presets of configs/.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/string.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

std::string Quote(const std::string& text) { return "'" + text + "'"; }

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr together.
};

// Runs `colmap-lidar <arguments>` (a shell fragment).
Result RunCli(const std::string& arguments) {
  const std::string log = JoinPaths(testing::CreateTestDir(), "cli.log");
  Result result;
  result.exit_code = testing::RunCommand(
      Quote(JoinPaths(testing::BinaryDir(), "colmap-lidar")) + " " +
          arguments,
      log);
  result.output = ReadTextFile(log);
  return result;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The "Section.name" keys of an INI text, comments and blanks skipped.
std::set<std::string> IniKeys(const std::string& text) {
  std::set<std::string> keys;
  std::string section;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    line = StringTrim(line);
    if (line.empty() || line[0] == '#') {
      continue;
    }
    if (line.front() == '[' && line.back() == ']') {
      section = line.substr(1, line.size() - 2);
      continue;
    }
    const std::string key = StringTrim(line.substr(0, line.find('=')));
    keys.insert(section.empty() ? key : section + "." + key);
  }
  return keys;
}

// The command names listed by `colmap-lidar help`, with their descriptions.
std::vector<std::pair<std::string, std::string>> ListedCommands(
    const std::string& help) {
  std::vector<std::pair<std::string, std::string>> commands;
  std::istringstream lines(help.substr(help.find("Commands:\n") + 10));
  std::string line;
  while (std::getline(lines, line)) {
    const std::string trimmed = StringTrim(line);
    const size_t space = trimmed.find(' ');
    if (StringStartsWith(line, "  ") && space != std::string::npos) {
      commands.emplace_back(trimmed.substr(0, space),
                            StringTrim(trimmed.substr(space)));
    }
  }
  return commands;
}

TEST(Cli, HelpListsCommands) {
  for (const char* arguments : {"help", "", "-h", "--help"}) {
    const Result result = RunCli(arguments);
    EXPECT_EQ(result.exit_code, 0) << arguments;
    const auto commands = ListedCommands(result.output);
    const std::pair<std::string, std::string> importer = {
        "lidar_importer",
        "Import a camera + LIDAR recording into a COLMAP workspace."};
    EXPECT_NE(std::find(commands.begin(), commands.end(), importer),
              commands.end())
        << result.output;
    EXPECT_EQ(commands.front().first, "help") << result.output;
  }
}

TEST(Cli, VersionPrintsBothVersions) {
  const Result result = RunCli("version");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(Contains(result.output, "colmap-lidar 0.")) << result.output;
  EXPECT_TRUE(Contains(result.output, "colmap 3.8 (")) << result.output;
}

TEST(Cli, CommandHelpShowsOptionsWithDefaults) {
  const Result result = RunCli("lidar_importer -h");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  const Result help_command = RunCli("help lidar_importer");
  EXPECT_EQ(help_command.exit_code, 0) << help_command.output;
  EXPECT_EQ(help_command.output, result.output);
  for (const char* expected :
       {"--dataset_path <string>  (required)",
        "--workspace_path <string>  (required)",
        "--database_path <string>  (default: \"\")",
        "[LidarImport] options:",
        "--LidarImport.input_format <string>  (default: auto)",
        "--LidarImport.copy_images <bool>  (default: true)",
        "--LidarImport.kitti_camera <int>  (default: 2)",
        "--LidarImport.overwrite <bool>  (default: false)", "0..3",
        "--project_path", "--check_options"}) {
    EXPECT_TRUE(Contains(result.output, expected))
        << expected << "\n" << result.output;
  }
}

TEST(Cli, UnknownCommandFails) {
  const Result result = RunCli("lidar_improter");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_TRUE(Contains(result.output, "ERROR: unknown command 'lidar_improter'"))
      << result.output;
}

TEST(Cli, UnknownOptionFailsNamingIt) {
  const Result result = RunCli(
      "lidar_importer --dataset_path /tmp --workspace_path /tmp/ws "
      "--LidarImport.copy_imagez 1");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_TRUE(Contains(result.output, "ERROR:")) << result.output;
  EXPECT_TRUE(Contains(result.output, "LidarImport.copy_imagez"))
      << result.output;
}

TEST(Cli, MissingRequiredOptionFails) {
  const Result result = RunCli("lidar_importer --dataset_path /tmp");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_TRUE(Contains(result.output, "--workspace_path is required"))
      << result.output;
}

TEST(Cli, BadValueFailsNamingIt) {
  const Result not_a_number = RunCli(
      "lidar_importer --dataset_path /tmp --workspace_path /tmp/ws "
      "--LidarImport.kitti_camera two");
  EXPECT_NE(not_a_number.exit_code, 0);
  EXPECT_TRUE(Contains(not_a_number.output, "--LidarImport.kitti_camera"))
      << not_a_number.output;

  // Out of range: ImporterOptions::Check() names the option.
  const Result out_of_range = RunCli(
      "lidar_importer --dataset_path /tmp --workspace_path /tmp/ws "
      "--LidarImport.kitti_camera 7");
  EXPECT_NE(out_of_range.exit_code, 0);
  EXPECT_TRUE(Contains(out_of_range.output, "LidarImport.kitti_camera"))
      << out_of_range.output;
}

TEST(Cli, MeshEvaluatorAlignmentNeedsModelAndPoses) {
  const std::string dir = testing::CreateTestDir();
  const std::string ply = JoinPaths(dir, "points.ply");
  std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 1\n"
                        "property float x\nproperty float y\n"
                        "property float z\nend_header\n0 0 0\n";
  const std::string base = "mesh_evaluator --input_path " + Quote(ply) +
                           " --reference_path " + Quote(ply);
  const Result bad_value = RunCli(base + " --alignment affine");
  EXPECT_NE(bad_value.exit_code, 0);
  EXPECT_TRUE(Contains(bad_value.output,
                       "--alignment must be none, se3, sim3, se3_axes or "
                       "sim3_axes, got 'affine'"))
      << bad_value.output;
  const Result no_model = RunCli(base + " --alignment se3");
  EXPECT_NE(no_model.exit_code, 0);
  EXPECT_TRUE(Contains(no_model.output, "needs --alignment_model_path"))
      << no_model.output;
  const Result no_poses =
      RunCli(base + " --alignment se3 --alignment_model_path " + Quote(dir) +
             " --ground_truth_poses_path " + Quote(JoinPaths(dir, "gt.txt")));
  EXPECT_NE(no_poses.exit_code, 0);
  EXPECT_TRUE(Contains(no_poses.output,
                       "--ground_truth_poses_path '" +
                           JoinPaths(dir, "gt.txt") + "' does not exist"))
      << no_poses.output;
}

TEST(Cli, LibraryErrorBecomesErrorMessage) {
  // The KITTI sample read as a rig recording: the importer throws, main()
  // prints "ERROR: ..." and exits with 1.
  const std::string workspace = JoinPaths(testing::CreateTestDir(), "ws");
  const Result result =
      RunCli("lidar_importer --dataset_path " +
             Quote(testing::KittiSampleDir()) + " --workspace_path " +
             Quote(workspace) + " --LidarImport.input_format rig");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_TRUE(Contains(result.output, "ERROR: ")) << result.output;
  EXPECT_FALSE(ExistsFile(JoinPaths(workspace, "lidar_importer.ini")));
}

TEST(Cli, ImportsKittiSampleAndWritesReloadableIni) {
  const std::string workspace = JoinPaths(testing::CreateTestDir(), "ws");
  const Result result = RunCli(
      "lidar_importer --dataset_path " + Quote(testing::KittiSampleDir()) +
      " --workspace_path " + Quote(workspace) +
      " --LidarImport.copy_scans 0");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(ExistsFile(JoinPaths(workspace, "database.db")));
  const std::string ini = JoinPaths(workspace, "lidar_importer.ini");
  ASSERT_TRUE(ExistsFile(ini));
  const std::string text = ReadTextFile(ini);
  EXPECT_TRUE(Contains(text, "workspace_path=" + workspace + "\n")) << text;
  EXPECT_TRUE(Contains(text, "copy_scans=false\n")) << text;

  // The written INI reproduces the run's options.
  const Result reloaded =
      RunCli("lidar_importer --check_options --project_path " + Quote(ini));
  EXPECT_EQ(reloaded.exit_code, 0) << reloaded.output;
  EXPECT_TRUE(Contains(reloaded.output, "copy_scans=false\n"))
      << reloaded.output;
}

// Every preset in configs/ belongs to a command, parses with it, and lists
// exactly that command's options.
TEST(Cli, EveryPresetParsesAndIsComplete) {
  const std::string configs = JoinPaths(testing::SourceDir(), "configs");
  int num_presets = 0;
  for (const auto& entry : std::filesystem::directory_iterator(configs)) {
    if (entry.path().extension() != ".ini") {
      continue;
    }
    ++num_presets;
    const std::string command = entry.path().stem().string();
    const std::string preset = entry.path().string();
    const Result parsed = RunCli(command + " --check_options --project_path " +
                                 Quote(preset));
    EXPECT_EQ(parsed.exit_code, 0) << preset << "\n" << parsed.output;

    const Result defaults = RunCli(command + " --check_options");
    if (defaults.exit_code != 0) {
      ADD_FAILURE() << preset << " names no command:\n" << defaults.output;
      continue;
    }
    EXPECT_EQ(IniKeys(ReadTextFile(preset)), IniKeys(defaults.output))
        << preset << " does not list the options of `" << command << "`";
    // The preset holds the defaults.
    EXPECT_EQ(parsed.output, defaults.output) << preset;
  }
  EXPECT_GE(num_presets, 1);
}

// Every command with options of its own has its preset in configs/.
TEST(Cli, EveryCommandHasPreset) {
  const Result help = RunCli("help");
  ASSERT_EQ(help.exit_code, 0);
  for (const auto& [command, description] : ListedCommands(help.output)) {
    if (command == "help" || command == "version") {
      continue;
    }
    EXPECT_TRUE(ExistsFile(JoinPaths(testing::SourceDir(),
                                     "configs/" + command + ".ini")))
        << "configs/" << command << ".ini is missing; `colmap-lidar "
        << command << " --check_options` prints its options";
  }
}

}  // namespace
}  // namespace colmap_lidar
