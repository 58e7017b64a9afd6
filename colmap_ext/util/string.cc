#include "colmap_ext/util/string.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

std::string StringTrim(const std::string& str) {
  const char* kWhite = " \t\r\n";
  const size_t begin = str.find_first_not_of(kWhite);
  if (begin == std::string::npos) {
    return "";
  }
  const size_t end = str.find_last_not_of(kWhite);
  return str.substr(begin, end - begin + 1);
}

std::vector<std::string> StringSplit(const std::string& str,
                                     const std::string& delimiters) {
  std::vector<std::string> fields;
  size_t begin = 0;
  while (true) {
    const size_t end = str.find_first_of(delimiters, begin);
    if (end == std::string::npos) {
      fields.push_back(str.substr(begin));
      return fields;
    }
    fields.push_back(str.substr(begin, end - begin));
    begin = end + 1;
  }
}

bool StringStartsWith(const std::string& str, const std::string& prefix) {
  return str.size() >= prefix.size() &&
         str.compare(0, prefix.size(), prefix) == 0;
}

bool StringEndsWith(const std::string& str, const std::string& suffix) {
  return str.size() >= suffix.size() &&
         str.compare(str.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string StringToLower(std::string str) {
  std::transform(str.begin(), str.end(), str.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return str;
}

std::string StringToUpper(std::string str) {
  std::transform(str.begin(), str.end(), str.begin(),
                 [](unsigned char c) { return std::toupper(c); });
  return str;
}

double ParseDouble(const std::string& str, const std::string& what) {
  const std::string trimmed = StringTrim(str);
  THROW_CHECK(!trimmed.empty(), what << ": expected a number, got ''");
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(trimmed.c_str(), &end);
  THROW_CHECK(end == trimmed.c_str() + trimmed.size() && errno != ERANGE,
              what << ": expected a number, got '" << str << "'");
  return value;
}

long long ParseInt(const std::string& str, const std::string& what) {
  const std::string trimmed = StringTrim(str);
  THROW_CHECK(!trimmed.empty(), what << ": expected an integer, got ''");
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(trimmed.c_str(), &end, 10);
  THROW_CHECK(end == trimmed.c_str() + trimmed.size() && errno != ERANGE,
              what << ": expected an integer, got '" << str << "'");
  return value;
}

}  // namespace colmap_lidar
