#include "harness/view/json_text_edit.h"

#include <fmt/format.h>

#include <algorithm>

#include "base/error.h"

namespace svr {

namespace {

using Json = nlohmann::ordered_json;

// [begin, end) of one value, or of one member (its key to the end of its value) or element.
struct Span {
  size_t begin = 0, end = 0;
};

struct Item {
  std::string key;  // decoded; empty for array elements
  Span whole;       // key (if any) through value
  Span value;
};

// Positions in text already known to be valid JSON: nothing here needs to report an error.
class JsonScanner {
 public:
  explicit JsonScanner(const std::string& text) : t_(text) {}

  bool isObject(Span value) const { return t_[value.begin] == '{'; }
  bool isArray(Span value) const { return t_[value.begin] == '['; }

  size_t skipSpace(size_t at) const {
    while (at < t_.size() && (t_[at] == ' ' || t_[at] == '\t' || t_[at] == '\n' || t_[at] == '\r')) ++at;
    return at;
  }

  // The end of the value that starts at `at`.
  size_t skipValue(size_t at) const {
    if (t_[at] == '"') return skipString(at);
    if (t_[at] == '{' || t_[at] == '[') {
      int depth = 0;
      for (size_t i = at; i < t_.size(); ++i) {
        if (t_[i] == '"') {
          i = skipString(i) - 1;
        } else if (t_[i] == '{' || t_[i] == '[') {
          ++depth;
        } else if ((t_[i] == '}' || t_[i] == ']') && --depth == 0) {
          return i + 1;
        }
      }
      return t_.size();
    }
    while (at < t_.size() && t_.find_first_of(",}] \t\r\n", at) != at) ++at;  // number or literal
    return at;
  }

  // The members of the object, or elements of the array, whose value is `container`.
  std::vector<Item> items(Span container) const {
    std::vector<Item> out;
    const bool object = isObject(container);
    size_t at = skipSpace(container.begin + 1);
    while (at < container.end - 1) {
      Item item;
      item.whole.begin = at;
      if (object) {
        const size_t key_end = skipString(at);
        item.key = Json::parse(t_.substr(at, key_end - at)).get<std::string>();
        at = skipSpace(skipSpace(key_end) + 1);  // past the colon
      }
      item.value = {at, skipValue(at)};
      item.whole.end = item.value.end;
      out.push_back(item);
      at = skipSpace(item.value.end);
      if (t_[at] == ',') at = skipSpace(at + 1);
    }
    return out;
  }

 private:
  size_t skipString(size_t at) const {
    for (size_t i = at + 1; i < t_.size(); ++i) {
      if (t_[i] == '\\') ++i;
      else if (t_[i] == '"') return i + 1;
    }
    return t_.size();
  }
  const std::string& t_;
};

// `item_text` added as the last item of `container`, laid out as its siblings are.
std::string withItemAppended(const std::string& text, Span container, const std::vector<Item>& items,
                             const std::string& item_text) {
  if (items.empty())  // {} or [ ]: the item alone between the brackets
    return text.substr(0, container.begin + 1) + item_text + text.substr(container.end - 1);
  std::string separator;
  if (items.size() >= 2) {
    const Item& a = items[items.size() - 2];
    separator = text.substr(a.whole.end, items.back().whole.begin - a.whole.end);
  } else {
    const std::string lead = text.substr(container.begin + 1, items[0].whole.begin - container.begin - 1);
    separator = lead.find('\n') != std::string::npos ? "," + lead : ", ";
  }
  const size_t at = items.back().whole.end;
  return text.substr(0, at) + separator + item_text + text.substr(at);
}

// How far `path` exists under the root: the deepest value on it that exists, and how many of
// the path's keys lead there.
struct PathEnd {
  Span found;
  size_t depth = 0;
};

PathEnd follow(const JsonScanner& scanner, Span root, const std::vector<std::string>& path) {
  PathEnd end{root, 0};
  for (const std::string& key : path) {
    if (!scanner.isObject(end.found)) return end;
    const std::vector<Item> members = scanner.items(end.found);
    const auto hit = std::find_if(members.rbegin(), members.rend(), [&](const Item& m) { return m.key == key; });
    if (hit == members.rend()) return end;
    end = {hit->value, end.depth + 1};
  }
  return end;
}

Span rootOf(const std::string& text, const JsonScanner& scanner, const std::string& source) {
  const size_t begin = scanner.skipSpace(0);
  if (begin >= text.size() || text[begin] != '{')
    throw Error(fmt::format("{}: the file is not one JSON object", source));
  return {begin, scanner.skipValue(begin)};
}

// The edited text, once it parses to `expected`.
std::string checked(const std::string& edited, const Json& expected, const std::string& source) {
  const Json parsed = Json::parse(edited, nullptr, false);
  if (parsed.is_discarded() || parsed != expected)
    throw Error(fmt::format("{}: editing the file's text in place did not give the intended "
                            "document; the file is left as it was", source));
  return edited;
}

Json parsedOrThrow(const std::string& text, const std::string& source) {
  Json doc = Json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object())
    throw Error(fmt::format("{}: the file is not one valid JSON object", source));
  return doc;
}

// Wraps `value` in one object per key of path[from…]: the text of what must be added where the
// path stops existing.
Json nestedUnder(const std::vector<std::string>& path, size_t from, Json value) {
  for (size_t i = path.size(); i-- > from;) value = Json{{path[i], std::move(value)}};
  return value;
}

Json::json_pointer pointerOf(const std::vector<std::string>& path) {
  Json::json_pointer p;
  for (const std::string& key : path) p /= key;
  return p;
}

}  // namespace

std::string compactJson(const Json& value) {
  if (value.is_object() || value.is_array()) {
    std::string out = value.is_object() ? "{" : "[";
    bool first = true;
    for (auto it = value.begin(); it != value.end(); ++it) {
      out += first ? "" : ", ";
      first = false;
      if (value.is_object()) out += Json(it.key()).dump() + ": ";
      out += compactJson(*it);
    }
    return out + (value.is_object() ? "}" : "]");
  }
  return value.dump();
}

std::string withMemberSet(const std::string& text, const std::vector<std::string>& path,
                          const std::string& key, const Json& value, const std::string& source) {
  Json expected = parsedOrThrow(text, source);
  const JsonScanner scanner(text);
  const PathEnd end = follow(scanner, rootOf(text, scanner, source), path);
  if (!scanner.isObject(end.found))
    throw Error(fmt::format("{}: '{}' is not an object", source,
                            pointerOf({path.begin(), path.begin() + end.depth}).to_string()));
  expected[pointerOf(path) / key] = value;
  const std::vector<Item> members = scanner.items(end.found);
  if (end.depth == path.size()) {
    const auto hit = std::find_if(members.rbegin(), members.rend(), [&](const Item& m) { return m.key == key; });
    if (hit != members.rend())
      return checked(text.substr(0, hit->value.begin) + compactJson(value) + text.substr(hit->value.end),
                     expected, source);
  }
  // The first key of path + key that is missing, holding the rest.
  std::vector<std::string> full = path;
  full.push_back(key);
  const Json added = nestedUnder(full, end.depth + 1, value);
  return checked(withItemAppended(text, end.found, members,
                                  Json(full[end.depth]).dump() + ": " + compactJson(added)),
                 expected, source);
}

std::string withElementAppended(const std::string& text, const std::vector<std::string>& path,
                                const Json& element, const std::string& source) {
  Json expected = parsedOrThrow(text, source);
  const JsonScanner scanner(text);
  const PathEnd end = follow(scanner, rootOf(text, scanner, source), path);
  const bool exists = end.depth == path.size();
  if (exists ? !scanner.isArray(end.found) : !scanner.isObject(end.found))
    throw Error(fmt::format("{}: '{}' is not {}", source,
                            pointerOf({path.begin(), path.begin() + end.depth}).to_string(),
                            exists ? "an array" : "an object"));
  Json& array = expected[pointerOf(path)];
  if (array.is_null()) array = Json::array();
  array.push_back(element);
  const std::vector<Item> items = scanner.items(end.found);
  if (exists) return checked(withItemAppended(text, end.found, items, compactJson(element)), expected, source);
  const Json added = nestedUnder(path, end.depth + 1, Json::array({element}));
  return checked(withItemAppended(text, end.found, items, Json(path[end.depth]).dump() + ": " + compactJson(added)),
                 expected, source);
}

}  // namespace svr
