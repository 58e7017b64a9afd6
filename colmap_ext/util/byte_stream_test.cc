#include "colmap_ext/util/byte_stream.h"

#include <array>
#include <string>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

TEST(ByteStream, RoundTripsValuesAndStrings) {
  std::string bytes;
  ByteWriter writer(&bytes);
  writer.Value<uint32_t>(7);
  writer.String("scan.bin");
  const std::array<double, 3> values = {0.5, -0.0, 1e300};
  writer.Values(values.data(), values.size());
  writer.String("");

  ByteReader reader(bytes);
  EXPECT_EQ(reader.Value<uint32_t>(), 7u);
  EXPECT_EQ(reader.String(), "scan.bin");
  std::array<double, 3> copy;
  EXPECT_EQ(reader.Remaining(), sizeof(copy) + sizeof(uint64_t));
  reader.Values(copy.data(), copy.size());
  EXPECT_EQ(copy, values);
  EXPECT_EQ(reader.String(), "");
  EXPECT_TRUE(reader.AtEnd());
}

TEST(ByteStream, ReadsPastTheEndThrow) {
  std::string bytes;
  ByteWriter writer(&bytes);
  writer.Value<uint16_t>(1);
  ByteReader reader(bytes);
  EXPECT_THROW(reader.Value<uint32_t>(), Error);
  std::array<uint8_t, 3> three;
  EXPECT_THROW(reader.Values(three.data(), three.size()), Error);
  // A count whose byte size wraps to 0 is refused.
  std::array<uint64_t, 1> eight;
  EXPECT_THROW(reader.Values(eight.data(), size_t{1} << 61), Error);
  EXPECT_EQ(reader.Value<uint16_t>(), 1);
  EXPECT_TRUE(reader.AtEnd());

  // A string whose size runs past the end.
  std::string text;
  ByteWriter(&text).Value<uint64_t>(~uint64_t{0});
  ByteReader text_reader(text);
  EXPECT_THROW(text_reader.String(), Error);
}

}  // namespace
}  // namespace colmap_lidar
