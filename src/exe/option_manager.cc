#include "src/exe/option_manager.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include <boost/program_options.hpp>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace po = boost::program_options;

namespace colmap_lidar {
namespace {

// Built-in options present in every subcommand (see option_manager.h).
constexpr char kHelp[] = "help";
constexpr char kProjectPath[] = "project_path";
constexpr char kCheckOptions[] = "check_options";

bool IsBuiltin(const std::string& name) {
  return name == kHelp || name == kProjectPath || name == kCheckOptions;
}

// Boost.ProgramOptions builds an error message by replacing each
// %placeholder% with its text until none is left, so a name, token or preset
// line that itself holds a placeholder never terminates (found by tests/fuzz,
// through option names, bool switches given a value and ';' lines of a
// preset). Boost therefore never sees a '%' of the user's: each one is swapped
// for this control character before parsing and swapped back in the values and
// messages that come out. Input that holds the stand-in itself is refused.
constexpr char kPercentStandIn = '\x1f';

std::string HidePercent(std::string text) {
  std::replace(text.begin(), text.end(), '%', kPercentStandIn);
  return text;
}

std::string RestorePercent(std::string text) {
  std::replace(text.begin(), text.end(), kPercentStandIn, '%');
  return text;
}

// Word-wraps `text` to lines of at most `width` characters (longer words stay
// whole), each prefixed by `indent`.
std::string Wrap(const std::string& text, const std::string& indent,
                 size_t width) {
  std::ostringstream out;
  std::istringstream words(text);
  std::string word;
  std::string line;
  while (words >> word) {
    if (!line.empty() && indent.size() + line.size() + 1 + word.size() > width) {
      out << indent << line << "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) {
    out << indent << line << "\n";
  }
  return out.str();
}

std::string DisplayValue(const std::string& value) {
  return value.empty() ? "\"\"" : value;
}

// Splits a comma-separated list; the empty string is the empty list.
std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  if (StringTrim(text).empty()) {
    return items;
  }
  for (const std::string& item : StringSplit(text, ",")) {
    items.push_back(StringTrim(item));
  }
  return items;
}

}  // namespace

namespace option_internal {

void ParseValue(const std::string& text, const std::string& option,
                bool* value) {
  const std::string lower = StringToLower(StringTrim(text));
  if (lower == "1" || lower == "true") {
    *value = true;
  } else if (lower == "0" || lower == "false") {
    *value = false;
  } else {
    THROW_ERROR("--" << option << ": expected 0, 1, true or false, got '"
                     << text << "'");
  }
}

void ParseValue(const std::string& text, const std::string& option,
                int* value) {
  const long long parsed = ParseInt(text, "--" + option);
  THROW_CHECK(parsed >= std::numeric_limits<int>::min() &&
                  parsed <= std::numeric_limits<int>::max(),
              "--" << option << ": integer out of range, got '" << text
                   << "'");
  *value = static_cast<int>(parsed);
}

void ParseValue(const std::string& text, const std::string& option,
                double* value) {
  const double parsed = ParseDouble(text, "--" + option);
  THROW_CHECK(std::isfinite(parsed), "--" << option
                                          << ": expected a finite number, got '"
                                          << text << "'");
  *value = parsed;
}

void ParseValue(const std::string& text, const std::string& option,
                std::string* value) {
  *value = StringTrim(text);
}

// Parses each comma-separated item; errors quote the whole list.
template <typename T>
std::vector<T> ParseList(const std::string& text, const std::string& option) {
  std::vector<T> parsed;
  try {
    for (const std::string& item : SplitList(text)) {
      parsed.emplace_back();
      ParseValue(item, option, &parsed.back());
    }
  } catch (const Error& error) {
    THROW_ERROR(error.what() << " in the list '" << text << "'");
  }
  return parsed;
}

void ParseValue(const std::string& text, const std::string& option,
                std::vector<int>* value) {
  *value = ParseList<int>(text, option);
}

void ParseValue(const std::string& text, const std::string& option,
                std::vector<double>* value) {
  *value = ParseList<double>(text, option);
}

void ParseValue(const std::string& text, const std::string& option,
                std::vector<std::string>* value) {
  *value = SplitList(text);
}

std::string FormatValue(bool value) { return value ? "true" : "false"; }

std::string FormatValue(int value) { return std::to_string(value); }

std::string FormatValue(double value) {
  // std::to_chars without a format gives the shortest text that reads back
  // to exactly `value`, fixed or scientific, whichever is shorter.
  char buffer[64];
  const std::to_chars_result result =
      std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string FormatValue(const std::string& value) { return value; }

namespace {
template <typename T>
std::string FormatList(const std::vector<T>& values) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i) {
    text += (i == 0 ? "" : ",") + FormatValue(values[i]);
  }
  return text;
}
}  // namespace

std::string FormatValue(const std::vector<int>& value) {
  return FormatList(value);
}
std::string FormatValue(const std::vector<double>& value) {
  return FormatList(value);
}
std::string FormatValue(const std::vector<std::string>& value) {
  return FormatList(value);
}

const char* TypeName(const bool*) { return "bool"; }
const char* TypeName(const int*) { return "int"; }
const char* TypeName(const double*) { return "double"; }
const char* TypeName(const std::string*) { return "string"; }
const char* TypeName(const std::vector<int>*) { return "int,int,..."; }
const char* TypeName(const std::vector<double>*) {
  return "double,double,...";
}
const char* TypeName(const std::vector<std::string>*) {
  return "string,string,...";
}

}  // namespace option_internal

OptionManager::OptionManager() = default;

void OptionManager::AddCheck(std::function<bool()> check) {
  checks_.push_back(std::move(check));
}

void OptionManager::AddOptionImpl(Option option) {
  THROW_CHECK(!option.name.empty(), "Option name must not be empty");
  THROW_CHECK(!IsBuiltin(option.name),
              "Option name --" << option.name << " is reserved");
  THROW_CHECK(FindOption(option.name) == nullptr,
              "Option --" << option.name << " is registered twice");
  const std::vector<std::string> parts = StringSplit(option.name, ".");
  THROW_CHECK(parts.size() <= 2 && !parts.front().empty() &&
                  !parts.back().empty(),
              "Option name --" << option.name
                               << " must be 'name' or 'Section.name'");
  if (parts.size() == 2) {
    option.section = parts[0];
  }
  options_.push_back(std::move(option));
}

const OptionManager::Option* OptionManager::FindOption(
    const std::string& name) const {
  for (const Option& option : options_) {
    if (option.name == name) {
      return &option;
    }
  }
  return nullptr;
}

bool OptionManager::Fail(const std::string& message) {
  std::cerr << "ERROR: " << message << "\n"
            << "Run 'colmap-lidar " << command_name_
            << " -h' to list the options." << std::endl;
  exit_code_ = EXIT_FAILURE;
  return false;
}

bool OptionManager::Parse(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  argv.reserve(args.size());
  for (const std::string& arg : args) {
    argv.push_back(const_cast<char*>(arg.c_str()));
  }
  return Parse(static_cast<int>(argv.size()), argv.data());
}

bool OptionManager::Parse(int argc, char** argv) {
  exit_code_ = EXIT_FAILURE;
  if (argc >= 1) {
    command_name_ = argv[0];
  }

  // Help wins over everything else so that it works even next to a mistake.
  for (int i = 1; i < argc; ++i) {
    const std::string token = argv[i];
    if (token == "-h" || token == "--help") {
      std::cout << Help() << std::flush;
      exit_code_ = EXIT_SUCCESS;
      return false;
    }
  }

  // Joins "--name value" into "--name=value" for known options so that
  // values starting with '-' (negative numbers) are not mistaken for options
  // by Boost. An empty value, or the value of an unknown name, stays a
  // separate token (Boost then reports the unknown name as typed). Bare words
  // that no option consumes are errors.
  std::vector<std::string> tokens;
  for (int i = 1; i < argc; ++i) {
    const std::string token = argv[i];
    if (!StringStartsWith(token, "-")) {
      return Fail("unexpected argument '" + token +
                  "'; options are given as --name value");
    }
    if (token.find(kPercentStandIn) != std::string::npos) {
      return Fail("the argument '" + RestorePercent(token) +
                  "' holds a control character (0x1f)");
    }
    const bool takes_value = StringStartsWith(token, "--") &&
                             token.find('=') == std::string::npos &&
                             token.substr(2) != kCheckOptions;
    if (takes_value && i + 1 < argc &&
        !StringStartsWith(argv[i + 1], "--")) {
      const std::string name = token.substr(2);
      const std::string value = argv[++i];
      if (value.find(kPercentStandIn) != std::string::npos) {
        return Fail("the value '" + value + "' of " + token +
                    " holds a control character (0x1f)");
      }
      if (!value.empty() && (name == kProjectPath || FindOption(name))) {
        tokens.push_back(HidePercent(token + "=" + value));
      } else {
        tokens.push_back(HidePercent(token));
        tokens.push_back(HidePercent(value));
      }
    } else {
      tokens.push_back(HidePercent(token));
    }
  }

  po::options_description ini_description;
  for (const Option& option : options_) {
    ini_description.add_options()(option.name.c_str(),
                                  po::value<std::string>());
  }
  po::options_description cli_description;
  cli_description.add(ini_description);
  cli_description.add_options()(kProjectPath, po::value<std::string>())(
      kCheckOptions, po::bool_switch());

  // Name -> (text, where it came from); the command line overrides the preset.
  std::map<std::string, std::pair<std::string, std::string>> texts;
  bool check_only = false;
  try {
    po::variables_map cli_values;
    const int style = po::command_line_style::default_style &
                      ~po::command_line_style::allow_guessing;
    po::store(po::command_line_parser(tokens)
                  .options(cli_description)
                  .style(style)
                  .run(),
              cli_values);
    check_only = cli_values[kCheckOptions].as<bool>();

    if (cli_values.count(kProjectPath)) {
      project_path_ =
          RestorePercent(cli_values[kProjectPath].as<std::string>());
      std::ifstream file(project_path_);
      if (!ExistsFile(project_path_) || !file.is_open()) {
        return Fail("cannot read the preset --project_path " + project_path_);
      }
      std::ostringstream text;
      text << file.rdbuf();
      if (text.str().find(kPercentStandIn) != std::string::npos) {
        return Fail("the preset " + project_path_ +
                    " holds a control character (0x1f)");
      }
      std::istringstream hidden(HidePercent(text.str()));
      po::variables_map ini_values;
      try {
        po::store(po::parse_config_file(hidden, ini_description,
                                        /*allow_unregistered=*/false),
                  ini_values);
      } catch (const po::error& error) {
        return Fail("in preset " + project_path_ + ": " +
                    RestorePercent(error.what()));
      }
      for (const auto& [name, value] : ini_values) {
        texts[name] = {RestorePercent(value.as<std::string>()),
                       "preset " + project_path_};
      }
    }

    for (const auto& [name, value] : cli_values) {
      if (!IsBuiltin(name)) {
        texts[name] = {RestorePercent(value.as<std::string>()),
                       "command line"};
      }
    }
  } catch (const po::error& error) {
    return Fail(RestorePercent(error.what()));
  }

  for (const Option& option : options_) {
    const auto it = texts.find(option.name);
    if (it == texts.end()) {
      continue;
    }
    try {
      option.set(it->second.first);
    } catch (const Error& error) {
      return Fail(std::string(error.what()) + " (" + it->second.second + ")");
    }
  }

  if (!check_only) {
    for (const Option& option : options_) {
      const auto it = texts.find(option.name);
      if (option.required &&
          (it == texts.end() || StringTrim(it->second.first).empty())) {
        return Fail("the option --" + option.name + " is required");
      }
    }
  }

  bool checks_pass = true;
  for (const std::function<bool()>& check : checks_) {
    checks_pass = check() && checks_pass;
  }
  if (!checks_pass) {
    return Fail("invalid option values (the reasons are logged above)");
  }

  if (check_only) {
    WriteIni(std::cout);
    std::cout << std::flush;
    exit_code_ = EXIT_SUCCESS;
    return false;
  }

  exit_code_ = EXIT_SUCCESS;
  return true;
}

std::string OptionManager::Help() const {
  std::ostringstream out;
  out << "Usage: colmap-lidar " << command_name_
      << " [--project_path preset.ini] [--name value ...]\n\n"
      << Wrap("Options are given as --name value (or --name=value) on the "
              "command line, or as name=value in an INI preset, with "
              "Section.name written as name=value under [Section]. Values on "
              "the command line override the preset. Booleans accept 0, 1, "
              "true, false; lists are comma-separated.",
              "", 79)
      << "\nGeneral options:\n"
      << "  -h, --help\n"
      << Wrap("Print this help and exit.", "      ", 79)
      << "  --project_path <path>\n"
      << Wrap("INI preset loaded before the command-line options.", "      ",
              79)
      << "  --check_options\n"
      << Wrap("Check the options (with the preset, if any), print them as INI "
              "and exit without running; required options may be missing.",
              "      ", 79);

  std::vector<std::string> sections;
  for (const Option& option : options_) {
    bool known = false;
    for (const std::string& section : sections) {
      known = known || section == option.section;
    }
    if (!known) {
      sections.push_back(option.section);
    }
  }
  // Plain options belong with the general ones, printed first.
  std::stable_partition(sections.begin(), sections.end(),
                        [](const std::string& s) { return s.empty(); });

  for (const std::string& section : sections) {
    if (!section.empty()) {
      out << "\n[" << section << "] options:\n";
    }
    for (const Option& option : options_) {
      if (option.section != section) {
        continue;
      }
      out << "  --" << option.name << " <" << option.type_name << ">  ";
      if (option.required) {
        out << "(required)\n";
      } else {
        out << "(default: " << DisplayValue(option.default_value) << ")\n";
      }
      out << Wrap(option.help, "      ", 79);
    }
  }
  return out.str();
}

void OptionManager::WriteIni(std::ostream& stream) const {
  stream << "# colmap-lidar " << command_name_
         << " options; load with --project_path.\n";
  std::vector<std::string> sections = {""};
  for (const Option& option : options_) {
    bool known = false;
    for (const std::string& section : sections) {
      known = known || section == option.section;
    }
    if (!known) {
      sections.push_back(option.section);
    }
  }
  for (const std::string& section : sections) {
    if (!section.empty()) {
      stream << "\n[" << section << "]\n";
    }
    for (const Option& option : options_) {
      if (option.section != section) {
        continue;
      }
      const std::string suffix =
          option.required
              ? " (required)"
              : " (default: " + DisplayValue(option.default_value) + ")";
      stream << Wrap(option.help + suffix, "# ", 79);
      const std::string key = section.empty()
                                  ? option.name
                                  : option.name.substr(section.size() + 1);
      stream << key << "=" << option.get() << "\n";
    }
  }
}

void OptionManager::Write(const std::string& ini_path) const {
  WriteFileAtomically(
      ini_path, [this](std::ostream& stream) { WriteIni(stream); },
      /*binary=*/false);
}

}  // namespace colmap_lidar
