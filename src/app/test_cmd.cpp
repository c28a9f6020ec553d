// reel test SUITE.json: golden-image tests as a product (docs/testing.md). Each case's scene is
// simulated once and the listed frames rendered; each frame is compared with its golden image
// by four limits (mean error, differing pixels, SSIM, FLIP); --update writes missing and differing
// goldens and never touches one that passes; --report writes an HTML report, --junit JUnit XML.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include "app/body_kinds.h"
#include "app/commands.h"
#include "app/test_report.h"
#include "core/format.h"
#include "core/image_metrics.h"
#include "io/files.h"
#include "io/json_reader.h"
#include "io/png.h"
#include "io/test_suite.h"

namespace reel::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A case checked against its scene: the frames it renders, and their times.
struct Planned {
  const TestCase* c = nullptr;
  std::vector<int> frames;
  std::vector<double> times;
};

// Every case's scene loaded and its frames checked against the film, before anything renders:
// every error at once.
Status plan(const TestSuite& suite, std::vector<Planned>& out) {
  std::vector<std::string> errors;
  for (const TestCase& c : suite.cases) {
    auto scene = loadScene(c.scene);
    if (!scene.ok()) {
      errors.push_back(suite.file + ": " + c.where + ": the scene " + c.scene + " does not load:");
      for (const std::string& m : scene.error().messages) errors.push_back("  " + m);
      continue;
    }
    const int n = scene.value().frameCount(), fps = scene.value().fps;
    Planned p;
    p.c = &c;
    for (std::size_t i = 0; i < c.frames.size(); ++i) {
      if (c.frames[i] >= n)
        errors.push_back(suite.file + ": " + c.where + "/frames/" + std::to_string(i) + ": frame " +
                         std::to_string(c.frames[i]) + " is outside the film (frames 0.." + std::to_string(n - 1) + " of " +
                         c.scene + ")");
      p.frames.push_back(c.frames[i]);
    }
    for (std::size_t i = 0; i < c.times.size(); ++i) {
      const double k = std::round(c.times[i] * fps);
      if (k > n - 1) {
        errors.push_back(suite.file + ": " + c.where + "/times/" + std::to_string(i) + ": " + formatNumber(c.times[i], 6) +
                         " s is outside the film (0 to " + formatNumber((n - 1) / static_cast<double>(fps), 6) + " s of " +
                         c.scene + ")");
        continue;
      }
      p.frames.push_back(static_cast<int>(k));
    }
    for (int k : p.frames) p.times.push_back(static_cast<double>(k) / fps);
    out.push_back(std::move(p));
  }
  if (!errors.empty()) return Error(ErrorKind::BadInput, std::move(errors));
  return {};
}

// A picture shrunk by whole-pixel boxes to at most `width` pixels wide (report thumbnails).
Image shrink(const Image& im, int width) {
  const int f = std::max(1, (im.width + width - 1) / width);
  if (f == 1) return im;
  Image out(im.width / f, im.height / f);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 3; ++c) {
        int s = 0;
        for (int j = 0; j < f; ++j)
          for (int i = 0; i < f; ++i) s += im.pixel(x * f + i, y * f + j)[c];
        out.pixel(x, y)[c] = static_cast<std::uint8_t>((s + f * f / 2) / (f * f));
      }
  return out;
}

// The comparison of one rendered frame with its golden: the verdict and the limits broken.
void judge(const Image& actual, const Image& expected, FrameOutcome& o, std::vector<float>* flip_map) {
  const Tolerance& t = o.tolerance;
  o.diff = compareImages(actual, expected, t.threshold);
  o.ssim = ssim(expected, actual);
  const FlipResult f = flip(expected, actual, kFlipPpd, flip_map);
  o.flip = f.mean;
  o.flip_max = f.max;
  if (o.diff.mean_abs > t.max_mean) o.broken.push_back("mean error");
  if (o.diff.over_fraction > t.max_fraction) o.broken.push_back("differing pixels");
  if (o.ssim < t.min_ssim) o.broken.push_back("SSIM");
  if (o.flip > t.max_flip) o.broken.push_back("FLIP");
  o.verdict = o.broken.empty() ? FrameOutcome::Verdict::Pass : FrameOutcome::Verdict::Fail;
}

struct Runner {
  const TestOptions& opt;
  const TestSuite& suite;
  std::vector<std::vector<FrameOutcome>> results;  // per case
  Status output;                                   // the first output error
  std::mutex mutex;
  const std::vector<Planned>* planned = nullptr;
  std::vector<char> done;  // per case
  std::size_t printed = 0;

  void fail(const Status& st) {
    std::lock_guard lock(mutex);
    if (output.ok()) output = st;
  }

  // Writes a report picture; its name relative to the report's folder ("" without a report).
  std::string picture(const Image& im, const std::string& name) {
    if (opt.report.empty()) return "";
    const std::string rel = "images/" + name;
    if (Status st = io::writePng(opt.report + "/" + rel, im, {}, 6); !st) {
      fail(st);
      return "";
    }
    return rel;
  }

  void runCase(const Planned& p) {
    const TestCase& c = *p.c;
    const auto t0 = Clock::now();
    RenderOptions ro;
    ro.scene = c.scene;
    ro.width = c.width;
    ro.height = c.height;
    ro.samples = c.samples;
    ro.seed = c.seed;
    ro.gl = opt.gl;
    ro.quiet = true;
    std::vector<Image> images;
    const Status rendered = renderFrames(ro, p.frames, images);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    std::vector<FrameOutcome> out;
    for (std::size_t i = 0; i < p.frames.size(); ++i) {
      FrameOutcome o;
      o.test_case = c.name;
      o.scene = c.scene;
      o.frame = p.frames[i];
      o.time = p.times[i];
      o.tolerance = c.tolerance;
      o.seconds = seconds / static_cast<double>(p.frames.size());
      const std::string golden_file = goldenName(c.name, o.frame);
      const std::string golden = suite.goldens + "/" + golden_file;
      o.golden = golden;
      const std::string stem = golden_file.substr(0, golden_file.size() - 4);
      if (!rendered) {
        o.verdict = FrameOutcome::Verdict::Error;
        for (const std::string& m : rendered.error().messages) o.message += (o.message.empty() ? "" : "; ") + m;
        out.push_back(std::move(o));
        continue;
      }
      const Image& actual = images[i];
      std::error_code ec;
      std::optional<Image> expected;
      if (fs::exists(golden, ec)) {
        auto read = io::readPng(golden);
        if (read.ok()) expected = std::move(read.value());
        else o.message = "the golden " + golden + " does not read: " + read.error().messages.front();
      } else {
        o.message = "no golden " + golden + (opt.update ? "" : " (`reel test --update` writes it)");
      }
      std::vector<float> map;
      if (!expected) {
        o.verdict = FrameOutcome::Verdict::Missing;
      } else if (expected->width != actual.width || expected->height != actual.height) {
        o.verdict = FrameOutcome::Verdict::Fail;
        o.message = "the golden is " + std::to_string(expected->width) + "x" + std::to_string(expected->height) +
                    ", the render " + std::to_string(actual.width) + "x" + std::to_string(actual.height);
        o.broken.push_back("size");
        o.diff.mean_abs = 255;
        o.diff.over_fraction = 1;
        o.ssim = -1;
        o.flip = o.flip_max = 1;
      } else {
        judge(actual, *expected, o, opt.report.empty() ? nullptr : &map);
      }
      if (!o.passed() && opt.update) {
        if (Status st = io::writePng(golden, actual, {{"Software", std::string("reel ") + REEL_VERSION},
                                                      {"reel:test", suite.name + "/" + c.name},
                                                      {"reel:frame", std::to_string(o.frame)}}, 9);
            !st)
          fail(st);
        else
          o.updated = true;
      }
      if (!opt.report.empty()) {
        if (o.passed()) {
          o.thumbnail = picture(shrink(actual, 180), stem + ".thumb.png");
        } else {
          o.actual = picture(actual, stem + ".actual.png");
          if (expected) o.expected = picture(*expected, stem + ".expected.png");
          if (!map.empty()) o.difference = picture(heatmap(map, actual.width, actual.height, &*expected), stem + ".diff.png");
        }
      }
      out.push_back(std::move(o));
    }
    // Printed in suite order: this case's lines wait for the cases before it.
    std::lock_guard lock(mutex);
    const auto index = static_cast<std::size_t>(&p - &planned->front());
    results[index] = std::move(out);
    done[index] = 1;
    for (; printed < results.size() && done[printed]; ++printed)
      for (const FrameOutcome& o : results[printed]) print(o);
    std::fflush(stdout);
  }

  void print(const FrameOutcome& o) const {
    if (opt.quiet && o.passed()) return;
    const char* word = o.passed() ? "pass" : o.updated ? "updated" : o.verdict == FrameOutcome::Verdict::Fail ? "FAIL"
                                            : o.verdict == FrameOutcome::Verdict::Missing ? "MISSING" : "ERROR";
    const bool measured = (o.verdict == FrameOutcome::Verdict::Pass || o.verdict == FrameOutcome::Verdict::Fail) &&
                          std::find(o.broken.begin(), o.broken.end(), "size") == o.broken.end();
    std::printf("%-8s %s, frame %d: %s\n", word, o.test_case.c_str(), o.frame,
                measured ? (metricsLine(o) + (o.message.empty() ? "" : "; " + o.message)).c_str() : o.message.c_str());
  }
};

}  // namespace

int test(const TestOptions& opt) {
  const auto t0 = Clock::now();
  auto loaded = io::loadTestSuite(opt.suite);
  if (!loaded.ok()) return report(loaded.error());
  TestSuite& suite = loaded.value();
  // --case: only the cases named, each of which must be in the suite.
  if (!opt.cases.empty()) {
    std::vector<std::string> names, errors;
    for (const TestCase& c : suite.cases) names.push_back(c.name);
    for (const std::string& want : opt.cases)
      if (std::find(names.begin(), names.end(), want) == names.end()) {
        const std::string near = io::nearest(want, names);
        errors.push_back(suite.file + ": --case " + want + ": no such case" + (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
      }
    if (!errors.empty()) return report(Error(ErrorKind::BadInput, std::move(errors)));
    std::erase_if(suite.cases, [&](const TestCase& c) {
      return std::find(opt.cases.begin(), opt.cases.end(), c.name) == opt.cases.end();
    });
  }
  std::vector<Planned> planned;
  if (Status st = plan(suite, planned); !st) return report(st.error());
  for (const std::string& out : {opt.report.empty() ? std::string() : opt.report + "/index.html", opt.junit})
    if (!out.empty())
      if (Status st = io::checkOutputTarget(out); !st) return report(st.error());
  Runner run{opt, suite, {}, {}, {}, &planned, {}, 0};
  run.results.resize(planned.size());
  run.done.assign(planned.size(), 0);
  // Cases in parallel, each on its own thread with its own GL context, taken in suite order.
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < planned.size();) run.runCase(planned[i]);
  };
  const int jobs = std::clamp(opt.jobs, 1, static_cast<int>(planned.size()));
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  std::vector<FrameOutcome> all;
  for (auto& r : run.results)
    for (FrameOutcome& o : r) all.push_back(std::move(o));
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!opt.report.empty())
    if (Status st = writeHtmlReport(opt.report, suite, all); !st) run.fail(st);
  if (!opt.junit.empty())
    if (Status st = writeJunit(opt.junit, suite, all, seconds); !st) run.fail(st);
  if (!run.output.ok()) return report(run.output.error());
  int failed = 0, missing = 0, errors = 0, updated = 0;
  for (const FrameOutcome& o : all) {
    failed += o.verdict == FrameOutcome::Verdict::Fail;
    missing += o.verdict == FrameOutcome::Verdict::Missing;
    errors += o.verdict == FrameOutcome::Verdict::Error;
    updated += o.updated;
  }
  std::printf("%s: %zu frames of %zu cases: %zu passed, %d differ, %d without a golden, %d did not render%s (%.1f s)\n",
              suite.name.c_str(), all.size(), planned.size(), all.size() - static_cast<std::size_t>(failed + missing + errors),
              failed, missing, errors,
              opt.update ? (", " + std::to_string(updated) + " goldens written to " + suite.goldens).c_str() : "", seconds);
  if (!opt.report.empty()) std::printf("report: %s/index.html\n", opt.report.c_str());
  if (errors > 0) return 1;
  if (opt.update) return 0;
  return failed + missing > 0 ? 1 : 0;
}

}  // namespace reel::app
