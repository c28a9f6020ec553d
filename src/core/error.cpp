#include "core/error.h"

namespace reel {

void failCheck(const char* file, int line, const char* cond, const std::string& msg) {
  throw InternalError(std::string(file) + ":" + std::to_string(line) + ": check failed: " + cond +
                      (msg.empty() ? "" : ": " + msg));
}

}  // namespace reel
