#include "taskmatrix/io/yaml_reader.h"

#include <gtest/gtest.h>

#include "taskmatrix/core/input_error.h"

namespace taskmatrix::io {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(YamlReader, UnknownKeyNamesFileLineAndKey) {
  const YamlNode root =
      YamlNode::parse("name: a\nchains:\n  arm:\n    joints: [a]\n    colour: red\n", "p.yaml");
  const std::string e =
      error_of([&] { root.required("chains").required("arm").expect_keys({"joints"}); });
  EXPECT_EQ(e, "p.yaml:5: chains.arm.colour: unknown key (expected one of: joints)");
}

TEST(YamlReader, MissingKeyIsNamed) {
  const YamlNode root = YamlNode::parse("a: 1\n", "f.yaml");
  EXPECT_EQ(error_of([&] { root.required("b"); }), "f.yaml:1: b: is required but missing");
}

TEST(YamlReader, NanAndInfinityAndTextAreNotNumbers) {
  const YamlNode root = YamlNode::parse("a: .nan\nb: .inf\nc: twelve\nd: [1, 2, x]\n", "f.yaml");
  EXPECT_NE(error_of([&] {
              root.required("a").as_double();
            }).find("f.yaml:1: a: must be a finite number"),
            std::string::npos);
  EXPECT_NE(error_of([&] { root.required("b").as_double(); }).find("must be a finite number"),
            std::string::npos);
  EXPECT_NE(
      error_of([&] { root.required("c").as_double(); }).find("must be a number, got 'twelve'"),
      std::string::npos);
  EXPECT_NE(error_of([&] { root.required("d").as_doubles(); }).find("d[2]: must be a number"),
            std::string::npos);
}

TEST(YamlReader, MalformedYamlNamesFileAndLine) {
  const std::string e = error_of([] { YamlNode::parse("a: [1, 2\nb: 3\n", "bad.yaml"); });
  EXPECT_EQ(e.rfind("bad.yaml:", 0), 0u) << e;
  EXPECT_NE(e.find("not valid YAML"), std::string::npos) << e;
}

TEST(YamlReader, MissingFileIsNamed) {
  EXPECT_EQ(error_of([] { YamlNode::load_file("/nonexistent/x.yaml"); }),
            "/nonexistent/x.yaml: cannot open file");
}

TEST(YamlReader, TypedValuesRoundTrip) {
  const YamlNode root = YamlNode::parse("a: 1.5\nb: 7\nc: true\nd: [x, y]\n", "f.yaml");
  EXPECT_EQ(root.required("a").as_double(), 1.5);
  EXPECT_EQ(root.required("b").as_int(), 7);
  EXPECT_TRUE(root.required("c").as_bool());
  EXPECT_EQ(root.required("d").as_strings(), (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(root.get_double("missing", 2.5), 2.5);
  EXPECT_NE(error_of([&] { root.required("a").as_int(); }).find("must be an integer"),
            std::string::npos);
}

}  // namespace
}  // namespace taskmatrix::io
