#include "harness/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

namespace svr {

Progress::Progress(std::string label, int total, bool quiet)
    : label_(std::move(label)),
      total_(total),
      enabled_(!quiet && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {
  if (enabled_) draw("");
}

Progress::~Progress() {
  if (enabled_) fmt::print(stderr, "\r\033[K");
}

void Progress::advance(const std::string& detail) {
  ++done_;
  if (enabled_) draw(detail);
}

void Progress::draw(const std::string& detail) {
  constexpr int kWidth = 30;
  const int filled = total_ > 0 ? done_ * kWidth / total_ : 0;
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  fmt::print(stderr, "\r\033[K{} [{:<{}}] {}/{} {:.0f}s {}", label_, std::string(filled, '#'),
             kWidth, done_, total_, secs, detail);
  std::fflush(stderr);
}

}  // namespace svr
