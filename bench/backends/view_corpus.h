#pragma once
// Issue 49's view corpus: the scenes of issue 40's stress corpus (bench/models/scene_corpus.h)
// seen the way users look at them — from any side (azimuth −180…180°, elevation −85…85°),
// zoomed 1–3×, with an orthographic camera or, half the time, a perspective one (fov 20–45°),
// at 96–128 pixels square. View `index` is corpus scene `index` with a camera and size drawn
// from (seed, index) alone, so any slice is reproducible by itself.

#include <nlohmann/json.hpp>
#include <string>

#include "bench/models/scene_corpus.h"

namespace svr {

class ViewCorpus {
 public:
  ViewCorpus(const SceneCorpus& scenes, const SpectrumLibrary& library, unsigned seed);

  // The scene file view `index` would be: the corpus scene with the view's camera and size.
  nlohmann::json sceneJson(int index) const;
  Scene scene(int index) const;
  std::string name(int index) const;  // "views/<seed>/<index>"
  // "perspective 31° zoom 2.4, 112²": how the bench's CSV describes the view.
  std::string describe(int index) const;

 private:
  const SceneCorpus& scenes_;
  const SpectrumLibrary& library_;
  unsigned seed_;
};

}  // namespace svr
