#pragma once
// What a backend is and supports, in one value its registry entry carries. The harness, the
// tests and the benches read this instead of backend names: a comparison skips a backend that
// cannot take its camera, with a note; a bench leaves out backends that need a GL context; and
// `svr render --help-options` prints the options from here.

#include <optional>
#include <string>
#include <vector>

#include "renderers/render/backend_options.h"

namespace svr {

struct Camera;

struct BackendCapabilities {
  bool perspective = true;             // perspective cameras (else orthographic only)
  bool spectral_transmittance = true;  // k-channel T (else scalar absorbers only)
  int max_channels = 128;              // the largest k
  bool needs_gl = false;               // needs an OpenGL context (OSMesa or EGL)
  // Renders one brick of a distributed render (ClassifiedVolume::brick): samples the whole
  // grid's lattice and takes only the brick's own samples.
  bool bricks = false;
  // Takes RenderRequest::front: stops a brick's rays where the whole render stops them.
  bool front_transmittance = false;
  // The backend the harness's reference and auto's probe render with (one in the registry):
  // the others are measured against it.
  bool reference = false;
};

struct BackendInfo {
  std::string name;     // the registry key: "raycast"
  std::string summary;  // one line for --help-options
  BackendCapabilities supports;
  std::vector<OptionSpec> options;
};

// Why this backend cannot render a view with this camera and these channel counts, or nothing.
std::optional<std::string> unsupportedBy(const BackendInfo& backend, const Camera& camera, int k,
                                         int t_channels);

}  // namespace svr
