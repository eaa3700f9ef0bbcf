#include "taskmatrix/io/yaml_reader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "taskmatrix/core/input_error.h"
#include "taskmatrix/core/utf8.h"
#include "taskmatrix/io/text_file.h"

namespace taskmatrix::io {

using core::InputError;

YamlNode::YamlNode(YAML::Node node, std::shared_ptr<const std::string> file, std::string key)
    : node_(std::move(node)), file_(std::move(file)), key_(std::move(key)) {}

YamlNode YamlNode::parse(const std::string& text, const std::string& file) {
  // YAML is UTF-8 here; other bytes would pass through to names, reports and JSON.
  if (const std::optional<size_t> bad = core::invalid_utf8_at(text)) {
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + *bad, '\n'));
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02x", static_cast<unsigned char>(text[*bad]));
    throw InputError(file, "", std::string("not UTF-8 text (byte ") + byte + ")", line);
  }
  try {
    YAML::Node root = YAML::Load(text);
    return YamlNode(root, std::make_shared<const std::string>(file), "");
  } catch (const YAML::Exception& e) {
    throw InputError(file, "", "not valid YAML: " + e.msg, e.mark.line >= 0 ? e.mark.line + 1 : 0);
  }
}

YamlNode YamlNode::load_file(const std::filesystem::path& file) {
  YamlNode root = parse(read_text_file(file), file.string());
  if (!root.is_map()) throw InputError(file.string(), "", "the document must be a YAML mapping");
  return root;
}

int YamlNode::line() const {
  const YAML::Mark mark = node_.Mark();
  return mark.line >= 0 ? mark.line + 1 : 0;
}

void YamlNode::fail(const std::string& message) const {
  throw InputError(*file_, key_, message, line());
}

YamlNode YamlNode::child(const YAML::Node& node, const std::string& child_key) const {
  std::string path = key_;
  if (!child_key.empty() && child_key.front() != '[' && !path.empty()) path += ".";
  path += child_key;
  return YamlNode(node, file_, path);
}

bool YamlNode::has(std::string_view child_key) const {
  if (!node_.IsMap()) return false;
  const YAML::Node c = node_[std::string(child_key)];
  return c.IsDefined() && !c.IsNull();
}

YamlNode YamlNode::required(std::string_view child_key) const {
  if (!node_.IsMap()) fail("must be a mapping");
  const YAML::Node c = node_[std::string(child_key)];
  if (!c.IsDefined() || c.IsNull()) {
    throw InputError(*file_,
                     key_.empty() ? std::string(child_key) : key_ + "." + std::string(child_key),
                     "is required but missing", line());
  }
  return child(c, std::string(child_key));
}

std::optional<YamlNode> YamlNode::optional(std::string_view child_key) const {
  if (!has(child_key)) return std::nullopt;
  return required(child_key);
}

std::string YamlNode::key_text(const YAML::Node& key) const {
  if (!key.IsScalar()) {
    throw InputError(*file_, key_, "keys must be plain names",
                     key.Mark().line >= 0 ? key.Mark().line + 1 : line());
  }
  return key.Scalar();
}

void YamlNode::expect_keys(std::initializer_list<std::string_view> allowed) const {
  if (!node_.IsMap()) fail("must be a mapping");
  std::set<std::string> seen;
  for (const auto& kv : node_) {
    const std::string k = key_text(kv.first);
    if (!seen.insert(k).second) {
      throw InputError(*file_, key_.empty() ? k : key_ + "." + k, "appears twice",
                       kv.first.Mark().line >= 0 ? kv.first.Mark().line + 1 : line());
    }
    bool known = false;
    for (std::string_view a : allowed) known = known || a == k;
    if (!known) {
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      const int l = kv.first.Mark().line >= 0 ? kv.first.Mark().line + 1 : line();
      throw InputError(*file_, key_.empty() ? k : key_ + "." + k,
                       "unknown key (expected one of: " + list + ")", l);
    }
  }
}

std::vector<std::pair<std::string, YamlNode>> YamlNode::entries() const {
  if (!node_.IsMap()) fail("must be a mapping");
  std::vector<std::pair<std::string, YamlNode>> out;
  std::set<std::string> seen;
  for (const auto& kv : node_) {
    const std::string k = key_text(kv.first);
    if (!seen.insert(k).second) {
      throw InputError(*file_, key_.empty() ? k : key_ + "." + k, "appears twice",
                       kv.first.Mark().line >= 0 ? kv.first.Mark().line + 1 : line());
    }
    out.emplace_back(k, child(kv.second, k));
  }
  return out;
}

std::vector<YamlNode> YamlNode::items() const {
  if (!node_.IsSequence()) fail("must be a list");
  std::vector<YamlNode> out;
  for (size_t i = 0; i < node_.size(); ++i) {
    out.push_back(child(node_[i], "[" + std::to_string(i) + "]"));
  }
  return out;
}

double YamlNode::as_double() const {
  if (!node_.IsScalar()) fail("must be a number");
  double v = 0;
  try {
    v = node_.as<double>();
  } catch (const YAML::Exception&) {
    fail("must be a number, got '" + node_.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail("must be a finite number, got '" + node_.Scalar() + "'");
  return v;
}

double YamlNode::as_positive_double() const {
  const double v = as_double();
  if (v <= 0) fail("must be positive, got " + node_.Scalar());
  return v;
}

int YamlNode::as_int() const {
  if (!node_.IsScalar()) fail("must be an integer");
  try {
    return node_.as<int>();
  } catch (const YAML::Exception&) {
    fail("must be an integer, got '" + node_.Scalar() + "'");
  }
}

std::uint64_t YamlNode::as_uint64() const {
  if (!node_.IsScalar()) fail("must be an integer");
  const std::string& text = node_.Scalar();
  if (text.empty() || text.size() > 20 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    fail("must be an integer from 0 to 18446744073709551615, got '" + text + "'");
  }
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE)
    fail("must be an integer from 0 to 18446744073709551615, got '" + text + "'");
  return static_cast<std::uint64_t>(v);
}

bool YamlNode::as_bool() const {
  if (!node_.IsScalar()) fail("must be true or false");
  try {
    return node_.as<bool>();
  } catch (const YAML::Exception&) {
    fail("must be true or false, got '" + node_.Scalar() + "'");
  }
}

std::string YamlNode::as_string() const {
  if (!node_.IsScalar() || node_.Scalar().empty()) fail("must be a non-empty string");
  return node_.Scalar();
}

std::vector<double> YamlNode::as_doubles() const {
  std::vector<double> out;
  for (const YamlNode& item : items()) out.push_back(item.as_double());
  return out;
}

std::vector<std::string> YamlNode::as_strings() const {
  std::vector<std::string> out;
  for (const YamlNode& item : items()) out.push_back(item.as_string());
  return out;
}

double YamlNode::get_double(std::string_view child_key, double fallback) const {
  auto c = optional(child_key);
  return c ? c->as_double() : fallback;
}

int YamlNode::get_int(std::string_view child_key, int fallback) const {
  auto c = optional(child_key);
  return c ? c->as_int() : fallback;
}

std::string YamlNode::get_string(std::string_view child_key, const std::string& fallback) const {
  auto c = optional(child_key);
  return c ? c->as_string() : fallback;
}

}  // namespace taskmatrix::io
