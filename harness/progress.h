#pragma once
// A one-line progress bar on stderr, drawn only when stderr is a terminal and not silenced.

#include <chrono>
#include <string>

namespace svr {

class Progress {
 public:
  Progress(std::string label, int total, bool quiet);
  ~Progress();
  void advance(const std::string& detail = {});

 private:
  void draw(const std::string& detail);
  std::string label_;
  int total_, done_ = 0;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace svr
