#include "harness/results/json_input.h"

#include <cmath>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/io/text_file.h"

namespace taskmatrix::harness {

namespace {

// nlohmann's message without its "[json.exception.parse_error.101] parse error at line 1,
// column 5: " prefix (the InputError names the file and line instead).
std::string bare_message(const std::string& what) {
  std::string m = what;
  const size_t bracket = m.find("] ");
  if (m.rfind("[json.exception", 0) == 0 && bracket != std::string::npos) m = m.substr(bracket + 2);
  const size_t colon = m.find(": ");
  if (m.rfind("parse error at line", 0) == 0 && colon != std::string::npos) m = m.substr(colon + 2);
  if (m.rfind("parse error: ", 0) == 0) m = m.substr(13);
  return m;
}

int line_of(const std::string& text, size_t byte, int first_line) {
  int line = first_line;
  for (size_t i = 0; i < byte && i < text.size(); ++i) line += text[i] == '\n';
  return line;
}

const char* kind_name(JsonKind kind) {
  switch (kind) {
    case JsonKind::kString:
      return "a string";
    case JsonKind::kBool:
      return "true or false";
    case JsonKind::kNumber:
      return "a finite number";
    case JsonKind::kUnsigned:
      return "an integer >= 0";
    case JsonKind::kObject:
      return "an object";
    case JsonKind::kArray:
      return "an array";
  }
  return "?";
}

bool is_kind(const nlohmann::json& v, JsonKind kind) {
  switch (kind) {
    case JsonKind::kString:
      return v.is_string();
    case JsonKind::kBool:
      return v.is_boolean();
    case JsonKind::kNumber:
      return v.is_number() && std::isfinite(v.get<double>());
    case JsonKind::kUnsigned:
      return v.is_number_unsigned() || (v.is_number_integer() && v.get<std::int64_t>() >= 0);
    case JsonKind::kObject:
      return v.is_object();
    case JsonKind::kArray:
      return v.is_array();
  }
  return false;
}

const nlohmann::json& null_json() {
  static const nlohmann::json null;
  return null;
}

}  // namespace

nlohmann::json parse_json_text(const std::string& text, const std::string& file, int first_line) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is 1-based: the byte after the last one read.
    const size_t at = e.byte > 0 ? e.byte - 1 : 0;
    throw core::InputError(file, "", "not JSON: " + bare_message(e.what()),
                           line_of(text, at, first_line));
  } catch (const nlohmann::json::exception& e) {  // out_of_range.406: 1e999
    throw core::InputError(file, "", "not JSON: " + bare_message(e.what()), first_line);
  }
}

nlohmann::json read_json_file(const std::filesystem::path& file) {
  return parse_json_text(io::read_text_file(file), file.string());
}

JsonPlace JsonPlace::at(const std::string& child) const {
  JsonPlace p = *this;
  if (!child.empty() && child.front() != '[' && !p.key.empty()) p.key += ".";
  p.key += child;
  return p;
}

void JsonPlace::fail(const std::string& message) const {
  throw core::InputError(file, key, message, line);
}

const nlohmann::json& json_field(const nlohmann::json& object, const char* key, JsonKind kind,
                                 const JsonPlace& where, bool nullable) {
  if (!object.is_object()) where.fail("must be an object");
  const auto it = object.find(key);
  if (it == object.end()) where.at(key).fail("is required but missing");
  if (nullable && it->is_null()) return *it;
  if (!is_kind(*it, kind)) {
    // A nested value is named, not printed (dump recurses: no depth limit).
    std::string got = it->is_array()    ? std::string("an array")
                      : it->is_object() ? std::string("an object")
                                        : json_text(*it);
    if (got.size() > 40) got = got.substr(0, 37) + "...";
    where.at(key).fail(std::string("must be ") + kind_name(kind) + (nullable ? " or null" : "") +
                       ", got " + got);
  }
  return *it;
}

const nlohmann::json& json_optional_field(const nlohmann::json& object, const char* key,
                                          JsonKind kind, const JsonPlace& where) {
  if (!object.is_object()) where.fail("must be an object");
  if (!object.contains(key)) return null_json();
  return json_field(object, key, kind, where, /*nullable=*/true);
}

std::string json_text(const nlohmann::json& value, int indent) {
  return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace taskmatrix::harness
