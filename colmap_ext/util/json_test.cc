#include "colmap_ext/util/json.h"

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

TEST(Json, WritesIndentedInInsertionOrder) {
  Json json;
  json["name"] = "a\"b\\c\n";
  json["count"] = 3;
  json["ok"] = true;
  json["nan"] = std::nan("");
  json["values"] = std::vector<double>{0.1, 1.0, 1e-20};
  json["items"] =
      Json::array({Json{{"x", 2.5}}, uint64_t{18446744073709551615u}});
  json["empty"] = Json::object();
  json["none"] = Json::array();
  const std::string path = JoinPaths(testing::CreateTestDir(), "a.json");
  WriteJsonFile(path, json);
  EXPECT_EQ(ReadTextFile(path),
            "{\n"
            "  \"name\": \"a\\\"b\\\\c\\n\",\n"
            "  \"count\": 3,\n"
            "  \"ok\": true,\n"
            "  \"nan\": null,\n"
            "  \"values\": [\n"
            "    0.1,\n"
            "    1.0,\n"
            "    1e-20\n"
            "  ],\n"
            "  \"items\": [\n"
            "    {\n"
            "      \"x\": 2.5\n"
            "    },\n"
            "    18446744073709551615\n"
            "  ],\n"
            "  \"empty\": {},\n"
            "  \"none\": []\n"
            "}\n");
}

TEST(Json, NumbersRoundTrip) {
  const std::vector<double> values = {
      0.1,     1.0 / 3.0, 123456.789,       -2e-300, 1e300,
      5e-324,  DBL_MAX,   0.30000000000000004, 1.0,  -0.0};
  Json json;
  json["values"] = values;
  json["max_uint64"] = std::numeric_limits<uint64_t>::max();
  json["min_int64"] = std::numeric_limits<int64_t>::min();
  const std::string path = JoinPaths(testing::CreateTestDir(), "n.json");
  WriteJsonFile(path, json);
  const Json read = ReadJsonFile(path);
  ASSERT_EQ(read.at("values").size(), values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    // A double stays a double, also when its value is integral.
    EXPECT_TRUE(read.at("values").at(i).is_number_float()) << i;
    EXPECT_EQ(read.at("values").at(i).get<double>(), values[i]) << i;
  }
  EXPECT_TRUE(std::signbit(read.at("values").at(9).get<double>()));
  EXPECT_EQ(read.at("max_uint64").get<uint64_t>(),
            std::numeric_limits<uint64_t>::max());
  EXPECT_EQ(read.at("min_int64").get<int64_t>(),
            std::numeric_limits<int64_t>::min());
  // Shortest text: 0.1 is not written as 0.10000000000000001.
  EXPECT_NE(ReadTextFile(path).find("    0.1,\n"), std::string::npos);
}

TEST(Json, EigenVectorsAndMatrixRows) {
  Eigen::Matrix<double, 2, 3> matrix;
  matrix << 1, 2, 3, 4, 5, 6.5;
  EXPECT_EQ(MatrixRowsToJson(matrix).dump(), "[[1.0,2.0,3.0],[4.0,5.0,6.5]]");
  EXPECT_EQ(VectorToJson(Eigen::Vector2d(0.25, -1)).dump(), "[0.25,-1.0]");
  EXPECT_EQ(VectorToJson(Eigen::VectorXd()).dump(), "[]");
}

TEST(Json, InvalidUtf8ThrowsAndWritesNothing) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "bad.json");
  Json json;
  json["name"] = std::string("caf\xe9.png");
  try {
    WriteJsonFile(path, json);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
  }
  EXPECT_FALSE(ExistsFile(path));
}

TEST(Json, ReadErrorsNameThePath) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "broken.json");
  {
    std::ofstream stream(path);
    stream << "{\"a\": [1, 2,}\n";
  }
  try {
    ReadJsonFile(path);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
  }
  EXPECT_THROW(ReadJsonFile(JoinPaths(dir, "missing.json")), Error);
}

}  // namespace
}  // namespace colmap_lidar
