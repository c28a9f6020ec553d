// Reading a golden-image test suite ("format": "reel-test/1", docs/testing.md). Every error of
// the file at once, each with its JSON path; unknown keys with the nearest known one; a scene
// that is not there named with its path.
#pragma once

#include <string>

#include "core/error.h"
#include "core/test_suite.h"

namespace reel::io {

inline constexpr std::size_t kMaxSuiteBytes = 16u << 20;
inline constexpr std::size_t kMaxSuiteCases = 10000;
inline constexpr std::size_t kMaxCaseFrames = 10000;

Result<TestSuite> loadTestSuite(const std::string& path);

}  // namespace reel::io
