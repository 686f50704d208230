#include "bench/models/scene_corpus.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "base/error.h"
#include "bench/models/corpus_draw.h"
#include "renderers/volume/volume_io.h"

namespace svr {
namespace {

// A material's spectra: a reflectance from Munsell (most) or the ColorChecker; an absorption
// that is achromatic, haemoglobin's, or another chip's shape; an extinction given as the optical
// depth across the volume's diagonal.
nlohmann::json randomMaterial(Draw& draw, const SpectrumLibrary& library, double diagonal) {
  auto chip = [&] {
    return draw.chance(0.75) ? draw.pick(library.munsellNames())
                             : draw.pick(library.colorCheckerNames());
  };
  nlohmann::json m = {{"reflectance", chip()}};
  const double kind = draw.uniform(0, 1);
  if (kind < 0.45) m["absorption"] = "achromatic";
  else if (kind < 0.7) m["absorption"] = draw.chance(0.5) ? "Hb" : "HbO2";
  else m["absorption"] = chip();
  m["opacity"] = draw.logUniform(0.3, 300.0) / diagonal;
  if (draw.chance(0.35)) m["specular"] = draw.uniform(0.1, 0.6);
  if (draw.chance(0.15)) m["xray"] = true;
  return m;
}

glm::dvec3 randomDirection(Draw& draw) {
  const double z = draw.uniform(-1, 1), phi = draw.uniform(0, 2 * M_PI);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Strictly increasing values (transfer functions need them) from sorted ones.
std::vector<double> increasing(std::vector<double> v, double span) {
  std::sort(v.begin(), v.end());
  for (size_t i = 1; i < v.size(); ++i) v[i] = std::max(v[i], v[i - 1] + 1e-3 * span);
  return v;
}

}  // namespace

SceneCorpus::SceneCorpus(std::string data_dir, const SpectrumLibrary& library, unsigned seed,
                         int size)
    : data_dir_(std::move(data_dir)), library_(library), seed_(seed), size_(size) {
  for (const auto& entry : std::filesystem::directory_iterator(data_dir_ + "/volumes"))
    if (entry.path().extension() == ".nhdr") volume_files_.push_back(entry.path().string());
  std::sort(volume_files_.begin(), volume_files_.end());
  if (volume_files_.empty()) throw Error(fmt::format("{}/volumes: no .nhdr volumes", data_dir_));
}

const SceneCorpus::VolumeFacts& SceneCorpus::facts(int which) const {
  auto it = facts_.find(which);
  if (it != facts_.end()) return it->second;
  VolumeFacts f;
  f.path = std::filesystem::absolute(volume_files_[which]).lexically_normal().string();
  const Volume volume = loadVolume(f.path);
  const glm::dvec3 e = volume.extent();
  f.diagonal = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
  // Quantiles of the matter: voxels above the smallest value (air, the empty background).
  const std::vector<float> values = volume.toFloat();
  const float lowest = *std::min_element(values.begin(), values.end());
  std::vector<float> matter;
  const size_t stride = std::max<size_t>(1, values.size() / 200000);
  for (size_t i = 0; i < values.size(); i += stride)
    if (values[i] > lowest) matter.push_back(values[i]);
  if (matter.empty()) matter.push_back(lowest);
  std::sort(matter.begin(), matter.end());
  for (int q = 0; q <= 100; ++q)
    f.quantiles.push_back(matter[std::min(matter.size() - 1, matter.size() * q / 100)]);
  return facts_.emplace(which, std::move(f)).first->second;
}

std::string SceneCorpus::name(int index) const { return fmt::format("corpus/{}/{}", seed_, index); }

nlohmann::json SceneCorpus::sceneJson(int index) const {
  Draw draw(seed_, index);
  const VolumeFacts& v = facts(draw.integer(0, int(volume_files_.size()) - 1));
  auto quantile = [&](double q) {
    const double x = std::clamp(q, 0.0, 1.0) * 100;
    const int i = std::min(99, static_cast<int>(x));
    return v.quantiles[i] + (x - i) * (v.quantiles[i + 1] - v.quantiles[i]);
  };
  const double span = std::max(1e-6, v.quantiles.back() - v.quantiles.front());

  nlohmann::json j;
  j["description"] = fmt::format("{} (issue 40's stress corpus)", name(index));
  j["volume"] = {{"file", v.path}};
  const int materials = draw.integer(1, 5);
  std::vector<double> at;
  for (int i = 0; i < materials; ++i) {
    j["materials"][fmt::format("m{}", i)] = randomMaterial(draw, library_, v.diagonal);
    at.push_back(quantile(draw.uniform(0.05, 0.995)));
  }
  at = increasing(at, span);
  nlohmann::json points = nlohmann::json::array();
  for (int i = 0; i < materials; ++i) points.push_back({at[i], fmt::format("m{}", i)});
  const double q0 = draw.uniform(0.02, 0.7);
  const std::vector<double> ramp =
      increasing({quantile(q0), quantile(q0 + draw.uniform(0.02, 0.2))}, span);
  j["transfer_function"] = {
      {"type", "scalar"},
      {"points", points},
      {"opacity", {{ramp[0], 0.0}, {ramp[1], 1.0}}}};

  const int lights = draw.integer(1, 8);
  const std::vector<std::string> names = draw.distinct(library_.lightNames(), lights);
  j["lights"] = names;
  if (lights >= 2 && draw.chance(0.5))
    j["light_mixes"]["mix"] = {{names[0], draw.uniform(0.2, 1.0)},
                               {names[1], draw.uniform(0.2, 1.0)}};
  const glm::dvec3 d = randomDirection(draw);
  j["light_direction"] = {d.x, d.y, d.z};
  j["camera"] = {{"azimuth", draw.uniform(-180, 180)}, {"elevation", draw.uniform(-70, 70)}};
  if (draw.chance(0.3)) j["background"] = draw.pick(library_.munsellNames());
  j["image"] = {{"width", size_}, {"height", size_}};
  j["render"] = {{"step", 0.5}};
  return j;
}

Scene SceneCorpus::scene(int index) const {
  return parseScene(sceneJson(index), name(index), library_);
}

}  // namespace svr
