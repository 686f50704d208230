#pragma once
// svr's public C++ API (issue 50; docs/api.md): the route from a scene to a frame.
//
//   svr::Session session = svr::Session::fromFile("engine.json", {.model = "factor:6"});
//   session.render();                                   // the light-independent image
//   session.relight("D65").savePng("engine_d65.png");   // any light, after the render
//
// A session loads a scene (from a file, or from JSON text built in code), trains or takes its
// colour model, classifies the volume and renders one light-independent image with a backend.
// Relighting it under any light or mix of lights is then a 3 × k matrix per pixel: no render.
// Everything here throws svr::Error with a message naming the file, key and value.
//
// Link with svr::svr (CMake: find_package(svr CONFIG)) or `pkg-config --cflags --libs svr`.

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "svr/error.h"

namespace svr {

// What a session renders with; empty or zero fields take the scene's own.
struct RenderSettings {
  std::string renderer = "raycast";  // raycast, shearwarp, splat, or gl (where built)
  std::string model;                 // rgb, factor:k, spectral:n or auto; empty: the scene's
  int width = 0, height = 0;         // pixels; 0: the scene's image size
  std::vector<std::string> options;  // backend options, "BACKEND.KEY=VALUE"
  std::string data_dir;              // spectra and volumes; empty: svr's own (installed)
};

// 8-bit sRGB, interleaved RGB, row 0 at the top.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // 3 · width · height bytes

  void savePng(const std::string& path) const;  // written whole or not at all
};

class Session {
 public:
  static Session fromFile(const std::string& scene_file, const RenderSettings& settings = {});
  // A scene written in code: `scene_json` is a scene file's text; relative paths in it are
  // taken from `base_dir`.
  static Session fromJson(const std::string& scene_json, const std::string& base_dir,
                          const RenderSettings& settings = {});

  Session(Session&&) noexcept;
  Session& operator=(Session&&) noexcept;
  ~Session();

  // Renders the light-independent image (the relight calls render first when it is missing).
  void render();

  int width() const;
  int height() const;
  std::string modelName() const;     // the model rendered with: "factor:6", "rgb", …
  std::string rendererName() const;
  int imagePlanes() const;           // the image's planes: k S channels, then the T channels
  // The scene's lights, then its mixes, by name.
  std::vector<std::string> lights() const;

  // The image relit under a scene light or mix, or any library spectrum by name ("D65", "F11",
  // "LED-B3"), at unit luminance; the scene's backdrop shows through where the volume is thin.
  RgbImage relight(const std::string& light);
  // Under a mix: light name → weight (each light at unit luminance).
  RgbImage relight(const std::vector<std::pair<std::string, double>>& mix);

 private:
  struct State;
  explicit Session(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

// "0.1.0"
std::string version();

}  // namespace svr
