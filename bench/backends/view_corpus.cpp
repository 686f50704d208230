#include "bench/backends/view_corpus.h"

#include <fmt/format.h>

#include "bench/models/corpus_draw.h"

namespace svr {
namespace {

constexpr unsigned kViews = 0x49u;  // this corpus's salt (issue 49)

}  // namespace

ViewCorpus::ViewCorpus(const SceneCorpus& scenes, const SpectrumLibrary& library, unsigned seed)
    : scenes_(scenes), library_(library), seed_(seed) {}

std::string ViewCorpus::name(int index) const { return fmt::format("views/{}/{}", seed_, index); }

nlohmann::json ViewCorpus::sceneJson(int index) const {
  Draw draw(seed_, index, kViews);
  nlohmann::json j = scenes_.sceneJson(index);
  j["description"] = fmt::format("{}: {} from another view (issue 49's view corpus)", name(index),
                                 scenes_.name(index));
  const double azimuth = draw.uniform(-180, 180), elevation = draw.uniform(-85, 85);
  const double zoom = draw.uniform(1, 3);
  const double fov = draw.chance(0.5) ? draw.uniform(20, 45) : 0.0;
  j["camera"] = {{"azimuth", azimuth}, {"elevation", elevation}, {"zoom", zoom}, {"fov", fov}};
  const int side = draw.integer(96, 128);
  j["image"] = {{"width", side}, {"height", side}};
  return j;
}

Scene ViewCorpus::scene(int index) const {
  return parseScene(sceneJson(index), name(index), library_);
}

std::string ViewCorpus::describe(int index) const {
  const nlohmann::json j = sceneJson(index);
  const double fov = j["camera"]["fov"];
  return fmt::format("{} zoom {:.2f}, {}²",
                     fov > 0 ? fmt::format("perspective {:.0f}°", fov) : "orthographic",
                     j["camera"]["zoom"].get<double>(), j["image"]["width"].get<int>());
}

}  // namespace svr
