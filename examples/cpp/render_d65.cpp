// Renders a scene with the factor:6 model, relights it under D65 and writes a PNG.
//   render_d65 SCENE.json OUT.png
#include <svr/svr.h>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s SCENE.json OUT.png\n", argv[0]);
    return 2;
  }
  try {
    svr::RenderSettings settings;
    settings.model = "factor:6";
    svr::Session session = svr::Session::fromFile(argv[1], settings);
    session.render();  // the light-independent image, once
    session.relight("D65").savePng(argv[2]);
    std::printf("svr %s: %s, %d×%d, %s with %d planes → %s\n", svr::version().c_str(),
                session.rendererName().c_str(), session.width(), session.height(),
                session.modelName().c_str(), session.imagePlanes(), argv[2]);
  } catch (const svr::Error& e) {
    std::fprintf(stderr, "render_d65: %s\n", e.what());
    return 2;
  }
  return 0;
}
