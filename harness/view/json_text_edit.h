#pragma once
// Edits of a JSON document that keep its text (issue 41): the value changed or added is spliced
// into the text, and every other byte — key order, spacing, line breaks, number spellings —
// stays as the author wrote it. `svr view` saves a light mix this way, so one click does not
// reformat the user's scene file.
//
// A new member or element follows the layout of its siblings: the separator between the last
// two (or the whitespace after the opening bracket, where there is one sibling), so a
// one-line object stays on one line and an indented one gets the next indented line. The value
// itself is written compactly on one line.
//
// Every edit is checked: the result must parse to the document with exactly that change, or
// svr::Error is thrown and nothing is returned. The input must be valid JSON (svr::Error names
// `source` otherwise).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace svr {

// `text` with path[0].path[1]….key set to `value`: replaced where it exists, appended to its
// object where it does not; objects on the path that are missing are added with it.
std::string withMemberSet(const std::string& text, const std::vector<std::string>& path,
                          const std::string& key, const nlohmann::ordered_json& value,
                          const std::string& source);

// `text` with `element` appended to the array at `path` (added with it, when missing).
std::string withElementAppended(const std::string& text, const std::vector<std::string>& path,
                                const nlohmann::ordered_json& element, const std::string& source);

// A value as the edits write it: on one line, ", " and ": " as separators.
std::string compactJson(const nlohmann::ordered_json& value);

}  // namespace svr
