// The colmap-lidar executable: `colmap-lidar <command> [--option value ...]`.
// main() dispatches argv[1] through the table of commands.h; one try/catch
// turns any exception into "ERROR: <message>" on stderr and exit code 1.
// Under mpirun / srun only the commands marked distributed run.
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include <glog/logging.h>

#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/process_group.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"

namespace colmap_lidar {
namespace {

void PrintCommands(std::ostream& stream) {
  stream << "colmap-lidar " << COLMAP_LIDAR_VERSION
         << " -- surface reconstruction from a camera and a LIDAR, "
            "extending COLMAP\n\n"
         << "Usage:\n"
         << "  colmap-lidar <command> [--option value ...]\n"
         << "  colmap-lidar <command> -h    (options of the command)\n\n"
         << "Commands:\n";
  size_t width = 0;
  for (const Command& command : Commands()) {
    width = std::max(width, std::string(command.name).size());
  }
  for (const Command& command : Commands()) {
    const std::string name = command.name;
    stream << "  " << name << std::string(width + 2 - name.size(), ' ')
           << command.description << "\n";
  }
}

}  // namespace

// `help` lists the commands; `help <command>` is `<command> -h`.
int RunHelp(int argc, char** argv) {
  if (argc >= 2) {
    const Command* command = FindCommand(argv[1]);
    THROW_CHECK(command != nullptr, "unknown command '" << argv[1] << "'");
    std::string name = command->name;
    std::string help_flag = "-h";
    char* help_argv[] = {name.data(), help_flag.data(), nullptr};
    return command->run(2, help_argv);
  }
  PrintCommands(std::cout);
  return EXIT_SUCCESS;
}

int RunVersion(int argc, char** argv) {
  ColmapRunnerOptions runner_options;
  OptionManager options;
  options.AddOption("colmap_binary", &runner_options.colmap_binary,
                    "Stock colmap binary whose version is printed; empty: "
                    "$COLMAP_BINARY, else `colmap` on PATH.");
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }

  std::cout << "colmap-lidar " << COLMAP_LIDAR_VERSION << std::endl;
  // A missing stock binary is reported, not fatal: `version` is what one
  // runs to diagnose an installation.
  try {
    runner_options.log_path = "/dev/null";
    const ColmapRunner runner(runner_options);
    std::cout << "colmap " << runner.Version() << " ("
              << runner.binary_path() << ")" << std::endl;
  } catch (const Error& error) {
    std::cout << "colmap: not found (" << error.what() << ")" << std::endl;
  }
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar

int main(int argc, char** argv) {
  FLAGS_logtostderr = 1;
  google::InitGoogleLogging(argv[0]);

  using colmap_lidar::Command;
  if (argc < 2) {
    return colmap_lidar::RunHelp(0, nullptr);
  }
  const std::string name = argv[1];
  if (name == "-h" || name == "--help") {
    return colmap_lidar::RunHelp(0, nullptr);
  }
  const Command* command = colmap_lidar::FindCommand(argv[1]);
  if (command == nullptr) {
    std::cerr << "ERROR: unknown command '" << name
              << "'; run 'colmap-lidar help' to list the commands."
              << std::endl;
    return EXIT_FAILURE;
  }

  try {
    // Started by mpirun / srun: only the per-image commands split their
    // work; any other would run N times on the same workspace.
    const colmap_lidar::ProcessGroup& group =
        colmap_lidar::ProcessGroup::World();
    if (group.Distributed() && !command->distributed) {
      if (group.IsRoot()) {
        std::cerr << "ERROR: " << name << " runs in one process, not on "
                  << group.Size()
                  << " MPI ranks; under mpirun or srun run line_extractor or "
                     "lidar_patch_match_stereo (docs/scale.md)."
                  << std::endl;
      }
      return EXIT_FAILURE;
    }
    return command->run(argc - 1, argv + 1);
  } catch (const colmap_lidar::Error& error) {
    std::cerr << "ERROR: " << error.what() << std::endl;
  } catch (const std::exception& error) {
    std::cerr << "ERROR: " << error.what() << std::endl;
  }
  return EXIT_FAILURE;
}
