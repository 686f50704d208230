#pragma once
// The random draws of the benches' corpora (scene_corpus.h, bench/backends/view_corpus.h):
// std::mt19937 mapped by hand, so a corpus entry is the same with any standard library (the
// <random> distributions are implementation-defined). An entry's draws depend only on (seed,
// index, salt); each corpus has its own salt, so one corpus's draws do not shift another's.

#include <cmath>
#include <random>
#include <utility>
#include <vector>

namespace svr {

class Draw {
 public:
  static constexpr unsigned kScenes = 0x5eedu;  // the scene corpus's salt

  Draw(unsigned seed, int index, unsigned salt = kScenes) {
    std::seed_seq seq{seed, static_cast<unsigned>(index), salt};
    rng_.seed(seq);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * (rng_() / 4294967296.0); }
  double logUniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  int integer(int lo, int hi) { return lo + static_cast<int>(rng_() % unsigned(hi - lo + 1)); }
  bool chance(double p) { return uniform(0, 1) < p; }
  template <class T>
  const T& pick(const std::vector<T>& from) { return from[integer(0, int(from.size()) - 1)]; }
  // `count` distinct entries.
  template <class T>
  std::vector<T> distinct(std::vector<T> from, int count) {
    for (int i = 0; i < count; ++i) std::swap(from[i], from[integer(i, int(from.size()) - 1)]);
    from.resize(count);
    return from;
  }

 private:
  std::mt19937 rng_;
};

}  // namespace svr
