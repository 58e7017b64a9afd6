#include "src/eval/json_writer.h"

#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

TEST(JsonWriter, NestedOutput) {
  std::ostringstream stream;
  JsonWriter json(&stream);
  json.BeginObject();
  json.Field("name", "a\"b\\c\n");
  json.Field("count", 3);
  json.Field("ok", true);
  json.Field("nan", std::nan(""));
  json.Key("values");
  json.Array({0.1, 1.0, 1e-20});
  json.Key("items");
  json.BeginArray();
  json.BeginObject();
  json.Field("x", 2.5);
  json.EndObject();
  json.Value(uint64_t{18446744073709551615u});
  json.EndArray();
  json.Key("empty");
  json.BeginObject();
  json.EndObject();
  json.EndObject();
  EXPECT_EQ(stream.str(),
            "{\n"
            "  \"name\": \"a\\\"b\\\\c\\n\",\n"
            "  \"count\": 3,\n"
            "  \"ok\": true,\n"
            "  \"nan\": null,\n"
            "  \"values\": [0.1, 1, 1e-20],\n"
            "  \"items\": [\n"
            "    {\n"
            "      \"x\": 2.5\n"
            "    },\n"
            "    18446744073709551615\n"
            "  ],\n"
            "  \"empty\": {}\n"
            "}\n");
}

TEST(JsonWriter, ShortestRoundTripDoubles) {
  for (const double value : {0.1, 1.0 / 3.0, 123456.789, -2e-300}) {
    EXPECT_EQ(std::stod(JsonWriter::FormatDouble(value)), value);
  }
  EXPECT_EQ(JsonWriter::FormatDouble(INFINITY), "null");
}

TEST(JsonWriter, MisuseThrows) {
  std::ostringstream stream;
  JsonWriter json(&stream);
  json.BeginObject();
  EXPECT_THROW(json.Value(1.0), Error);
  EXPECT_THROW(json.EndArray(), Error);
}

}  // namespace
}  // namespace colmap_lidar
