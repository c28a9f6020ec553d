// reel: the command line (DESIGN 3).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "core/parallel.h"

namespace {

// --seed N: an integer 0..2^53-1, the range of the scene's `seed` (exact in any JSON reader).
std::optional<std::uint64_t> parseSeed(const std::string& text) {
  constexpr std::uint64_t kMax = (std::uint64_t{1} << 53) - 1;
  std::uint64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || ptr != end || v > kMax) return std::nullopt;
  return v;
}

// Every option of every subcommand, filled by the parser.
struct Cli {
  CLI::App app{"reel: physically based animation, simulated and rendered headlessly", "reel"};
  int threads = 0;
  std::string seed;
  std::vector<CLI::Option*> seed_opts;
  reel::app::SimulateOptions sim;
  std::vector<std::string> scenes;
  reel::app::RenderOptions ropt;
  std::string size;
  double still_time = -1;
  int still_frame = -1;
  std::string frames;
  bool no_overwrite = false;
  reel::app::CompareOptions cmp;
  reel::app::TestOptions topt;
  std::vector<std::string> bench_names;
  double bench_seconds = 1.0;
  std::string mass_file;   // info --mass
  std::string video_file;  // info --video
  std::vector<std::string> chunks;  // join
  std::string join_out;
  double density = 1000.0;  // info --density, kg/m³
  CLI::App *simulate = nullptr, *check = nullptr, *info = nullptr, *still = nullptr, *render = nullptr,
           *compare = nullptr, *bench = nullptr, *join = nullptr, *test = nullptr;

  void addThreads(CLI::App* sub) {
    sub->add_option("--threads", threads, "worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  }
  void addSeed(CLI::App* sub) {
    seed_opts.push_back(sub->add_option("--seed", seed, "seed of all randomness, 0..2^53-1 (default: the scene's)")
                            ->type_name("N"));
  }
  void addRenderOptions(CLI::App* sub) {
    sub->add_option("scene", ropt.scene, "scene file (reel/1 JSON)")->required();
    sub->add_option("--size", size, "image size WxH (default: the scene's)");
    sub->add_option("--samples", ropt.samples, "MSAA samples: 1, 2 or 4")->check(CLI::IsMember({1, 2, 4}));
    sub->add_option("--gl", ropt.gl, "OpenGL backend: auto, osmesa or egl (default: $REEL_GL or auto)");
    sub->add_flag("-q,--quiet", ropt.quiet, "print nothing on success, no progress on stderr");
    sub->add_flag_callback("--no-cache", [this] { ropt.cache.clear(); },
                           "neither read nor write the simulation cache (render_out/.cache)");
    sub->add_option("--cache", ropt.from, "draw the frames from the farm cache DIR that `reel simulate --cache` wrote, "
                                          "without simulating (docs/farm.md)")->type_name("DIR");
    addSeed(sub);
    addThreads(sub);
  }

  // simulate, check, info.
  void addSimulation() {
    simulate = app.add_subcommand("simulate", "simulate a scene, optionally dumping its state");
    simulate->add_option("scene", sim.scene, "scene file (reel/1 JSON)")->required();
    simulate->add_option("--dump", sim.dump, "write the state dump (reel-dump/1 JSON) here");
    simulate->add_option("--dump-every", sim.dump_every, "dump every K-th frame (first and last always)")
        ->check(CLI::Range(1, 1 << 30));
    simulate->add_flag("-q,--quiet", sim.quiet, "no progress on stderr");
    auto* cache = simulate->add_option("--cache", sim.cache, "write every frame's state into the farm cache DIR, "
                                                             "for `reel render --cache` (docs/farm.md)")->type_name("DIR");
    simulate->add_flag("--resume", sim.resume, "continue the cache after its last good frame (a new cache when there is none)")
        ->needs(cache);
    simulate->add_option("--stats", sim.stats, "write per-frame statistics of the bodies (CSV: a school's polarization, milling, centroid, nearest-neighbour distance)");
    addSeed(simulate);
    addThreads(simulate);
    check = app.add_subcommand("check", "validate scene files without simulating");
    check->add_option("scenes", scenes, "scene files")->required();
    info = app.add_subcommand("info", "versions, build type, threads; or a mesh's mass properties");
    info->add_option("--mass", mass_file, "print the volume, mass, centre of mass and inertia tensor of a closed mesh (JSON)");
    info->add_option("--density", density, "kg/m³ for --mass (default 1000)")->check(CLI::PositiveNumber);
    info->add_option("--video", video_file, "print what a video holds (codec, size, frame rate, frames, duration) as JSON");
  }

  // still, render.
  void addRendering() {
    still = app.add_subcommand("still", "render one frame to a PNG");
    addRenderOptions(still);
    auto* t_opt = still->add_option("--time", still_time, "scene time, s (the nearest frame)")->check(CLI::NonNegativeNumber);
    auto* f_opt = still->add_option("--frame", still_frame, "frame number, from 0")->check(CLI::NonNegativeNumber);
    t_opt->excludes(f_opt);
    still->add_option("-o,--output", ropt.outputs, "output PNG")->required();
    render = app.add_subcommand("render", "render a film: video and/or PNG frames");
    addRenderOptions(render);
    render->add_option("-o,--output", ropt.outputs,
                       "NAME.mp4, NAME.webm, NAME.gif or dir/name_####.png; repeatable (default: render_out/<scene>.mp4)");
    auto* range = render->add_option("--frames", frames, "render frames A-B only (frame k shows time k/fps)");
    render->add_option("--chunk", ropt.chunk, "render the I-th of K nearly equal runs of frames, I from 0 (a farm's job array)")
        ->type_name("I/K")->excludes(range);
    render->add_flag("--no-overwrite", no_overwrite, "keep valid existing PNG frames (resume)");
  }

  // compare, bench.
  void addTools() {
    compare = app.add_subcommand("compare", "compare two PNGs: exit 0 within tolerance, 1 otherwise");
    compare->add_option("a", cmp.a, "first PNG")->required();
    compare->add_option("b", cmp.b, "second PNG")->required();
    compare->add_option("--diff", cmp.diff, "write a difference image here");
    compare->add_option("--threshold", cmp.threshold, "per-channel difference that makes a pixel differ (default 16)")
        ->check(CLI::Range(0, 255));
    compare->add_option("--max-mean", cmp.max_mean, "largest mean absolute error allowed (default 1.0)")
        ->check(CLI::Range(0.0, 255.0));
    compare->add_option("--max-fraction", cmp.max_fraction, "largest fraction of differing pixels allowed (default 0.005)")
        ->check(CLI::Range(0.0, 1.0));
    compare->add_option("--min-ssim", cmp.min_ssim, "smallest mean SSIM allowed (default: not checked)")
        ->check(CLI::Range(-1.0, 1.0));
    compare->add_option("--max-flip", cmp.max_flip, "largest mean FLIP allowed, a the reference (default: not checked)")
        ->check(CLI::Range(0.0, 1.0));
    test = app.add_subcommand("test", "golden-image tests: render a suite's cases and compare each frame with its golden "
                                      "(exit 0 all within tolerance, 1 some differ or lack a golden; docs/testing.md)");
    test->add_option("suite", topt.suite, "the suite (reel-test/1 JSON)")->required();
    test->add_flag("--update", topt.update, "write the goldens that are missing or differ (never one that passes) and exit 0");
    test->add_option("--report", topt.report, "write an HTML report into DIR (DIR/index.html)")->type_name("DIR");
    test->add_option("--junit", topt.junit, "write JUnit XML here, for CI")->type_name("FILE");
    test->add_option("-j,--jobs", topt.jobs, "cases rendered at once (default 1)")->check(CLI::Range(1, 64));
    test->add_option("--gl", topt.gl, "OpenGL backend: auto, osmesa or egl (default: $REEL_GL or auto)");
    test->add_flag("-q,--quiet", topt.quiet, "print only the frames that fail, and the summary");
    test->add_option("--case", topt.cases, "run only this case (repeatable)")->type_name("NAME");
    addThreads(test);
    join = app.add_subcommand("join", "join video chunks of one film into one video without re-encoding");
    join->add_option("chunks", chunks, "the chunks (reel's chunks go in film order whatever order they are given in)")->required();
    join->add_option("-o,--output", join_out, "the joined video (same type as the chunks)")->required();
    join->add_flag("-q,--quiet", ropt.quiet, "print nothing on success");
    bench = app.add_subcommand("bench", "run benchmarks, one JSON line each");
    bench->add_option("names", bench_names,
                      "benchmarks to run (default: all): springs, render, film, cloth, fluid, school, fish, rigid, "
                      "cloth_liquid, face, cache; a scene file (*.json) is a film for `film` to render");
    bench->add_option("--frames", frames, "film: render frames A-B only (default: the whole film)");
    bench->add_option("--seconds", bench_seconds, "time spent on each measurement")->check(CLI::Range(0.01, 600.0));
    addThreads(bench);
  }

  // Checks what the parser cannot, then runs the chosen subcommand.
  int run() {
    if (threads > 0) reel::setThreadCount(threads);
    if (std::any_of(seed_opts.begin(), seed_opts.end(), [](const CLI::Option* o) { return o->count() > 0; })) {
      const auto n = parseSeed(seed);
      if (!n) {
        std::fprintf(stderr, "reel: --seed must be an integer 0..9007199254740991 (2^53 - 1), got \"%s\"\n", seed.c_str());
        return 2;
      }
      sim.seed = ropt.seed = n;
    }
    if (*simulate) return reel::app::simulate(sim);
    if (*check) return reel::app::check(scenes);
    if (*info)
      return !mass_file.empty() ? reel::app::meshMass(mass_file, density)
             : !video_file.empty() ? reel::app::videoInfo(video_file)
                                   : reel::app::info();
    if (*join) return reel::app::join(chunks, join_out, ropt.quiet);
    if (!size.empty()) {
      int w = 0, h = 0;
      char x = 0;
      if (std::sscanf(size.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 || w > 16384 || h > 16384) {
        std::fprintf(stderr, "reel: --size must be WxH with 16..16384 pixels each, got \"%s\"\n", size.c_str());
        return 2;
      }
      ropt.width = w;
      ropt.height = h;
    }
    if (*still) {
      if (still_time < 0 && still_frame < 0) {
        std::fprintf(stderr, "reel: still needs --time T or --frame K\n");
        return 2;
      }
      return reel::app::still(ropt, still_time, still_frame);
    }
    if (*render) return reel::app::render(ropt, frames, no_overwrite);
    if (*compare) return reel::app::compare(cmp);
    if (*test) return reel::app::test(topt);
    if (*bench) return reel::app::bench(bench_names, bench_seconds, frames);
    return 1;
  }
};

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (`ulimit -f`) would kill reel with SIGXFSZ and no word; ignored, the write
  // fails with EFBIG instead and is reported like a full disk (exit 4, naming the file).
  std::signal(SIGXFSZ, SIG_IGN);
  // REEL_PARALLEL_MIN=N: loops of N or more elements run in parallel (tests: 1, every parallel
  // path; the results are the same bits whatever it is).
  if (const char* pm = std::getenv("REEL_PARALLEL_MIN"))
    if (const long n = std::strtol(pm, nullptr, 10); n >= 1) reel::setParallelMin(n);
  Cli cli;
  cli.app.require_subcommand(1);
  cli.app.set_version_flag("--version", std::string(REEL_VERSION));
  cli.addSimulation();
  cli.addRendering();
  cli.addTools();
  try {
    cli.app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return cli.app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return cli.app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return cli.app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "reel: %s\n", e.what());
    std::fprintf(stderr, "run 'reel --help' for usage\n");
    return 2;
  }
  try {
    return cli.run();
  } catch (const std::bad_alloc&) {
    // What the input asks for is more than the machine gives: bad input for this machine (exit 2),
    // said as such; nothing half-written is left (outputs are written as .part files).
    std::fprintf(stderr, "reel: out of memory: the scene or the options (bodies' counts and resolutions, --size) need more "
                         "memory than this process may use; lower them or run where there is more\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reel: internal error: %s\n", e.what());
    return 1;
  }
}
