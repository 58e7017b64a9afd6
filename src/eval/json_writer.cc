#include "src/eval/json_writer.h"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

JsonWriter::JsonWriter(std::ostream* stream) : stream_(stream) {}

void JsonWriter::Indent() {
  *stream_ << '\n' << std::string(2 * levels_.size(), ' ');
}

void JsonWriter::BeforeItem() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (levels_.empty()) {
    return;
  }
  THROW_CHECK(levels_.back().is_array,
              "JsonWriter: a value inside an object needs a Key()");
  if (levels_.back().num_items++ > 0) {
    *stream_ << ',';
  }
  Indent();
}

void JsonWriter::BeginObject() {
  BeforeItem();
  *stream_ << '{';
  levels_.push_back(Level{false, 0});
}

void JsonWriter::EndObject() {
  THROW_CHECK(!levels_.empty() && !levels_.back().is_array && !after_key_,
              "JsonWriter: unbalanced EndObject()");
  const bool empty = levels_.back().num_items == 0;
  levels_.pop_back();
  if (!empty) {
    Indent();
  }
  *stream_ << '}';
  if (levels_.empty()) {
    *stream_ << '\n';
  }
}

void JsonWriter::BeginArray() {
  BeforeItem();
  *stream_ << '[';
  levels_.push_back(Level{true, 0});
}

void JsonWriter::EndArray() {
  THROW_CHECK(!levels_.empty() && levels_.back().is_array,
              "JsonWriter: unbalanced EndArray()");
  const bool empty = levels_.back().num_items == 0;
  levels_.pop_back();
  if (!empty) {
    Indent();
  }
  *stream_ << ']';
}

void JsonWriter::Key(const std::string& key) {
  THROW_CHECK(!levels_.empty() && !levels_.back().is_array && !after_key_,
              "JsonWriter: Key(\"" << key << "\") outside an object");
  if (levels_.back().num_items++ > 0) {
    *stream_ << ',';
  }
  Indent();
  *stream_ << '"' << Escape(key) << "\": ";
  after_key_ = true;
}

void JsonWriter::Value(double value) {
  BeforeItem();
  *stream_ << FormatDouble(value);
}

void JsonWriter::Value(int64_t value) {
  BeforeItem();
  *stream_ << value;
}

void JsonWriter::Value(uint64_t value) {
  BeforeItem();
  *stream_ << value;
}

void JsonWriter::Value(bool value) {
  BeforeItem();
  *stream_ << (value ? "true" : "false");
}

void JsonWriter::Value(const std::string& value) {
  BeforeItem();
  *stream_ << '"' << Escape(value) << '"';
}

void JsonWriter::Array(const std::vector<double>& values) {
  // Short numeric arrays stay on one line for readability.
  BeforeItem();
  *stream_ << '[';
  for (size_t i = 0; i < values.size(); ++i) {
    *stream_ << (i > 0 ? ", " : "") << FormatDouble(values[i]);
  }
  *stream_ << ']';
}

std::string JsonWriter::Escape(const std::string& text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '"':
        escaped += "\\\"";
        break;
      case '\\':
        escaped += "\\\\";
        break;
      case '\n':
        escaped += "\\n";
        break;
      case '\t':
        escaped += "\\t";
        break;
      case '\r':
        escaped += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof(buffer), "\\u%04x",
                        static_cast<unsigned int>(c));
          escaped += buffer;
        } else {
          escaped += c;
        }
    }
  }
  return escaped;
}

std::string JsonWriter::FormatDouble(double value) {
  if (!std::isfinite(value)) {
    return "null";
  }
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

}  // namespace colmap_lidar
