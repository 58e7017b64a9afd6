#include "src/exe/option_manager.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

// A typical options struct with a range check, as the algorithms have.
struct TestOptions {
  bool flag = true;
  int count = 3;
  double ratio = 0.25;
  std::string mode = "auto";
  std::vector<double> weights = {1.0, 0.5};
  std::vector<std::string> names = {"a", "b"};

  bool Check() const {
    if (count < 0) {
      LOG(ERROR) << "Test.count must be >= 0, got " << count;
      return false;
    }
    return true;
  }
};

// The manager of a small command: two plain paths and one section.
struct Fixture {
  std::string input_path;
  std::string output_path = "out";
  TestOptions test;
  OptionManager options;

  Fixture() {
    options.AddRequiredOption("input_path", &input_path, "Input folder.");
    options.AddOption("output_path", &output_path, "Output folder.");
    options.AddOption("Test.flag", &test.flag, "A switch.");
    options.AddOption("Test.count", &test.count, "A count, >= 0.");
    options.AddOption("Test.ratio", &test.ratio, "A ratio in [0, 1].");
    options.AddOption("Test.mode", &test.mode, "auto | fast.");
    options.AddOption("Test.weights", &test.weights, "Weights, unitless.");
    options.AddOption("Test.names", &test.names, "Names.");
    options.AddCheck([this] { return test.Check(); });
  }

  bool Parse(std::vector<std::string> args) {
    args.insert(args.begin(), "test_command");
    return options.Parse(args);
  }
};

std::string WriteIniFile(const std::string& content) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "preset.ini");
  std::ofstream(path) << content;
  return path;
}

TEST(OptionManager, DefaultsStayWhenNotGiven) {
  Fixture f;
  ASSERT_TRUE(f.Parse({"--input_path", "in"}));
  EXPECT_EQ(f.options.ExitCode(), EXIT_SUCCESS);
  EXPECT_EQ(f.input_path, "in");
  EXPECT_EQ(f.output_path, "out");
  EXPECT_TRUE(f.test.flag);
  EXPECT_EQ(f.test.count, 3);
  EXPECT_EQ(f.test.ratio, 0.25);
  EXPECT_EQ(f.test.mode, "auto");
  EXPECT_EQ(f.test.weights, (std::vector<double>{1.0, 0.5}));
  EXPECT_EQ(f.test.names, (std::vector<std::string>{"a", "b"}));
}

TEST(OptionManager, CommandLineOverridesAllTypes) {
  Fixture f;
  ASSERT_TRUE(f.Parse({"--input_path", "in", "--output_path=o2",
                       "--Test.flag", "false", "--Test.count", "7",
                       "--Test.ratio", "-0.5", "--Test.mode", "fast",
                       "--Test.weights", "2, 3.5,-1", "--Test.names", ""}));
  EXPECT_EQ(f.output_path, "o2");
  EXPECT_FALSE(f.test.flag);
  EXPECT_EQ(f.test.count, 7);
  EXPECT_EQ(f.test.ratio, -0.5);  // A negative value is not an option.
  EXPECT_EQ(f.test.mode, "fast");
  EXPECT_EQ(f.test.weights, (std::vector<double>{2.0, 3.5, -1.0}));
  EXPECT_TRUE(f.test.names.empty());
}

TEST(OptionManager, BooleansAcceptZeroOneTrueFalse) {
  for (const auto& [text, expected] :
       std::vector<std::pair<std::string, bool>>{
           {"0", false}, {"1", true}, {"true", true}, {"FALSE", false}}) {
    Fixture f;
    f.test.flag = !expected;
    ASSERT_TRUE(f.Parse({"--input_path", "in", "--Test.flag", text}))
        << text;
    EXPECT_EQ(f.test.flag, expected) << text;
  }
  Fixture f;
  EXPECT_FALSE(f.Parse({"--input_path", "in", "--Test.flag", "yes2"}));
  EXPECT_EQ(f.options.ExitCode(), EXIT_FAILURE);
}

TEST(OptionManager, IniPresetLoads) {
  const std::string ini = WriteIniFile(
      "# A comment.\n"
      "input_path = /data/rec\n"
      "\n"
      "[Test]\n"
      "count=11\n"
      "ratio = 0.75\n"
      "weights = 4,5\n"
      "mode =\n");
  Fixture f;
  ASSERT_TRUE(f.Parse({"--project_path", ini}));
  EXPECT_EQ(f.options.project_path(), ini);
  EXPECT_EQ(f.input_path, "/data/rec");
  EXPECT_EQ(f.test.count, 11);
  EXPECT_EQ(f.test.ratio, 0.75);
  EXPECT_EQ(f.test.weights, (std::vector<double>{4.0, 5.0}));
  EXPECT_EQ(f.test.mode, "");
  EXPECT_TRUE(f.test.flag);  // Not in the preset: default.
}

TEST(OptionManager, CommandLineOverridesIni) {
  const std::string ini =
      WriteIniFile("input_path=/from/ini\n[Test]\ncount=11\nratio=0.75\n");
  // The preset may come before or after the overriding options.
  for (const bool preset_first : {true, false}) {
    Fixture f;
    std::vector<std::string> args = {"--Test.count", "2"};
    args.insert(preset_first ? args.begin() : args.end(),
                {"--project_path", ini});
    ASSERT_TRUE(f.Parse(args));
    EXPECT_EQ(f.test.count, 2);
    EXPECT_EQ(f.test.ratio, 0.75);
    EXPECT_EQ(f.input_path, "/from/ini");
  }
}

// Runs Parse with stderr captured; returns the error output.
std::string ParseCapturingStderr(Fixture* f,
                                 const std::vector<std::string>& args,
                                 bool* result) {
  ::testing::internal::CaptureStderr();
  *result = f->Parse(args);
  return ::testing::internal::GetCapturedStderr();
}

TEST(OptionManager, UnknownOptionFailsNamingIt) {
  Fixture f;
  bool result = true;
  const std::string error = ParseCapturingStderr(
      &f, {"--input_path", "in", "--Test.cuont", "2"}, &result);
  EXPECT_FALSE(result);
  EXPECT_EQ(f.options.ExitCode(), EXIT_FAILURE);
  EXPECT_NE(error.find("Test.cuont"), std::string::npos) << error;
}

// Boost's messages replace %placeholders% until none is left, so one in the
// user's text never returned (found by tests/fuzz/fuzz_options, through an
// option name, a bool switch given a value and a preset's ';' line): each of
// these must fail, naming what was wrong, and return.
TEST(OptionManager, PlaceholdersInNamesFailAndReturn) {
  for (const std::string name :
       {"--x%canonical_option%", "--%original_token%=1", "--Test.%prefix%",
        "--check_options=%original_token%", "-%option%"}) {
    Fixture f;
    bool result = true;
    const std::string error =
        ParseCapturingStderr(&f, {"--input_path", "in", name}, &result);
    EXPECT_FALSE(result) << name;
    EXPECT_EQ(f.options.ExitCode(), EXIT_FAILURE);
    EXPECT_NE(error.find(name.substr(0, name.find('='))), std::string::npos)
        << error;
  }
  for (const std::string ini :
       {"input_path=in\nx%canonical_option%=1\n", ";%invalid_line%\n",
        "%invalid_line%\n", "[x%canonical_option%]\ncount=1\n"}) {
    Fixture f;
    bool result = true;
    const std::string error = ParseCapturingStderr(
        &f, {"--project_path", WriteIniFile(ini)}, &result);
    EXPECT_FALSE(result) << ini;
    EXPECT_NE(error.find("preset"), std::string::npos) << error;
    EXPECT_NE(error.find('%'), std::string::npos) << error;
  }
}

// A '%' in a value is the user's text, kept as given (the stand-in that hides
// it from Boost never shows); the stand-in itself is refused.
TEST(OptionManager, PercentInValuesIsKept) {
  Fixture f;
  EXPECT_TRUE(f.Parse({"--input_path", "in%20dir", "--Test.names",
                       "%option%,b%"}));
  EXPECT_EQ(f.input_path, "in%20dir");
  EXPECT_EQ(f.test.names, (std::vector<std::string>{"%option%", "b%"}));
  Fixture g;
  EXPECT_TRUE(g.Parse({"--project_path",
                       WriteIniFile("input_path=%value%\n[Test]\nmode=%\n")}));
  EXPECT_EQ(g.input_path, "%value%");
  EXPECT_EQ(g.test.mode, "%");
  Fixture h;
  EXPECT_FALSE(h.Parse({"--input_path", "in\x1f"}));
  EXPECT_EQ(h.options.ExitCode(), EXIT_FAILURE);
}

TEST(OptionManager, AbbreviatedOptionIsUnknown) {
  Fixture f;
  EXPECT_FALSE(f.Parse({"--input_path", "in", "--Test.cou", "2"}));
  EXPECT_EQ(f.test.count, 3);
}

TEST(OptionManager, UnknownIniKeyFailsNamingIt) {
  const std::string ini = WriteIniFile("[Test]\ncount=1\nbogus_key=2\n");
  Fixture f;
  bool result = true;
  const std::string error = ParseCapturingStderr(
      &f, {"--input_path", "in", "--project_path", ini}, &result);
  EXPECT_FALSE(result);
  EXPECT_NE(error.find("Test.bogus_key"), std::string::npos) << error;
  EXPECT_NE(error.find(ini), std::string::npos) << error;
}

TEST(OptionManager, MissingIniFails) {
  Fixture f;
  EXPECT_FALSE(f.Parse({"--input_path", "in", "--project_path",
                        "/nonexistent/preset.ini"}));
  EXPECT_EQ(f.options.ExitCode(), EXIT_FAILURE);
  // A folder opens as a stream on Linux but is no preset.
  Fixture g;
  EXPECT_FALSE(g.Parse({"--input_path", "in", "--project_path",
                        testing::CreateTestDir()}));
}

TEST(OptionManager, BadNumberFailsNamingIt) {
  for (const std::vector<std::string>& bad :
       std::vector<std::vector<std::string>>{{"--Test.count", "abc"},
                                             {"--Test.count", "2.5"},
                                             {"--Test.count", "99999999999"},
                                             {"--Test.ratio", "0.5x"},
                                             {"--Test.ratio", "nan"},
                                             {"--Test.weights", "1,,2"}}) {
    Fixture f;
    std::vector<std::string> args = {"--input_path", "in"};
    args.insert(args.end(), bad.begin(), bad.end());
    bool result = true;
    const std::string error = ParseCapturingStderr(&f, args, &result);
    EXPECT_FALSE(result) << bad[1];
    EXPECT_NE(error.find(bad[0]), std::string::npos) << error;
    EXPECT_NE(error.find(bad[1]), std::string::npos) << error;
  }
}

TEST(OptionManager, BadNumberInIniFailsNamingFile) {
  const std::string ini = WriteIniFile("[Test]\nratio=high\n");
  Fixture f;
  bool result = true;
  const std::string error = ParseCapturingStderr(
      &f, {"--input_path", "in", "--project_path", ini}, &result);
  EXPECT_FALSE(result);
  EXPECT_NE(error.find("--Test.ratio"), std::string::npos) << error;
  EXPECT_NE(error.find(ini), std::string::npos) << error;
}

TEST(OptionManager, CheckFailureFails) {
  Fixture f;
  bool result = true;
  const std::string error = ParseCapturingStderr(
      &f, {"--input_path", "in", "--Test.count", "-1"}, &result);
  EXPECT_FALSE(result);
  EXPECT_EQ(f.options.ExitCode(), EXIT_FAILURE);
  // The struct's Check() logged the option by name.
  EXPECT_NE(error.find("Test.count must be >= 0"), std::string::npos)
      << error;
}

TEST(OptionManager, MissingRequiredOptionFails) {
  Fixture f;
  bool result = true;
  const std::string error = ParseCapturingStderr(&f, {}, &result);
  EXPECT_FALSE(result);
  EXPECT_NE(error.find("--input_path"), std::string::npos) << error;
  // An empty value does not satisfy a required option either.
  Fixture g;
  EXPECT_FALSE(g.Parse({"--input_path", ""}));
}

TEST(OptionManager, PositionalArgumentFails) {
  Fixture f;
  bool result = true;
  const std::string error =
      ParseCapturingStderr(&f, {"--input_path", "in", "stray"}, &result);
  EXPECT_FALSE(result);
  EXPECT_NE(error.find("stray"), std::string::npos) << error;
}

TEST(OptionManager, RepeatedOptionFails) {
  Fixture f;
  EXPECT_FALSE(f.Parse({"--input_path", "in", "--Test.count", "1",
                        "--Test.count", "2"}));
}

TEST(OptionManager, HelpShowsDefaultsAndHelpBySection) {
  Fixture f;
  ::testing::internal::CaptureStdout();
  EXPECT_FALSE(f.Parse({"--Test.count", "not checked", "-h"}));
  const std::string help = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(f.options.ExitCode(), EXIT_SUCCESS);
  EXPECT_NE(help.find("Usage: colmap-lidar test_command"), std::string::npos);
  EXPECT_NE(help.find("--input_path <string>  (required)"), std::string::npos)
      << help;
  EXPECT_NE(help.find("--Test.count <int>  (default: 3)"), std::string::npos)
      << help;
  EXPECT_NE(help.find("A count, >= 0."), std::string::npos) << help;
  EXPECT_NE(help.find("--Test.ratio <double>  (default: 0.25)"),
            std::string::npos)
      << help;
  EXPECT_NE(help.find("--Test.flag <bool>  (default: true)"),
            std::string::npos)
      << help;
  EXPECT_NE(help.find("(default: 1,0.5)"), std::string::npos) << help;
  // Plain options come before the sections.
  EXPECT_LT(help.find("--output_path"), help.find("[Test] options:"));
  EXPECT_LT(help.find("[Test] options:"), help.find("--Test.flag"));
}

TEST(OptionManager, WriteRoundTripsThroughProjectPath) {
  Fixture f;
  ASSERT_TRUE(f.Parse({"--input_path", "/a b/in", "--Test.count", "9",
                       "--Test.ratio", "0.1", "--Test.flag", "0",
                       "--Test.weights", "0.3,7"}));
  const std::string ini = JoinPaths(testing::CreateTestDir(), "written.ini");
  f.options.Write(ini);
  const std::string text = ReadTextFile(ini);
  EXPECT_NE(text.find("input_path=/a b/in\n"), std::string::npos) << text;
  EXPECT_NE(text.find("[Test]\n"), std::string::npos) << text;
  EXPECT_NE(text.find("count=9\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# A count, >= 0. (default: 3)\n"), std::string::npos)
      << text;
  // Plain keys precede the first section, or they would belong to it.
  EXPECT_LT(text.find("output_path="), text.find("[Test]"));

  Fixture g;
  ASSERT_TRUE(g.Parse({"--project_path", ini}));
  EXPECT_EQ(g.input_path, "/a b/in");
  EXPECT_EQ(g.test.count, 9);
  EXPECT_EQ(g.test.ratio, 0.1);  // Exact: doubles are written round-trip.
  EXPECT_FALSE(g.test.flag);
  EXPECT_EQ(g.test.weights, (std::vector<double>{0.3, 7.0}));
  EXPECT_EQ(g.test.names, (std::vector<std::string>{"a", "b"}));
}

TEST(OptionManager, CheckOptionsPrintsIniWithoutRequiredPaths) {
  Fixture f;
  ::testing::internal::CaptureStdout();
  EXPECT_FALSE(f.Parse({"--check_options", "--Test.count", "5"}));
  const std::string text = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(f.options.ExitCode(), EXIT_SUCCESS);
  EXPECT_NE(text.find("count=5\n"), std::string::npos) << text;
  EXPECT_NE(text.find("input_path=\n"), std::string::npos) << text;

  // Checks still run in this mode.
  Fixture g;
  ::testing::internal::CaptureStdout();
  EXPECT_FALSE(g.Parse({"--check_options", "--Test.count", "-5"}));
  ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(g.options.ExitCode(), EXIT_FAILURE);
}

TEST(OptionManager, RegistrationErrorsThrow) {
  OptionManager options;
  int value = 0;
  options.AddOption("A.x", &value, "");
  EXPECT_THROW(options.AddOption("A.x", &value, ""), Error);
  EXPECT_THROW(options.AddOption("project_path", &value, ""), Error);
  EXPECT_THROW(options.AddOption("A.b.c", &value, ""), Error);
}

TEST(OptionValue, DoublesFormatShortestExact) {
  EXPECT_EQ(option_internal::FormatValue(0.1), "0.1");
  EXPECT_EQ(option_internal::FormatValue(100.0), "100");
  EXPECT_EQ(option_internal::FormatValue(1e-7), "1e-07");
  const double third = 1.0 / 3.0;
  double parsed = 0;
  option_internal::ParseValue(option_internal::FormatValue(third), "x",
                              &parsed);
  EXPECT_EQ(parsed, third);
}

}  // namespace
}  // namespace colmap_lidar
