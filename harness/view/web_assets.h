#pragma once
// The viewer's page (harness/view/web/: HTML, JS, CSS), embedded in the binary at build time
// (cmake/EmbedFiles.cmake), so `svr view` and `svr render --html` work from any folder and
// nothing is fetched from the internet.

#include <string_view>

namespace svr {

struct WebAsset {
  std::string_view path;          // "index.html", "viewer.js", …
  std::string_view content_type;  // "text/html; charset=utf-8", …
  std::string_view bytes;
};

// The asset at this path, or nullptr.
const WebAsset* findWebAsset(std::string_view path);

}  // namespace svr
