// JSON read from files (run directories, benchmark results) with errors like the YAML ones: one
// core::InputError naming the file, the line and the key, for text that is not JSON, not UTF-8,
// holds a number out of range (1e999), or a value of the wrong type. And JSON written for
// people and tools: text that is not UTF-8 (a name from a model file) is written with U+FFFD in
// its place instead of failing the write.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace taskmatrix::harness {

// Parses `text`, which starts at line `first_line` of `file`. Throws core::InputError.
nlohmann::json parse_json_text(const std::string& text, const std::string& file,
                               int first_line = 1);
// Reads and parses a whole file. Throws core::InputError (also when it cannot be read).
nlohmann::json read_json_file(const std::filesystem::path& file);

// Where a value was read from, for errors: "FILE:LINE: KEY: message".
struct JsonPlace {
  std::string file;
  int line = 0;  // 0: unknown
  std::string key;
  JsonPlace at(const std::string& child) const;  // key.child (or [i])
  [[noreturn]] void fail(const std::string& message) const;
};

enum class JsonKind { kString, kBool, kNumber, kUnsigned, kObject, kArray };
// `object[key]` checked for `kind` (kNumber: finite; kUnsigned: an integer >= 0). With
// `nullable`, null passes too. Throws core::InputError naming the place and key.
const nlohmann::json& json_field(const nlohmann::json& object, const char* key, JsonKind kind,
                                 const JsonPlace& where, bool nullable = false);
// As json_field, but a missing key passes (returns null).
const nlohmann::json& json_optional_field(const nlohmann::json& object, const char* key,
                                          JsonKind kind, const JsonPlace& where);

// dump() that never throws on text that is not UTF-8 (it is replaced).
std::string json_text(const nlohmann::json& value, int indent = -1);

// A measured value as written: the number, or null when it is not finite (unmeasured).
nlohmann::json number_or_null(double v);

}  // namespace taskmatrix::harness
