#pragma once
// Long calls into the library from Python (render, compare): the GIL released for their whole
// length, so other Python threads run and two renders run at once; Ctrl-C and the caller's
// progress callback handled on the calling thread, which is the one a backend reports progress
// from (renderers/render/progress_counter.h). A pending KeyboardInterrupt, or an exception from
// the callback, sets the render's stop flag; the backend skips its remaining work, and the
// Python exception is raised once the call has unwound.

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <optional>

#include "renderers/render/progress_counter.h"
#include "base/error.h"

namespace svr::python {

namespace py = pybind11;

class ReleasedCall {
 public:
  // progress: a Python callable taking the fraction done, or None.
  explicit ReleasedCall(py::object progress) : callback_(std::move(progress)) {}

  // Runs body(ProgressFn, const std::atomic<bool>* stop) without the GIL; then raises what a
  // signal handler or the callback raised, if anything did.
  template <class Body>
  void run(Body&& body) {
    {
      py::gil_scoped_release released;
      try {
        body(progressFn(), &stop_);
      } catch (const Cancelled&) {
        if (!pending_) throw;
      }
    }
    if (pending_) throw std::move(*pending_);
  }

 private:
  // Signals are looked at every kSignalCheck at most when there is no callback: each look
  // takes the GIL, and a render of a few milliseconds need not look at all.
  static constexpr std::chrono::milliseconds kSignalCheck{20};

  ProgressFn progressFn() {
    return [this](double fraction) {
      if (stop_.load(std::memory_order_relaxed)) return;
      const auto now = std::chrono::steady_clock::now();
      const bool call = !callback_.is_none();
      if (!call && now - last_check_ < kSignalCheck) return;
      last_check_ = now;
      py::gil_scoped_acquire held;
      try {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (call) callback_(fraction);
      } catch (py::error_already_set& e) {
        pending_.emplace(std::move(e));
        stop_.store(true, std::memory_order_relaxed);
      }
    };
  }

  py::object callback_;
  std::atomic<bool> stop_{false};
  std::optional<py::error_already_set> pending_;
  std::chrono::steady_clock::time_point last_check_ = std::chrono::steady_clock::now();
};

}  // namespace svr::python
