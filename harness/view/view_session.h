#pragma once
// What `svr view` serves (issue 20): one scene loaded, classified and kept for the server's
// life, its lights as relighting matrices, and renders of any orbit view of it as the
// light-independent image. Thread-safe: the HTTP server calls it from its worker threads.
//
// Renders run one at a time (a renderer uses every core). A newer view request supersedes the
// older ones: a request still waiting when a newer one arrives is answered "superseded" without
// rendering, and one whose frame finishes after a newer request arrived is answered so too (its
// frame is dropped: the newer view is already on its way). Backends have no cancellation
// points, so a frame that has started runs to its end; frames take tens of milliseconds.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/error.h"
#include "harness/render_session.h"
#include "harness/view/page_data.h"
#include "renderers/classification/classification.h"
#include "renderers/scene/camera.h"
#include "renderers/scene/scene.h"
#include "renderers/volume/memory_budget.h"
#include "spectral/light_independent_image.h"

namespace svr {

struct ViewOptions {
  std::string scene, renderer = "shearwarp", model, data_dir;
  std::vector<std::string> options;  // BACKEND.KEY=VALUE
  bool read_only = false;            // refuse to save mixes into the scene file
  std::uint64_t memory_budget = defaultMemoryBudget();  // voxels, and each frame with its work
};

// The scene file changed on disk since the session loaded it (or last saved a mix into it): a
// mix is not saved over it (the server answers 409).
struct SceneFileChanged : Error {
  using Error::Error;
};

struct ViewRequest {
  OrbitView view;
  int width = 0, height = 0;
  std::optional<SampleStorage> samples;  // empty: the session's choice (chooseSamples)
};

struct ViewFrame {
  LightIndependentImage image;  // in the storage asked for
  double render_ms = 0;
  std::uint64_t sequence = 0;   // the request's place in arrival order
};

class ViewSession {
 public:
  // Limits on what one request may ask for, so that memory stays bounded: a side, and the
  // values of one frame, planes × pixels (2048² × 32: 512 MiB as floats). A model of many planes
  // (spectral:81 with spectral absorbers: 162) is served at a smaller size.
  static constexpr int kMaxSide = 2048;
  static constexpr std::int64_t kMaxFrameValues = std::int64_t{2048} * 2048 * 32;
  // The page relights with one mat4x3 uniform (four vectors) per texture layer of four planes,
  // and WebGL2 guarantees 224 fragment uniform vectors: 56 layers, 224 planes.
  static constexpr int kMaxPlanes = 224;

  // Loads, classifies, and renders the initial view once (which decides half or float samples,
  // chooseSamples) and a tiny frame along each axis: that builds what the backend keeps per
  // classification and axis before the first request.
  explicit ViewSession(const ViewOptions& options);

  // The scene's lights (each as a 3 × planes matrix to linear sRGB, unit luminance, the
  // backdrop folded in), its mixes, the model and the initial view, as /api/scene gives them.
  const nlohmann::json& sceneInfo() const { return scene_info_; }
  // A library spectrum as a light: {"name", "matrix"}; svr::Error for an unknown name.
  nlohmann::json libraryLight(const std::string& name) const;
  // The frame, or empty when a newer request superseded this one. svr::Error when it fails.
  std::optional<ViewFrame> render(const ViewRequest& request);
  // Adds the mix {light name: weight} to the scene file as light_mixes[name], adding library
  // lights the scene lacks to its lights. Only those two entries of the file's text change
  // (harness/view/json_text_edit.h); the write is atomic. svr::Error for bad names or weights;
  // SceneFileChanged when the file is no longer the text the session knows. The server refuses
  // to call it when started --read-only (403).
  void saveMix(const std::string& name, const std::vector<std::pair<std::string, double>>& weights);

  bool readOnly() const { return options_.read_only; }
  const Scene& scene() const { return session_->scene(); }
  const ClassifiedVolume& classified() const { return session_->classified(); }
  const ViewOptions& options() const { return options_; }
  const OrbitView& initialView() const { return initial_view_; }

 private:
  PageLightContext lightContext() const;

  ViewOptions options_;
  std::string scene_text_;  // the scene file as loaded, then as last saved (under file_mutex_)
  std::unique_ptr<RenderSession> session_;  // the scene, its model and classification, the backend
  OrbitView initial_view_;
  SampleChoice samples_;
  nlohmann::json scene_info_;

  std::mutex render_mutex_;
  std::atomic<std::uint64_t> latest_{0};
  std::mutex file_mutex_;
};

}  // namespace svr
