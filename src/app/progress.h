// Progress on stderr (frames done, frames/s, time left), only when it is a terminal: quiet in
// pipes and CI.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace reel::app {

class Progress {
 public:
  explicit Progress(int total) : total_(total), on_(isatty(STDERR_FILENO) != 0), t0_(Clock::now()) {}
  void update(int done) {
    if (!on_) return;
    const double s = std::chrono::duration<double>(Clock::now() - t0_).count();
    const double rate = s > 0 ? done / s : 0.0;
    const double left = rate > 0 ? (total_ - done) / rate : 0.0;
    std::fprintf(stderr, "\r  frame %d/%d  %.1f frames/s  %.0f s left   ", done, total_, rate, left);
    if (done == total_) std::fprintf(stderr, "\n");
  }

 private:
  using Clock = std::chrono::steady_clock;
  int total_;
  bool on_;
  Clock::time_point t0_;
};

}  // namespace reel::app
