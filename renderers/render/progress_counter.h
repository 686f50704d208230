#pragma once
// Progress of one render, shared by the threads of a parallel loop: any thread may count work
// done, and only the thread that made the counter reports, so a ProgressFn is always called
// from one thread, with a fraction that never decreases. It also carries the render's stop
// request (RenderRequest::stop): a backend's parallel loops skip their remaining work units once
// stopped() — an exception cannot leave an OpenMP loop — and Renderer::render then throws
// svr::Cancelled.

#include <atomic>
#include <functional>
#include <thread>

namespace svr {

// Called with the fraction done, from one thread, often enough for a progress bar.
using ProgressFn = std::function<void(double)>;

class ProgressCounter {
 public:
  explicit ProgressCounter(ProgressFn report, const std::atomic<bool>* stop = nullptr)
      : report_(std::move(report)), owner_(std::this_thread::get_id()), stop_(stop) {}

  // Whether the render was asked to stop (any thread).
  bool stopped() const { return stop_ && stop_->load(std::memory_order_relaxed); }

  // Starts counting `units` of work that together take the fraction [from, to].
  void stage(long units, double from = 0.0, double to = 1.0) {
    units_ = units > 0 ? units : 1;
    from_ = from, to_ = to;
    done_.store(0, std::memory_order_relaxed);
  }
  // Counts units done (thread-safe); reports when called on the owning thread.
  void advance(long units = 1) {
    const long n = done_.fetch_add(units, std::memory_order_relaxed) + units;
    if (report_ && std::this_thread::get_id() == owner_)
      set(from_ + (to_ - from_) * static_cast<double>(n) / units_);
  }
  // Reports a fraction (owning thread only); lower than one already reported, it is ignored.
  void set(double fraction) {
    if (!report_ || std::this_thread::get_id() != owner_ || fraction <= shown_) return;
    shown_ = fraction > 1.0 ? 1.0 : fraction;
    report_(shown_);
  }

 private:
  ProgressFn report_;
  std::thread::id owner_;
  const std::atomic<bool>* stop_;
  std::atomic<long> done_{0};
  long units_ = 1;
  double from_ = 0.0, to_ = 1.0, shown_ = 0.0;
};

}  // namespace svr
