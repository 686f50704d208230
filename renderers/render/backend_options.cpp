#include "renderers/render/backend_options.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <stdexcept>

#include "base/error.h"
#include "base/json_reader.h"

namespace svr {

OptionSpec OptionSpec::integer(std::string key, int fallback, int lo, int hi, std::string help) {
  return {std::move(key), Kind::kInteger, double(fallback), double(lo), double(hi), {},
          std::move(help)};
}

OptionSpec OptionSpec::number(std::string key, double fallback, double lo, double hi,
                              std::string help) {
  return {std::move(key), Kind::kNumber, fallback, lo, hi, {}, std::move(help)};
}

OptionSpec OptionSpec::choice(std::string key, std::vector<std::string> choices,
                              std::string help) {
  return {std::move(key), Kind::kChoice, 0.0, 0.0, 0.0, std::move(choices), std::move(help)};
}

std::string OptionSpec::describe() const {
  std::string type;
  switch (kind) {
    case Kind::kInteger:
      type = fmt::format("integer in {}..{}, default {}", lo, hi, fallback);
      break;
    case Kind::kNumber:
      type = fmt::format("number in {}..{}, default {}", lo, hi, fallback);
      break;
    case Kind::kChoice:
      type = fmt::format("{}, default {}", fmt::join(choices, " | "), choices.front());
      break;
  }
  return fmt::format("{:<12} {}: {}", key, type, help);
}

const nlohmann::json& BackendOptions::value(const std::string& key, OptionSpec::Kind kind) const {
  const auto it = values_.find(key);
  if (it == values_.end() || it->second.first != kind)
    throw std::logic_error(fmt::format("backend option '{}' is not in its backend's description",
                                       key));
  return it->second.second;
}

int BackendOptions::integer(const std::string& key) const {
  return value(key, OptionSpec::Kind::kInteger).get<int>();
}

double BackendOptions::number(const std::string& key) const {
  return value(key, OptionSpec::Kind::kNumber).get<double>();
}

const std::string& BackendOptions::choice(const std::string& key) const {
  return value(key, OptionSpec::Kind::kChoice).get_ref<const std::string&>();
}

nlohmann::json BackendOptions::toJson() const {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [key, typed] : values_) out[key] = typed.second;
  return out;
}

BackendOptions readBackendOptions(const std::vector<OptionSpec>& specs,
                                  const nlohmann::json& options, const std::string& backend,
                                  const std::string& where) {
  static const nlohmann::json kNone = nlohmann::json::object();
  const bool given = options.is_object() && options.contains(backend);
  const JsonReader r(given ? options.at(backend) : kNone, where, backend);
  if (!r.isObject()) r.fail(fmt::format("expected an object of options, got {}", r.json().dump()));
  BackendOptions out;
  for (const OptionSpec& spec : specs) {
    nlohmann::json value;
    switch (spec.kind) {
      case OptionSpec::Kind::kInteger:
        value = r.integer(spec.key, static_cast<int>(spec.fallback), static_cast<int>(spec.lo),
                          static_cast<int>(spec.hi));
        break;
      case OptionSpec::Kind::kNumber:
        value = r.number(spec.key, spec.fallback, spec.lo, spec.hi);
        break;
      case OptionSpec::Kind::kChoice: {
        const std::string v = r.string(spec.key, spec.choices.front());
        if (std::find(spec.choices.begin(), spec.choices.end(), v) == spec.choices.end())
          r.at(spec.key).fail(fmt::format("'{}' is not one of {}", v, fmt::join(spec.choices, ", ")));
        value = v;
        break;
      }
    }
    out.values_[spec.key] = {spec.kind, std::move(value)};
  }
  if (specs.empty() && !r.keys().empty())
    r.fail(fmt::format("takes no options, got {}", r.json().dump()));
  r.rejectUnknownKeys();
  return out;
}

OptionAssignment parseOptionAssignment(const std::string& text, const std::string& flag) {
  const auto dot = text.find('.'), eq = text.find('=');
  if (dot == std::string::npos || eq == std::string::npos || dot == 0 || eq < dot + 2)
    throw Error(fmt::format("{} '{}': expected BACKEND.KEY=VALUE, e.g. splat.mode=sheet", flag,
                            text));
  const std::string value = text.substr(eq + 1);
  nlohmann::json parsed = nlohmann::json::parse(value, nullptr, false);
  return {text.substr(0, dot), text.substr(dot + 1, eq - dot - 1),
          parsed.is_discarded() ? nlohmann::json(value) : parsed};
}

}  // namespace svr
