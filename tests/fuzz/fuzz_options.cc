// The option manager: an INI preset and a command line. The input is the
// preset, a line "%%", then one argument per line; a non-empty preset is
// passed with --project_path first. The options cover every supported type
// (the subcommands register the same kinds through the same code).
#include <sstream>
#include <vector>

#include "tests/fuzz/fuzz_util.h"

#if __has_include("src/exe/option_manager.h")
#include "src/exe/option_manager.h"
#else
#include "colmap_ext/exe/option_manager.h"
#endif

using namespace colmap_lidar;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string preset;
  std::string command_line;
  fuzz::SplitInput(data, size, "\n%%\n", &preset, &command_line);

  std::vector<std::string> args = {"fuzz_command"};
  if (!preset.empty()) {
    args.push_back("--project_path");
    args.push_back(fuzz::WriteInput("preset.ini", preset));
  }
  std::istringstream lines(command_line);
  std::string line;
  while (std::getline(lines, line)) {
    args.push_back(line);
  }

  std::string workspace_path;
  bool flag = false;
  int count = 3;
  double scale = 0.5;
  std::string name = "default";
  std::vector<int> ints = {1, 2};
  std::vector<double> values = {0.25};
  std::vector<std::string> names = {"a", "b"};
  double threshold = 1.0;

  fuzz::ExpectNoCrash([&] {
    OptionManager options;
    options.AddRequiredOption("workspace_path", &workspace_path,
                              "workspace folder");
    options.AddOption("Section.flag", &flag, "a switch");
    options.AddOption("Section.count", &count, "an int");
    options.AddOption("Section.scale", &scale, "a double");
    options.AddOption("Section.name", &name, "a string");
    options.AddOption("Section.ints", &ints, "ints");
    options.AddOption("Section.values", &values, "doubles");
    options.AddOption("Section.names", &names, "strings");
    options.AddOption("Other.threshold", &threshold, "non-negative");
    options.AddCheck([&threshold] { return threshold >= 0; });
    if (options.Parse(args)) {
      std::ostringstream ini;
      options.WriteIni(ini);
      options.Help();
    }
  });
  return 0;
}
