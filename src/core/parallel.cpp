#include "core/parallel.h"

#include <omp.h>

namespace reel {

int threadCount() { return omp_get_max_threads(); }
void setThreadCount(int n) { omp_set_num_threads(n); }

}  // namespace reel
