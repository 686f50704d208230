#include "harness/view/standalone_page.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <vector>

#include "base/error.h"
#include "harness/view/frame_format.h"
#include "harness/view/web_assets.h"

namespace svr {

namespace {

std::string asset(const std::string& path) {
  const WebAsset* a = findWebAsset(path);
  if (!a) throw Error(fmt::format("render --html: the page's '{}' is not built in", path));
  return std::string(a->bytes);
}

// A script or style sheet to inline: a closing tag inside would end its element early.
std::string inlined(const std::string& path) {
  std::string text = asset(path);
  if (text.find("</script") != std::string::npos || text.find("</style") != std::string::npos)
    throw Error(fmt::format("render --html: the page's '{}' contains a closing tag", path));
  return text;
}

std::string base64(const std::string& bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3), '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()),
                                reinterpret_cast<const unsigned char*>(bytes.data()),
                                static_cast<int>(bytes.size()));
  out.resize(static_cast<size_t>(n));
  return out;
}

void replaceOnce(std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos)
    throw Error(fmt::format("render --html: the page has no '{}' to fill", from));
  text.replace(at, from.size(), to);
}

// Inside <script>, "</" would end the element: JSON escapes it as "<\/".
std::string scriptSafe(std::string json) {
  for (size_t at = 0; (at = json.find("</", at)) != std::string::npos; at += 3) json.replace(at, 2, "<\\/");
  return json;
}

}  // namespace

std::string standalonePage(const nlohmann::json& scene_info, const LightIndependentImage& image) {
  std::string page = asset("index.html");
  replaceOnce(page, R"(<link rel="stylesheet" href="viewer.css">)",
              "<style>\n" + inlined("viewer.css") + "</style>");
  const nlohmann::json header = {{"width", image.width()},
                                 {"height", image.height()},
                                 {"channels", image.channels()},
                                 {"t_channels", image.transmittanceChannels()},
                                 {"render_ms", 0}};
  const std::string data = fmt::format(
      "<script>\nwindow.SVR_EMBEDDED = {{info: {}, frame: \"{}\"}};\n</script>\n",
      scriptSafe(scene_info.dump()), base64(encodeFrame(image, header)));
  // Every script index.html loads, inlined where its tag was, in order; the frame before them.
  const std::string open = R"(<script src=")", close = R"("></script>)";
  bool first = true;
  for (size_t at = 0; (at = page.find(open, at)) != std::string::npos;) {
    const size_t end = page.find(close, at);
    if (end == std::string::npos)
      throw Error("render --html: the page has an unterminated script tag");
    const std::string script = page.substr(at + open.size(), end - at - open.size());
    const std::string inline_script =
        (first ? data : "") + "<script>\n" + inlined(script) + "</script>";
    page.replace(at, end + close.size() - at, inline_script);
    at += inline_script.size();
    first = false;
  }
  return page;
}

}  // namespace svr
