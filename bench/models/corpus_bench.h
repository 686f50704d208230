#pragma once
// What the corpus benches (svr_model_bench, svr_backend_bench) share: a private model cache, the
// quantiles of their tables, quoted CSV fields, and a main that reports an error and exits 2.

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace svr {

// XDG_CACHE_HOME pointed at a folder of this process's own, removed at the end: models are
// trained afresh, as a first-time user's would be, and reused within the run as the user's cache
// would reuse them.
class PrivateModelCache {
 public:
  explicit PrivateModelCache(const std::string& bench)
      : folder_(std::filesystem::temp_directory_path() / fmt::format("{}_{}", bench, getpid())) {
    setenv("XDG_CACHE_HOME", folder_.c_str(), 1);
  }
  ~PrivateModelCache() {
    std::error_code ignored;
    std::filesystem::remove_all(folder_, ignored);
  }
  PrivateModelCache(const PrivateModelCache&) = delete;
  PrivateModelCache& operator=(const PrivateModelCache&) = delete;

 private:
  std::filesystem::path folder_;
};

// The q-quantile (nearest rank) of v; NaN for none.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

// A CSV field in quotes, its own quotes doubled.
inline std::string csvField(std::string text) {
  for (size_t q = 0; (q = text.find('"', q)) != std::string::npos; q += 2) text.insert(q, 1, '"');
  return "\"" + text + "\"";
}

// bench_main(argc, argv), with any exception reported as "BENCH: what" and exit status 2.
template <class Main>
int runCorpusBench(const char* bench, Main bench_main, int argc, char** argv) {
  try {
    return bench_main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << bench << ": " << e.what() << "\n";
    return 2;
  }
}

}  // namespace svr
