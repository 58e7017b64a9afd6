// JSON reports and exports through nlohmann-json. `Json` keeps keys in the
// order they were set, which is the order our reports document. Files are
// indented by two spaces; doubles are written with the shortest text that
// reads back to the same value, non-finite doubles as null (JSON has no NaN
// or infinity).
//
//   Json json;
//   json["num_images"] = 12;
//   json["errors"] = errors;  // std::vector<double> -> array
//   WriteJsonFile(path, json);
#pragma once

#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace colmap_lidar {

using Json = nlohmann::ordered_json;

// Written atomically, with a final newline; throws colmap_lidar::Error
// naming the path when it cannot be written or a string is not UTF-8.
void WriteJsonFile(const std::string& path, const Json& json);

// Throws colmap_lidar::Error naming the path when the file cannot be read
// or is not JSON (with the parser's message and byte position).
Json ReadJsonFile(const std::string& path);

// A vector's coefficients as an array: [x, y, z].
template <typename Derived>
Json VectorToJson(const Eigen::MatrixBase<Derived>& vector) {
  Json array = Json::array();
  for (Eigen::Index i = 0; i < vector.size(); ++i) {
    array.push_back(static_cast<double>(vector(i)));
  }
  return array;
}

// A matrix as an array of its rows: [[r00, r01], [r10, r11]].
template <typename Derived>
Json MatrixRowsToJson(const Eigen::MatrixBase<Derived>& matrix) {
  Json rows = Json::array();
  for (Eigen::Index r = 0; r < matrix.rows(); ++r) {
    rows.push_back(VectorToJson(matrix.row(r).transpose()));
  }
  return rows;
}

}  // namespace colmap_lidar
