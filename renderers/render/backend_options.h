#pragma once
// A backend's options, described once: key, type, default, range and a one-line help. The same
// description reads and checks render.options (and --option, --variant, sweep parameters),
// prints `svr render --help-options`, and is the only place a default lives, so a header comment
// can no longer disagree with the code.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace svr {

struct OptionSpec {
  enum class Kind { kInteger, kNumber, kChoice };
  std::string key;
  Kind kind = Kind::kNumber;
  double fallback = 0.0;             // kInteger, kNumber
  double lo = 0.0, hi = 0.0;         // kInteger, kNumber: the closed range
  std::vector<std::string> choices;  // kChoice: the first is the default
  std::string help;

  static OptionSpec integer(std::string key, int fallback, int lo, int hi, std::string help);
  static OptionSpec number(std::string key, double fallback, double lo, double hi,
                           std::string help);
  static OptionSpec choice(std::string key, std::vector<std::string> choices, std::string help);

  // "sigma      number in 0.25..4, default 0.55: kernel σ in voxels"
  std::string describe() const;
};

// The values of one backend's options: given ones checked against their spec, defaults for the
// rest. Asking for a key the spec does not list is a programming error (std::logic_error).
class BackendOptions {
 public:
  int integer(const std::string& key) const;
  double number(const std::string& key) const;
  const std::string& choice(const std::string& key) const;
  // What was read, defaults included: render.json and report.json record it.
  nlohmann::json toJson() const;

 private:
  friend BackendOptions readBackendOptions(const std::vector<OptionSpec>&, const nlohmann::json&,
                                           const std::string&, const std::string&);
  const nlohmann::json& value(const std::string& key, OptionSpec::Kind kind) const;
  std::map<std::string, std::pair<OptionSpec::Kind, nlohmann::json>> values_;
};

// Reads options[backend] (options: {"backend": {"key": value}}) against the specs. A wrong type,
// a value out of range, an unknown choice or an unknown key is an svr::Error that names `where`
// ("scene.json: render.options"), the key path and the value.
BackendOptions readBackendOptions(const std::vector<OptionSpec>& specs,
                                  const nlohmann::json& options, const std::string& backend,
                                  const std::string& where = "render.options");

// "splat.mode=sheet" → {"splat", "mode", "sheet"}; values that parse as JSON (numbers,
// true/false) keep their type. `flag` ("--option") names the source in errors.
struct OptionAssignment {
  std::string backend, key;
  nlohmann::json value;
};
OptionAssignment parseOptionAssignment(const std::string& text, const std::string& flag);

}  // namespace svr
