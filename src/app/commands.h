// The reel commands. Each returns the process exit code (DESIGN 3); only main() exits.
#pragma once

#include <string>
#include <vector>

#include "core/error.h"

namespace reel::app {

// Prints an Error's lines to stderr ("reel: ..." each) and returns its exit code.
int report(const Error& e);

struct SimulateOptions {
  std::string scene;
  std::string dump;  // empty: no dump
  int dump_every = 1;
};
int simulate(const SimulateOptions& opt);
int check(const std::vector<std::string>& scenes);
int info();
int bench(const std::vector<std::string>& names, double seconds);

}  // namespace reel::app
