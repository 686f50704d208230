// Edits of a JSON text that keep the rest of it byte for byte (issue 41): each case states the
// whole text expected after the edit.

#include "harness/view/json_text_edit.h"

#include <gtest/gtest.h>

#include "base/error.h"

namespace svr {
namespace {

using Json = nlohmann::ordered_json;

const std::string kScene = R"({
  "volume": {"file": "../volumes/engine.nhdr"},
  "materials": {"a": {"reflectance": "ColorChecker/red",   "opacity": 0.50}},
  "lights": [
    {"name": "D65", "library": "D65"},
    {"name": "A", "library": "A"}
  ],
  "light_mixes": {
    "half": {"D65": 0.5, "A": 0.5}
  },
  "model": "factor:6"
}
)";

TEST(JsonTextEdit, AMemberAddedToAnIndentedObjectTakesTheNextIndentedLine) {
  const std::string out = withMemberSet(kScene, {"light_mixes"}, "dusk", Json{{"D65", 0.25}, {"F11", 0.75}}, "s.json");
  EXPECT_EQ(out, R"({
  "volume": {"file": "../volumes/engine.nhdr"},
  "materials": {"a": {"reflectance": "ColorChecker/red",   "opacity": 0.50}},
  "lights": [
    {"name": "D65", "library": "D65"},
    {"name": "A", "library": "A"}
  ],
  "light_mixes": {
    "half": {"D65": 0.5, "A": 0.5},
    "dusk": {"D65": 0.25, "F11": 0.75}
  },
  "model": "factor:6"
}
)");
}

TEST(JsonTextEdit, AnExistingMemberIsReplacedInItsPlace) {
  const std::string out = withMemberSet(kScene, {"light_mixes"}, "half", Json{{"A", 1}}, "s.json");
  std::string expected = kScene;
  expected.replace(expected.find(R"({"D65": 0.5, "A": 0.5})"), 22, R"({"A": 1})");
  EXPECT_EQ(out, expected);
}

TEST(JsonTextEdit, AnElementAppendedFollowsTheLastTwoElementsLayout) {
  const std::string out = withElementAppended(kScene, {"lights"}, Json{{"name", "F11"}, {"library", "F11"}}, "s.json");
  std::string expected = kScene;
  const std::string last = R"({"name": "A", "library": "A"})";
  expected.insert(expected.find(last) + last.size(), ",\n    {\"name\": \"F11\", \"library\": \"F11\"}");
  EXPECT_EQ(out, expected);
}

TEST(JsonTextEdit, OneLineContainersStayOnOneLine) {
  const std::string text = "{\"lights\": [\"D65\"], \"light_mixes\": {\"a\": {\"D65\": 1}}, \"model\": \"rgb\"}";
  const std::string one = withElementAppended(text, {"lights"}, Json("F11"), "s.json");
  EXPECT_EQ(one, "{\"lights\": [\"D65\", \"F11\"], \"light_mixes\": {\"a\": {\"D65\": 1}}, \"model\": \"rgb\"}");
  const std::string two = withMemberSet(one, {"light_mixes"}, "b", Json{{"F11", 2.5e-3}}, "s.json");
  EXPECT_EQ(two, "{\"lights\": [\"D65\", \"F11\"], \"light_mixes\": {\"a\": {\"D65\": 1}, \"b\": {\"F11\": 0.0025}}, \"model\": \"rgb\"}");
}

TEST(JsonTextEdit, AMissingObjectIsAddedAfterTheLastTopLevelMember) {
  const std::string text = "{\r\n\t\"lights\": [\"D65\", \"A\"],\r\n\t\"model\": \"rgb\"\r\n}\r\n";
  const std::string out = withMemberSet(text, {"light_mixes"}, "m", Json{{"A", 1}}, "s.json");
  EXPECT_EQ(out, "{\r\n\t\"lights\": [\"D65\", \"A\"],\r\n\t\"model\": \"rgb\",\r\n\t\"light_mixes\": {\"m\": {\"A\": 1}}\r\n}\r\n");
  const std::string arrays = withElementAppended("{\"model\": \"rgb\"}", {"lights"}, Json("A"), "s.json");
  EXPECT_EQ(arrays, "{\"model\": \"rgb\", \"lights\": [\"A\"]}");
  EXPECT_EQ(withMemberSet("{}", {"a", "b"}, "c", Json(1), "s.json"), R"({"a": {"b": {"c": 1}}})");
  EXPECT_EQ(withElementAppended("{\"lights\": [ ]}", {"lights"}, Json("A"), "s.json"), R"({"lights": ["A"]})");
}

TEST(JsonTextEdit, StringsWithBracketsQuotesAndEscapedKeysAreSkippedWhole) {
  const std::string text = R"({"description": "a } ] \" { [ , trap", "light_mixes": {"we\"ird": {"A": 1}}})";
  const std::string out = withMemberSet(text, {"light_mixes"}, "we\"ird", Json{{"A", 2}}, "s.json");
  EXPECT_EQ(out, R"({"description": "a } ] \" { [ , trap", "light_mixes": {"we\"ird": {"A": 2}}})");
}

TEST(JsonTextEdit, WhatIsNotAnObjectOrNotJsonIsAClearErrorNamingTheFile) {
  const auto message = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([] { withMemberSet("{\"light_mixes\": 5}", {"light_mixes"}, "a", Json(1), "s.json"); }),
            "s.json: '/light_mixes' is not an object");
  EXPECT_EQ(message([] { withElementAppended("{\"lights\": {}}", {"lights"}, Json(1), "s.json"); }),
            "s.json: '/lights' is not an array");
  EXPECT_EQ(message([] { withMemberSet("{\"a\": ", {}, "a", Json(1), "s.json"); }),
            "s.json: the file is not one valid JSON object");
  EXPECT_EQ(message([] { withMemberSet("[1]", {}, "a", Json(1), "s.json"); }),
            "s.json: the file is not one valid JSON object");
}

TEST(JsonTextEdit, CompactJsonIsOneLineWithSpacedSeparators) {
  EXPECT_EQ(compactJson(Json{{"b", Json::array({1, 2.5, "x"})}, {"a", nullptr}}), R"({"b": [1, 2.5, "x"], "a": null})");
  EXPECT_EQ(compactJson(Json::object()), "{}");
}

}  // namespace
}  // namespace svr
