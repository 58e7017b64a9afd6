// Runs the real build/colmap-lidar executable: command dispatch, help,
// option errors and the INI presets of configs/.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

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

// An INI option: its value and the comment lines above it (the help text
// `--check_options` writes), joined by spaces.
struct IniEntry {
  std::string value;
  std::string comment;
};

// The "Section.name" options of an INI text; blanks skipped.
std::map<std::string, IniEntry> IniEntries(const std::string& text) {
  std::map<std::string, IniEntry> entries;
  std::string section;
  std::string comment;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    line = StringTrim(line);
    if (line.empty()) {
      continue;
    }
    if (line[0] == '#') {
      comment += (comment.empty() ? "" : " ") + StringTrim(line.substr(1));
      continue;
    }
    if (line.front() == '[' && line.back() == ']') {
      section = line.substr(1, line.size() - 2);
      comment.clear();
      continue;
    }
    const size_t equals = line.find('=');
    const std::string key = StringTrim(line.substr(0, equals));
    IniEntry& entry = entries[section.empty() ? key : section + "." + key];
    entry.value =
        equals == std::string::npos ? "" : StringTrim(line.substr(equals + 1));
    entry.comment = comment;
    comment.clear();
  }
  return entries;
}

// The "Section.name" keys of an INI text, comments and blanks skipped.
std::set<std::string> IniKeys(const std::string& text) {
  std::set<std::string> keys;
  for (const auto& [key, entry] : IniEntries(text)) {
    keys.insert(key);
  }
  return keys;
}

// The command a preset is for, from the first line that `--check_options`
// writes: "# colmap-lidar <command> options; load with --project_path."
std::string PresetCommand(const std::string& text) {
  const std::string prefix = "# colmap-lidar ";
  const std::string first_line = text.substr(0, text.find('\n'));
  if (!StringStartsWith(first_line, prefix)) {
    return "";
  }
  const std::string rest = first_line.substr(prefix.size());
  return rest.substr(0, rest.find_first_of(" :"));
}

std::string Lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return text;
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

// Every preset in configs/ belongs to a command (its first line names it),
// parses with it and lists exactly that command's options. A preset named
// after its command holds the defaults; any other (paper.ini) changes some.
TEST(Cli, EveryPresetParsesAndIsComplete) {
  const std::string configs = JoinPaths(testing::SourceDir(), "configs");
  int num_presets = 0;
  for (const auto& entry : std::filesystem::directory_iterator(configs)) {
    if (entry.path().extension() != ".ini") {
      continue;
    }
    ++num_presets;
    const std::string preset = entry.path().string();
    const std::string text = ReadTextFile(preset);
    const std::string command = PresetCommand(text);
    if (command.empty()) {
      ADD_FAILURE() << preset << " does not start with \"# colmap-lidar "
                    << "<command> options\"";
      continue;
    }
    const Result parsed = RunCli(command + " --check_options --project_path " +
                                 Quote(preset));
    EXPECT_EQ(parsed.exit_code, 0) << preset << "\n" << parsed.output;

    const Result defaults = RunCli(command + " --check_options");
    if (defaults.exit_code != 0) {
      ADD_FAILURE() << preset << " names no command:\n" << defaults.output;
      continue;
    }
    EXPECT_EQ(IniKeys(text), IniKeys(defaults.output))
        << preset << " does not list the options of `" << command << "`";
    if (entry.path().stem().string() == command) {
      EXPECT_EQ(parsed.output, defaults.output) << preset;
    } else {
      EXPECT_NE(parsed.output, defaults.output) << preset;
    }
  }
  EXPECT_GE(num_presets, 2);
}

// configs/paper.ini is the method as published: it differs from the
// defaults only in options whose help says that they are not in the paper,
// and in every such switch the ablation turns (issue 21).
TEST(Cli, PaperPresetTurnsOffOnlyExtensions) {
  const std::string preset =
      JoinPaths(testing::SourceDir(), "configs/paper.ini");
  ASSERT_EQ(PresetCommand(ReadTextFile(preset)), "automatic_reconstructor");
  const Result paper =
      RunCli("automatic_reconstructor --check_options --project_path " +
             Quote(preset));
  ASSERT_EQ(paper.exit_code, 0) << paper.output;
  const Result defaults = RunCli("automatic_reconstructor --check_options");
  ASSERT_EQ(defaults.exit_code, 0) << defaults.output;

  const std::map<std::string, IniEntry> paper_entries =
      IniEntries(paper.output);
  const std::map<std::string, IniEntry> default_entries =
      IniEntries(defaults.output);
  std::set<std::string> changed;
  for (const auto& [key, entry] : default_entries) {
    const auto it = paper_entries.find(key);
    ASSERT_NE(it, paper_entries.end()) << key;
    if (it->second.value == entry.value) {
      continue;
    }
    changed.insert(key);
    EXPECT_TRUE(Contains(Lowercase(entry.comment), "not in the paper"))
        << key << "=" << it->second.value << " (default " << entry.value
        << ") is changed by paper.ini, but its help does not say that the "
        << "default is an extension: " << entry.comment;
  }
  for (const char* key :
       {"LidarMapper.init_method", "LineBundleAdjustment.lambda_lidar",
        "LineMatching.min_overlap", "LidarFusion.free_space_filter",
        "LidarPatchMatch.lidar_prior_weight", "DelaunayMeshing.validate_lines",
        "DelaunayMeshing.snap_to_creases"}) {
    EXPECT_EQ(changed.count(key), 1) << key << " is not turned off";
  }
  // The paper's own terms stay on.
  EXPECT_EQ(paper_entries.at("LineBundleAdjustment.lambda_L").value, "1");
  EXPECT_EQ(paper_entries.at("AutomaticReconstruction.mesh_with_lines").value,
            "true");
  EXPECT_EQ(paper_entries.at("LidarPatchMatch.init").value, "lidar");
}

// The paper preset runs the whole pipeline (synthesize to mesh) on a small
// scene, with the paper's SfM (the stock mapper's model, one round) and its
// PatchMatch (no LIDAR view in the geometric filter). The figures of the
// preset on the benchmark matrix: docs/benchmarks/ablation.md.
TEST(Cli, PaperPresetReconstructsASmallScene) {
  const std::string workspace = JoinPaths(testing::CreateTestDir(), "ws");
  const Result result =
      RunCli("automatic_reconstructor --project_path " +
             Quote(JoinPaths(testing::SourceDir(), "configs/paper.ini")) +
             " --workspace_path " + Quote(workspace) +
             " --AutomaticReconstruction.stages synthesize:mesh"
             " --AutomaticReconstruction.num_threads 2"
             " --AutomaticReconstruction.dense_image_step 2"
             " --AutomaticReconstruction.fusion_min_num_pixels 3"
             " --AutomaticReconstruction.dense_max_image_size 320"
             " --LidarFusion.voxel_size_m 0.1"
             " --Synthesis.num_frames 16 --Synthesis.path_fraction 0.16"
             " --Synthesis.supersampling 1 --Synthesis.lidar_columns 512"
             " --Synthesis.survey_num_stations 0"
             " --Synthesis.write_depth_maps false");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(ExistsDir(JoinPaths(workspace, "sparse/lidar_mapper/mapper/0")));
  EXPECT_TRUE(ExistsFile(JoinPaths(workspace, "sparse/refined/lines3D.bin")));
  EXPECT_TRUE(ExistsFile(JoinPaths(workspace, "dense/meshed-delaunay.ply")));
  const std::string stages =
      ReadTextFile(JoinPaths(workspace, "pipeline/stages.json"));
  EXPECT_TRUE(Contains(stages, "1 iterations")) << stages;
  EXPECT_TRUE(Contains(stages, "0.0 % images and LIDAR")) << stages;
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
