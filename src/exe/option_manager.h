// Command-line and INI options of one colmap-lidar subcommand, in the manner
// of COLMAP's OptionManager: every field of an options struct is registered as
// "Section.name" (e.g. LidarImport.copy_images) so that the same key works as
// `--LidarImport.copy_images 1` on the command line and as `copy_images=1`
// under `[LidarImport]` in an INI preset. Plain options without a section
// (`--dataset_path`) sit at the top of the INI file.
//
// Every subcommand gets three built-in options:
//   -h / --help        prints all options, grouped by section, with their
//                      default and help text, and exits with code 0;
//   --project_path F   loads the INI preset F first; values given on the
//                      command line override the preset;
//   --check_options    parses and checks the options (including the preset),
//                      prints the effective configuration as INI on stdout
//                      and exits with code 0 without running the command.
//                      Required options may stay empty in this mode, so a
//                      preset without paths can be validated.
//
// Values are parsed by this class, not by Boost, so that every error names the
// option: booleans accept 0/1/true/false, numbers must be whole and finite,
// lists are comma-separated ("1.5,2,3"). Unknown keys are errors both on the
// command line and in a preset, so a stale preset cannot be silently ignored.
// Boost.ProgramOptions splits the command line and reads the INI syntax.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace colmap_lidar {

class OptionManager {
 public:
  OptionManager();

  // Registers an option with its default taken from *value now (shown by -h).
  // `value` must outlive Parse(). `help` should state unit and allowed range.
  // Supported T: bool, int, double, std::string, std::vector<int>,
  // std::vector<double>, std::vector<std::string>.
  template <typename T>
  void AddOption(const std::string& name, T* value, const std::string& help);

  // Like AddOption, but Parse() fails unless the option is given a non-empty
  // value on the command line or in the preset.
  template <typename T>
  void AddRequiredOption(const std::string& name, T* value,
                         const std::string& help);

  // Adds a validation run after all values are set, typically
  // `[&opts] { return opts.Check(); }`. A check that fails must LOG(ERROR)
  // the offending option; all checks run, so every problem is reported.
  void AddCheck(std::function<bool()> check);

  // Parses argv[1..argc-1]; argv[0] is the subcommand name used in messages.
  // Returns true when the command should run. Returns false after printing
  // help or the configuration (ExitCode() == EXIT_SUCCESS) or after printing
  // an error that names the option (ExitCode() == EXIT_FAILURE). Usage:
  //   if (!options.Parse(argc, argv)) return options.ExitCode();
  bool Parse(int argc, char** argv);
  // Same with the arguments as strings (the subcommand name first).
  bool Parse(const std::vector<std::string>& args);
  int ExitCode() const { return exit_code_; }

  // The preset given with --project_path, empty when none.
  const std::string& project_path() const { return project_path_; }

  // The help text printed by -h.
  std::string Help() const;

  // Writes the current values as INI: plain options first, then one
  // [Section] per section, each key preceded by its help as a comment. The
  // output reads back with --project_path. Write() replaces the file
  // atomically; throws colmap_lidar::Error naming the path on failure.
  void Write(const std::string& ini_path) const;
  void WriteIni(std::ostream& stream) const;

 private:
  struct Option {
    std::string name;     // Full key: "Section.name" or "name".
    std::string section;  // "Section", or empty for plain options.
    std::string help;
    std::string type_name;      // Shown by -h, e.g. "int".
    std::string default_value;  // Formatted value at registration.
    bool required = false;
    // Parses text into the bound variable; throws colmap_lidar::Error with a
    // message that names the option.
    std::function<void(const std::string&)> set;
    // Formats the bound variable's current value.
    std::function<std::string()> get;
  };

  template <typename T>
  void Register(const std::string& name, T* value, const std::string& help,
                bool required);
  void AddOptionImpl(Option option);
  const Option* FindOption(const std::string& name) const;
  bool Fail(const std::string& message);

  std::string command_name_ = "command";
  std::string project_path_;
  std::vector<Option> options_;
  std::vector<std::function<bool()>> checks_;
  int exit_code_ = 0;
};

// Typed conversions used by AddOption; each throws colmap_lidar::Error whose
// message names `option` and shows the offending text.
namespace option_internal {

void ParseValue(const std::string& text, const std::string& option,
                bool* value);
void ParseValue(const std::string& text, const std::string& option,
                int* value);
void ParseValue(const std::string& text, const std::string& option,
                double* value);
void ParseValue(const std::string& text, const std::string& option,
                std::string* value);
void ParseValue(const std::string& text, const std::string& option,
                std::vector<int>* value);
void ParseValue(const std::string& text, const std::string& option,
                std::vector<double>* value);
void ParseValue(const std::string& text, const std::string& option,
                std::vector<std::string>* value);

std::string FormatValue(bool value);
std::string FormatValue(int value);
// Shortest text that reads back to exactly the same double ("0.1", "1e-07").
std::string FormatValue(double value);
std::string FormatValue(const std::string& value);
std::string FormatValue(const std::vector<int>& value);
std::string FormatValue(const std::vector<double>& value);
std::string FormatValue(const std::vector<std::string>& value);

const char* TypeName(const bool*);
const char* TypeName(const int*);
const char* TypeName(const double*);
const char* TypeName(const std::string*);
const char* TypeName(const std::vector<int>*);
const char* TypeName(const std::vector<double>*);
const char* TypeName(const std::vector<std::string>*);

}  // namespace option_internal

template <typename T>
void OptionManager::AddOption(const std::string& name, T* value,
                              const std::string& help) {
  Register(name, value, help, /*required=*/false);
}

template <typename T>
void OptionManager::AddRequiredOption(const std::string& name, T* value,
                                      const std::string& help) {
  Register(name, value, help, /*required=*/true);
}

template <typename T>
void OptionManager::Register(const std::string& name, T* value,
                             const std::string& help, bool required) {
  Option option;
  option.name = name;
  option.help = help;
  option.type_name = option_internal::TypeName(value);
  option.default_value = option_internal::FormatValue(*value);
  option.required = required;
  option.set = [name, value](const std::string& text) {
    option_internal::ParseValue(text, name, value);
  };
  option.get = [value]() { return option_internal::FormatValue(*value); };
  AddOptionImpl(std::move(option));
}

}  // namespace colmap_lidar
