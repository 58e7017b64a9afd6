#include "colmap_ext/mvs/stereo_config.h"

#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

constexpr char kAuto[] = "__auto__";
constexpr char kAll[] = "__all__";

// Lines of a file, trimmed, with their 1-based line numbers; blank lines
// dropped (COLMAP's ReadTextFileLines).
std::vector<std::pair<int, std::string>> ReadNonBlankLines(
    const std::string& path, const std::string& what) {
  CheckFileExists(path, what);
  std::istringstream content(ReadTextFile(path));
  std::vector<std::pair<int, std::string>> lines;
  std::string line;
  int line_number = 0;
  while (std::getline(content, line)) {
    ++line_number;
    line = StringTrim(line);
    if (!line.empty()) {
      lines.emplace_back(line_number, line);
    }
  }
  return lines;
}

// COLMAP's CSVToVector: split on ',' and ';', trim, drop empty fields.
std::vector<std::string> SplitList(const std::string& line) {
  std::vector<std::string> fields;
  for (const std::string& field : StringSplit(line, ",;")) {
    const std::string trimmed = StringTrim(field);
    if (!trimmed.empty()) {
      fields.push_back(trimmed);
    }
  }
  return fields;
}

void CheckWritableName(const std::string& name, const std::string& path,
                       const std::string& forbidden) {
  THROW_CHECK(!name.empty() && StringTrim(name) == name &&
                  name.find_first_of("\r\n" + forbidden) == std::string::npos,
              "Image name '" << name << "' cannot be written to " << path);
}

}  // namespace

std::vector<PatchMatchEntry> ReadPatchMatchConfig(const std::string& path) {
  const auto lines = ReadNonBlankLines(path, "patch-match.cfg");
  std::vector<PatchMatchEntry> entries;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].second[0] == '#') {
      continue;
    }
    PatchMatchEntry entry;
    entry.ref_image_name = lines[i].second;
    THROW_CHECK(i + 1 < lines.size(),
                "Reference image '" << entry.ref_image_name << "' at line "
                                    << lines[i].first << " of " << path
                                    << " has no sources line");
    ++i;
    const int line_number = lines[i].first;
    const std::string& source_line = lines[i].second;
    // COLMAP would take a comment here as a list of image names.
    THROW_CHECK(source_line[0] != '#',
                "Comment at line " << line_number << " of " << path
                                   << " where the sources of '"
                                   << entry.ref_image_name
                                   << "' are expected");
    const std::vector<std::string> fields = SplitList(source_line);
    if (fields.size() == 1 && fields[0] == kAll) {
      entry.source_kind = PatchMatchEntry::SourceKind::kAll;
    } else if (fields.size() == 2 && fields[0] == kAuto) {
      entry.source_kind = PatchMatchEntry::SourceKind::kAuto;
      const long long count =
          ParseInt(fields[1], "__auto__ count at line " +
                                  std::to_string(line_number) + " of " + path);
      THROW_CHECK(count > 0 && count <= 1000000,
                  "__auto__ count must be > 0 at line " << line_number
                                                        << " of " << path);
      entry.num_auto_src_images = static_cast<int>(count);
    } else {
      entry.source_kind = PatchMatchEntry::SourceKind::kList;
      entry.src_image_names = fields;
      if (fields.empty()) {
        LOG(WARNING) << "Ignoring reference image '" << entry.ref_image_name
                     << "' without source images in " << path;
        continue;
      }
    }
    entries.push_back(std::move(entry));
  }
  return entries;
}

void WritePatchMatchConfig(const std::string& path,
                           const std::vector<PatchMatchEntry>& entries) {
  std::ostringstream content;
  for (const PatchMatchEntry& entry : entries) {
    CheckWritableName(entry.ref_image_name, path, "");
    THROW_CHECK(entry.ref_image_name[0] != '#',
                "Image name '" << entry.ref_image_name
                               << "' would read as a comment in " << path);
    content << entry.ref_image_name << "\n";
    switch (entry.source_kind) {
      case PatchMatchEntry::SourceKind::kAuto:
        THROW_CHECK(entry.num_auto_src_images > 0,
                    "__auto__ count must be > 0 for '"
                        << entry.ref_image_name << "' writing " << path);
        content << kAuto << ", " << entry.num_auto_src_images << "\n";
        break;
      case PatchMatchEntry::SourceKind::kAll:
        content << kAll << "\n";
        break;
      case PatchMatchEntry::SourceKind::kList:
        THROW_CHECK(!entry.src_image_names.empty(),
                    "Empty source list for '" << entry.ref_image_name
                                              << "' writing " << path);
        for (size_t i = 0; i < entry.src_image_names.size(); ++i) {
          CheckWritableName(entry.src_image_names[i], path, ",;");
          content << (i > 0 ? ", " : "") << entry.src_image_names[i];
        }
        content << "\n";
        break;
    }
  }
  WriteFileAtomically(
      path, [&](std::ostream& stream) { stream << content.str(); },
      /*binary=*/false);
}

std::vector<std::string> ReadFusionConfig(const std::string& path) {
  std::vector<std::string> names;
  for (const auto& line : ReadNonBlankLines(path, "fusion.cfg")) {
    names.push_back(line.second);
  }
  return names;
}

void WriteFusionConfig(const std::string& path,
                       const std::vector<std::string>& image_names) {
  std::ostringstream content;
  for (const std::string& name : image_names) {
    CheckWritableName(name, path, "");
    content << name << "\n";
  }
  WriteFileAtomically(
      path, [&](std::ostream& stream) { stream << content.str(); },
      /*binary=*/false);
}

}  // namespace colmap_lidar
