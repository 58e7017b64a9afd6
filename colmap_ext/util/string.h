#pragma once

#include <string>
#include <vector>

namespace colmap_lidar {

// Removes leading and trailing white space (spaces, tabs, CR, LF).
std::string StringTrim(const std::string& str);

// Splits on any of the delimiter characters; empty fields are kept, so
// "a  b" split on " " gives {"a", "", "b"} (COLMAP's text formats rely on it).
std::vector<std::string> StringSplit(const std::string& str,
                                     const std::string& delimiters);

bool StringStartsWith(const std::string& str, const std::string& prefix);
bool StringEndsWith(const std::string& str, const std::string& suffix);
std::string StringToLower(std::string str);
std::string StringToUpper(std::string str);

// Parses a whole string as a number; throws colmap_lidar::Error naming
// `what` when the string is not a number or has trailing characters.
double ParseDouble(const std::string& str, const std::string& what);
long long ParseInt(const std::string& str, const std::string& what);

}  // namespace colmap_lidar
