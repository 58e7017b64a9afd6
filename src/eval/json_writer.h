// A minimal streaming JSON writer for the evaluation reports (no external
// dependency). Output is indented, keys keep the order they were written in,
// doubles use the shortest text that reads back to the same value and
// non-finite doubles are written as null (JSON has no NaN or infinity).
//
//   JsonWriter json(&stream);
//   json.BeginObject();
//   json.Field("num_images", 12);
//   json.Key("errors"); json.Array(errors);
//   json.EndObject();
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace colmap_lidar {

class JsonWriter {
 public:
  explicit JsonWriter(std::ostream* stream);

  void BeginObject();
  void EndObject();
  void BeginArray();
  void EndArray();
  // Inside an object, every value is preceded by its key.
  void Key(const std::string& key);

  void Value(double value);
  void Value(int value) { Value(static_cast<int64_t>(value)); }
  void Value(int64_t value);
  void Value(uint64_t value);
  void Value(unsigned int value) { Value(static_cast<uint64_t>(value)); }
  void Value(bool value);
  void Value(const std::string& value);
  void Value(const char* value) { Value(std::string(value)); }
  void Array(const std::vector<double>& values);

  template <typename T>
  void Field(const std::string& key, const T& value) {
    Key(key);
    Value(value);
  }

  // Escapes quotes, backslashes and control characters.
  static std::string Escape(const std::string& text);
  // Shortest round-trip text of a double; "null" when not finite.
  static std::string FormatDouble(double value);

 private:
  struct Level {
    bool is_array = false;
    int num_items = 0;
  };
  // Writes the separator and indentation before a value or key.
  void BeforeItem();
  void Indent();

  std::ostream* stream_;
  std::vector<Level> levels_;
  bool after_key_ = false;
};

}  // namespace colmap_lidar
