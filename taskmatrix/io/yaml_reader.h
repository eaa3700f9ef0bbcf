// A YAML node that knows its file and key path, so every error it raises is one line naming
// both (and the line number). Strict by design: callers list the keys they accept and any
// other key is an error, numbers must be finite, types must match.
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace taskmatrix::io {

class YamlNode {
 public:
  // Parses `file`; throws core::InputError if it is missing, unreadable or not YAML.
  static YamlNode load_file(const std::filesystem::path& file);
  // Parses text (for tests and inline documents); `file` names it in errors.
  static YamlNode parse(const std::string& text, const std::string& file);

  const std::string& file() const { return *file_; }
  const std::string& key() const { return key_; }
  int line() const;  // 1-based, 0 when unknown

  bool is_map() const { return node_.IsMap(); }
  bool is_scalar() const { return node_.IsScalar(); }
  bool has(std::string_view child_key) const;

  // Map access. `required` fails when the key is absent or null.
  YamlNode required(std::string_view child_key) const;
  std::optional<YamlNode> optional(std::string_view child_key) const;
  // Fails naming the first key not in `allowed`.
  void expect_keys(std::initializer_list<std::string_view> allowed) const;
  std::vector<std::pair<std::string, YamlNode>> entries() const;  // map, in file order
  std::vector<YamlNode> items() const;                            // sequence

  double as_double() const;  // finite only
  double as_positive_double() const;
  int as_int() const;
  std::uint64_t as_uint64() const;  // digits only, 0..2^64-1
  bool as_bool() const;
  std::string as_string() const;  // non-empty scalar
  std::vector<double> as_doubles() const;
  std::vector<std::string> as_strings() const;

  // Typed shortcuts for optional scalars.
  double get_double(std::string_view child_key, double fallback) const;
  int get_int(std::string_view child_key, int fallback) const;
  std::string get_string(std::string_view child_key, const std::string& fallback) const;

  [[noreturn]] void fail(const std::string& message) const;

 private:
  YamlNode(YAML::Node node, std::shared_ptr<const std::string> file, std::string key);
  YamlNode child(const YAML::Node& node, const std::string& child_key) const;
  std::string key_text(const YAML::Node& key) const;

  YAML::Node node_;
  std::shared_ptr<const std::string> file_;
  std::string key_;
};

}  // namespace taskmatrix::io
