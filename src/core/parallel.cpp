#include "core/parallel.h"

#include <omp.h>

#include <sys/auxv.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>

namespace reel {

namespace {
std::atomic<std::ptrdiff_t> g_parallel_min{kParallelMin};
thread_local std::ptrdiff_t t_scope_min = 0;  // a ParallelScope's threshold on this thread (0: none)
}  // namespace

std::ptrdiff_t parallelMin() {
  return t_scope_min > 0 ? t_scope_min : g_parallel_min.load(std::memory_order_relaxed);
}
void setParallelMin(std::ptrdiff_t n) { g_parallel_min.store(n < 1 ? 1 : n, std::memory_order_relaxed); }

ParallelScope::ParallelScope(std::ptrdiff_t work) : saved_(t_scope_min) {
  if (work < 0) return;
  const std::ptrdiff_t global = g_parallel_min.load(std::memory_order_relaxed);
  t_scope_min = work >= std::max<std::ptrdiff_t>(1, global / 4) ? std::min(kScopeMin, global) : PTRDIFF_MAX;
}
ParallelScope::~ParallelScope() { t_scope_min = saved_; }

int threadCount() { return omp_get_max_threads(); }
void setThreadCount(int n) { omp_set_num_threads(n); }

namespace {

// OpenMP threads that wait for work spin at most 1000 times (microseconds), then sleep. A thread
// that spins long (libgomp's default: 300,000 spins) takes a core from whatever else runs on a
// shared machine (a render farm node), and on a loaded machine the spinning and the work fight
// for the same cores: 0.3 s of the flag scene took 18 s at 2 threads against 2 s at 1. Sleeping
// at once (OMP_WAIT_POLICY=PASSIVE, GOMP_SPINCOUNT 0) costs a wake-up per parallel loop, and under
// load each wake-up waits for a core: a plain 64² implicit sheet took 8.6 s loaded and 1.2 s idle
// passive, 2.7 s and 0.66 s with the short spin (docs/engine.md, "Threads"). OpenMP has no call
// that sets this, and libgomp reads GOMP_SPINCOUNT when it loads, before main; an environment set
// before main is reset by the C library's own start-up. So before anything else runs
// (.preinit_array: before every library's initialisers), a process without OMP_WAIT_POLICY or
// GOMP_SPINCOUNT starts itself again with GOMP_SPINCOUNT=1000 added: nothing has happened yet,
// so nothing is lost but one exec. A user's own setting (or one set for a debugger or valgrind)
// is kept and skips this.
void waitPassively(int, char** argv, char** env) {
  // Started through the dynamic loader ("ld.so ./reel ..."): the executable is the loader, and
  // starting it again would lose its options. Leave such a run as it is.
  if (getauxval(AT_BASE) == 0) return;
  constexpr std::size_t kMax = 4096;
  static char* next[kMax + 2];
  static char policy[] = "GOMP_SPINCOUNT=1000";
  static char exe[4096];
  std::size_t n = 0;
  for (char** e = env; e && *e; ++e) {
    if (std::strncmp(*e, "OMP_WAIT_POLICY=", 16) == 0 || std::strncmp(*e, "GOMP_SPINCOUNT=", 15) == 0 || n == kMax)
      return;
    next[n++] = *e;
  }
  next[n++] = policy;
  next[n] = nullptr;
  // The executable by its real path, so that the process keeps its name ("reel", not "exe").
  const ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len <= 0 || static_cast<std::size_t>(len) >= sizeof exe - 1) return;
  exe[len] = '\0';
  execve(exe, argv, next);  // returns only when it fails: then the runtime's default
}

}  // namespace

}  // namespace reel

// (An executable's pre-initialisers: this object is in every reel executable, since the app and
// the tests set the thread count.)
__attribute__((section(".preinit_array"), used)) static void (*const reel_wait_passively)(int, char**, char**) =
    &reel::waitPassively;
