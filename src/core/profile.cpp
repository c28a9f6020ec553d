#include "core/profile.h"

namespace reel::profile {
namespace {

using Clock = std::chrono::steady_clock;
Seconds g_totals{};
Stage g_current = Stage::Other;
Clock::time_point g_mark;

// Charges the time since the last mark to the current stage.
void charge() {
  const Clock::time_point now = Clock::now();
  g_totals[static_cast<std::size_t>(g_current)] += std::chrono::duration<double>(now - g_mark).count();
  g_mark = now;
}

}  // namespace

namespace detail {
bool g_on = false;
thread_local bool t_muted = false;

void enter(Stage s, Stage& previous) {
  charge();
  previous = g_current;
  g_current = s;
}

void leave(Stage previous) {
  charge();
  g_current = previous;
}
}  // namespace detail

void enable(bool on) {
  if (on) {
    g_totals = {};
    g_current = Stage::Other;
    g_mark = Clock::now();
  } else if (detail::g_on) {
    charge();
  }
  detail::g_on = on;
}

bool enabled() { return detail::g_on; }

Seconds totals() {
  if (detail::g_on) charge();
  return g_totals;
}

}  // namespace reel::profile
