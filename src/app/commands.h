// The reel commands. Each returns the process exit code (DESIGN 3); only main() exits.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"
#include "core/profile.h"

namespace reel::app {

// Prints an Error's lines to stderr ("reel: ..." each) and returns its exit code.
int report(const Error& e);

struct SimulateOptions {
  std::string scene;
  std::string dump;  // empty: no dump
  int dump_every = 1;
  std::string stats;  // empty: no statistics file (CSV, io/stats.h)
  std::optional<std::uint64_t> seed;  // --seed: replaces the scene's
  bool quiet = false;  // no progress on stderr
  std::string cache;   // --cache DIR: write every frame's state there (app/farm_cache.h)
  bool resume = false;  // --resume: continue DIR's cache after its last good frame
};
int simulate(const SimulateOptions& opt);
int check(const std::vector<std::string>& scenes);
// `reel info --mass FILE`: the mass properties of a closed mesh at a density (kg/m³) as one JSON
// object: volume (m³), mass (kg), center_of_mass (m) and inertia (kg·m², about the centre of mass
// in the mesh's axes). An open, inside-out or self-intersecting mesh is refused (exit 2).
int meshMass(const std::string& file, double density);

struct RenderOptions {
  std::string scene;
  std::vector<std::string> outputs;
  int width = 0, height = 0;  // 0: the scene's size
  int samples = 0;            // 0: the scene's
  std::string gl;             // "", auto, osmesa, egl
  std::optional<std::uint64_t> seed;  // --seed: replaces the scene's
  bool quiet = false;         // print nothing on success, no progress
  std::string cache = "render_out/.cache";  // the simulation cache's folder; empty: none (app/sim_cache.h)
  std::string chunk;  // --chunk I/K: the frames of one chunk of K (chunkFrames)
  std::string from;  // --cache DIR: draw the frames from the farm cache there, never simulating
};
int still(const RenderOptions& opt, double time, int frame);
// Frames `frames` of opt.scene (at opt's size, samples and seed) as images in that order, the
// scene simulated once (the simulation cache applies); a frame outside the film is BadInput.
Status renderFrames(const RenderOptions& opt, const std::vector<int>& frames, std::vector<Image>& out);

// Where a render's time went (reel bench film): the busy seconds of each of the pipeline's three
// threads, which overlap, the simulation's split by stage (core/profile.h), and the wall time.
struct FilmTimes {
  std::string scene;  // its name
  int width = 0, height = 0, samples = 0;
  int frames = 0;
  double setup = 0;  // s: loading the scene, building the world, opening GL and the outputs
  double simulate = 0, draw = 0, encode = 0, total = 0;  // s
  profile::Seconds stages{};
};
// `times`: measure the stages into it (profiling on for the run).
int render(const RenderOptions& opt, const std::string& frames, bool no_overwrite, FilmTimes* times = nullptr);

struct CompareOptions {
  std::string a, b, diff;
  int threshold = 16;         // a pixel differs when a channel differs by more than this
  double max_mean = 1.0;      // tolerance: mean absolute error (0..255)
  double max_fraction = 0.005;  // tolerance: fraction of differing pixels
  double min_ssim = -1.0;       // tolerance: mean SSIM (default: not checked)
  double max_flip = 1.0;        // tolerance: mean FLIP, a the reference (default: not checked)
};
int compare(const CompareOptions& o);

// `reel test SUITE.json` (docs/testing.md): exit 0 when every frame is within its tolerance, 1
// when one differs, has no golden or does not render, 2 for a bad suite, 4 for an output error.
struct TestOptions {
  std::string suite;
  bool update = false;  // write missing and differing goldens (never one that passes); exit 0
  std::string report;   // a folder for the HTML report; empty: none
  std::string junit;    // a JUnit XML file; empty: none
  int jobs = 1;         // cases at once
  std::string gl;       // OpenGL backend
  bool quiet = false;   // print only what fails, and the summary
  std::vector<std::string> cases;  // --case NAME (repeatable): only these; empty: all
};
int test(const TestOptions& o);
int info();
// `reel info --video FILE`: what a video holds, as one JSON object.
int videoInfo(const std::string& file);
// `reel join CHUNK... -o OUT`: chunks of one film into one video without re-encoding.
int join(const std::vector<std::string>& chunks, const std::string& output, bool quiet);
// --chunk I/K: the I-th of K nearly equal runs of the film's N frames, as "A-B" (exit 2 if bad).
Result<std::string> chunkFrames(const std::string& chunk, int frames);
// `names`: benchmarks, or scene files (*.json) for `film`; `frames`: A-B, the film's frames only.
int bench(const std::vector<std::string>& names, double seconds, const std::string& frames = "");

}  // namespace reel::app
