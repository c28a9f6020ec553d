#pragma once

#include <doctest/doctest.h>

// CAPTURE of a structured binding: doctest's CAPTURE is a lambda, and clang before 16 cannot
// capture a binding, so the value is first bound to a plain reference (which it can).
#define REEL_TEST_CAT2(a, b) a##b
#define REEL_TEST_CAT(a, b) REEL_TEST_CAT2(a, b)
#define CAPTURE_BINDING(x)                                      \
  const auto& REEL_TEST_CAT(reel_captured_, __LINE__) = (x);   \
  INFO(#x " := ", REEL_TEST_CAT(reel_captured_, __LINE__))
