// Progress on stderr (frames done, frames/s, time left). On a terminal one line redrawn in place;
// otherwise (a log file, a render farm's job output) a plain line every few seconds and one at
// the end, so a long run shows it is alive. --quiet silences both.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace reel::app {

class Progress {
 public:
  // Seconds between plain lines when stderr is not a terminal.
  static constexpr double kLogInterval = 5.0;

  Progress(int total, bool quiet, const char* what = "frame")
      : total_(total), what_(what), tty_(isatty(STDERR_FILENO) != 0), on_(!quiet && total > 0), t0_(Clock::now()) {}
  void update(int done) {
    if (!on_) return;
    const double s = std::chrono::duration<double>(Clock::now() - t0_).count();
    const double rate = s > 0 ? done / s : 0.0;
    const double left = rate > 0 ? (total_ - done) / rate : 0.0;
    if (tty_) {
      std::fprintf(stderr, "\r  %s %d/%d  %.1f frames/s  %.0f s left   ", what_, done, total_, rate, left);
      if (done == total_) std::fprintf(stderr, "\n");
      return;
    }
    if (done < total_ && s < next_) return;
    next_ = s + kLogInterval;
    std::fprintf(stderr, "reel: %s %d/%d (%.0f%%), %.2f frames/s, %.0f s elapsed, %.0f s left\n", what_, done, total_,
                 100.0 * done / total_, rate, s, left);
    std::fflush(stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;
  int total_;
  const char* what_;
  bool tty_, on_;
  double next_ = kLogInterval;
  Clock::time_point t0_;
};

}  // namespace reel::app
