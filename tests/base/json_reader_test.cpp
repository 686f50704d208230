#include "base/json_reader.h"

#include <gtest/gtest.h>

#include <string>

#include "base/error.h"

namespace svr {
namespace {

std::string parseError(const std::string& text) {
  try {
    JsonReader::parse(text, "in.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(JsonReader, ParsesWellFormedJson) {
  const nlohmann::json j = JsonReader::parse(R"({"a": [1, {"b": 2}], "c": {"a": 3}})", "in.json");
  EXPECT_EQ(j["a"][1]["b"], 2);
  EXPECT_EQ(j["c"]["a"], 3);  // the same key in another object is no duplicate
}

TEST(JsonReader, RejectsDuplicateKeysNamingTheirPath) {
  EXPECT_EQ(parseError(R"({"camera": {}, "camera": {}})"), "in.json: duplicate key 'camera'");
  EXPECT_EQ(parseError(R"({"camera": {"azimuth": 1, "azimuth": 2}})"),
            "in.json: duplicate key 'camera.azimuth'");
  EXPECT_EQ(parseError(R"({"lights": ["D65", {"name": "a"}, {"name": "b", "name": "c"}]})"),
            "in.json: duplicate key 'lights[2].name'");
  EXPECT_EQ(parseError(R"([[1, 2], [{"x": 1, "x": 1}]])"), "in.json: duplicate key '[1][0].x'");
}

TEST(JsonReader, RejectsDeepNestingAndMalformedJson) {
  EXPECT_EQ(parseError(std::string(300, '[') + std::string(300, ']')),
            "in.json: '" + [] {
              std::string path;
              for (int i = 0; i < 256; ++i) path += "[0]";
              return path;
            }() + "' nests deeper than 256 levels");
  EXPECT_NE(parseError(R"({"a": 1,})").find("in.json: invalid JSON: "), std::string::npos);
}

TEST(JsonReader, ErrorMessagesShowLongValuesShortened) {
  const nlohmann::json j = JsonReader::parse(
      R"({"camera": [")" + std::string(200, 'a') + R"(", ")" + std::string(200, 'b') + R"("]})",
      "in.json");
  try {
    JsonReader(j, "in.json").at("camera").at("zoom");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("in.json: camera: expected an object, got [\"aaaa", 0), 0u) << what;
    EXPECT_LT(what.size(), 140u) << what;
    EXPECT_EQ(what.substr(what.size() - 3), "…");
  }
}

}  // namespace
}  // namespace svr
