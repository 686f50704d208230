// The OSMesa context and the GL plumbing of the gl backend: version, error reporting (shader
// logs, incomplete framebuffers), and creation and teardown without leaks.

#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <vector>
#include <string>

#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_framebuffer.h"
#include "renderers/gl/gl_program.h"
#include "base/error.h"

namespace svr {
namespace {

TEST(GlContext, ShaderCompileErrorCarriesTheLog) {
  const gl::GlContext context;
  const gl::GlContext::Current current(context);
  try {
    gl::GlProgram program(context, "broken",
                          {{GL_FRAGMENT_SHADER, "#version 450 core\nvoid main() { nope(); }\n"}});
    FAIL() << "compiled";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("program 'broken': the fragment shader does not compile"),
              std::string::npos) << what;
    EXPECT_NE(what.find("nope"), std::string::npos) << what;  // the driver's log
  }
}

TEST(GlContext, IncompleteFramebufferIsAnError) {
  const gl::GlContext context;
  const gl::GlContext::Current current(context);
  GLuint fbo = 0;
  context.api().CreateFramebuffers(1, &fbo);  // no attachment
  try {
    gl::checkFramebufferComplete(context, fbo, "empty");
    FAIL() << "complete";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "framebuffer 'empty' is incomplete: GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT"),
              std::string::npos)
        << e.what();
  }
  context.api().DeleteFramebuffers(1, &fbo);
}

TEST(GlContext, IsOpenGl45Core) {
  const gl::GlContext context;
  EXPECT_NE(context.description().find("Core Profile"), std::string::npos)
      << context.description();
  EXPECT_GE(context.limits().max_draw_buffers, 8);
  EXPECT_GE(context.limits().max_dual_source_buffers, 1);
}

// Resident memory (kB) and thread count of this process, from /proc/self/status.
std::pair<long, long> residentKbAndThreads() {
  std::ifstream status("/proc/self/status");
  long rss = -1, threads = -1;
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) rss = std::stol(line.substr(6));
    if (line.rfind("Threads:", 0) == 0) threads = std::stol(line.substr(8));
  }
  return {rss, threads};
}

// 100 contexts created, used (a program, a 16 MiB framebuffer cleared and read back) and
// destroyed: resident memory grows by less than four contexts' worth and the thread count
// returns to where it was. A live context holds ≈ 16 MB (three live ones measured +32 MB, the
// allocator reusing one's pages; checked below), so leaking all 100 would add ≈ 1.6 GB;
// measured after the loop: +16 MB, the allocator keeping freed pages. The sanitize preset runs
// the same loop under LeakSanitizer.
TEST(GlContext, CreateAndDestroy100TimesLeaksNothing) {
  const auto cycle = [] {
    const gl::GlContext context;
    const gl::GlContext::Current current(context);
    gl::GlProgram program(context, "trivial",
                          {{GL_VERTEX_SHADER,
                            "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n"},
                           {GL_FRAGMENT_SHADER,
                            "#version 450 core\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n"}});
    // 16 MiB of render target, written: a context (or target) that outlived its owner would
    // show in the resident size.
    gl::LayeredTarget target(context, 512, 512, 4, "scratch");
    target.drawInto(0, 4);
    target.clear(0.5f, 1.f);
    std::vector<float> rgba;
    target.read(3, 0, 0, 64, 64, rgba);
    ASSERT_EQ(rgba[5], 0.5f);
  };
  for (int i = 0; i < 5; ++i) cycle();  // first-use allocations (shader cache, LLVM) settle
  const auto [rss_before, threads_before] = residentKbAndThreads();
  {
    // The check's sensitivity: contexts kept alive do show. Three at once, as the allocator
    // reuses the pages the warm-up freed for the first.
    std::vector<std::unique_ptr<gl::GlContext>> contexts;
    std::vector<std::unique_ptr<gl::LayeredTarget>> targets;
    for (int i = 0; i < 3; ++i) {
      contexts.push_back(std::make_unique<gl::GlContext>());
      const gl::GlContext::Current current(*contexts.back());
      targets.push_back(std::make_unique<gl::LayeredTarget>(*contexts.back(), 512, 512, 4, "live"));
      targets.back()->drawInto(0, 4);
      targets.back()->clear(0.f, 0.f);
      std::vector<float> rgba;
      targets.back()->read(3, 0, 0, 64, 64, rgba);  // runs the queued clear
    }
    const long rss_live = residentKbAndThreads().first;
    std::printf("[ measured ] three live contexts: resident %+ld kB\n", rss_live - rss_before);
    // Measured +16 to +32 MiB depending on how much of the warm-up's pages the allocator
    // reuses; a leak in the 100 cycles below would hold 100 targets of 16 MiB.
    EXPECT_GT(rss_live - rss_before, 12 * 1024);
    for (std::size_t i = 0; i < contexts.size(); ++i) {
      const gl::GlContext::Current current(*contexts[i]);
      targets[i].reset();
    }
  }
  for (int i = 0; i < 100; ++i) cycle();
  const auto [rss_after, threads_after] = residentKbAndThreads();
  std::printf("[ measured ] 100 contexts: resident %+ld kB, threads %ld → %ld\n",
              rss_after - rss_before, threads_before, threads_after);
  EXPECT_EQ(threads_after, threads_before);
  EXPECT_LT(rss_after - rss_before, 64 * 1024);
}

}  // namespace
}  // namespace svr
