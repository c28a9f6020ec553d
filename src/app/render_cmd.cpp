// reel still / reel render: simulate, draw each frame headlessly, write PNGs.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <optional>
#include <thread>

#include "app/body_kinds.h"
#include "app/commands.h"
#include "app/farm_cache.h"
#include "app/progress.h"
#include "app/sim_cache.h"
#include "core/format.h"
#include "core/hash.h"
#include "core/image_compare.h"
#include "core/image_metrics.h"
#include "core/scene_view.h"
#include "core/queue.h"
#include "io/files.h"
#include "io/png.h"
#include "io/video.h"
#include "render/gl/context.h"
#include "render/renderer.h"
#include "sim/world.h"

namespace reel::app {

Result<gl::Backend> chooseBackend(const std::string& flag) {
  std::string name = flag;
  if (name.empty()) {
    const char* env = std::getenv("REEL_GL");
    name = env && *env ? env : "auto";
  }
  gl::Backend b;
  if (!gl::parseBackend(name, b))
    return Error(ErrorKind::BadInput, "unknown GL backend \"" + name + "\" (auto, osmesa or egl)");
  return b;
}

namespace {

struct Setup {
  SceneDesc scene;
  std::unique_ptr<World> world;
  std::unique_ptr<gl::Context> ctx;
  std::unique_ptr<Renderer> renderer;
};

Status setup(const RenderOptions& opt, Setup& s) {
  auto scene = loadScene(opt.scene);
  if (!scene.ok()) return scene.error();
  s.scene = std::move(scene.value());
  if (opt.width > 0) {
    s.scene.render.width = opt.width;
    s.scene.render.height = opt.height;
  }
  if (opt.samples > 0) s.scene.render.samples = opt.samples;
  if (opt.seed) s.scene.seed = *opt.seed;
  auto world = makeWorld(s.scene);
  if (!world.ok()) return world.error();
  s.world = std::make_unique<World>(std::move(world.value()));
  auto backend = chooseBackend(opt.gl);
  if (!backend.ok()) return backend.error();
  auto ctx = gl::createContext(backend.value());
  if (!ctx.ok()) return ctx.error();
  s.ctx = std::move(ctx.value());
  RenderSettings rs;
  rs.width = s.scene.render.width;
  rs.height = s.scene.render.height;
  rs.samples = s.scene.render.samples;
  auto r = Renderer::create(*s.ctx, rs, findShaderDir());
  if (!r.ok()) return r.error();
  s.renderer = std::move(r.value());
  return {};
}

// The simulation cache of the scene (after it is loaded: the key covers its assets), unless off.
std::optional<SimCache> openCache(const RenderOptions& opt, int frames) {
  std::optional<SimCache> cache;
  if (!opt.cache.empty()) cache.emplace(opt.cache, opt.scene, opt.seed, frames);
  return cache;
}

// --cache DIR: the farm cache of this scene (after it is loaded: the manifest covers its assets),
// checked to hold frames [first, last].
Status openFarmCache(const RenderOptions& opt, const Setup& s, int first, int last, CacheReader& reader) {
  auto want = CacheManifest::of(opt.scene, s.scene);
  if (!want.ok()) return want.error();
  if (Status st = reader.open(opt.from, want.value()); !st) return st;
  if (last >= reader.frames())
    return Error(ErrorKind::BadInput, opt.from + ": frames " + std::to_string(first) + "-" + std::to_string(last) +
                                          " are not all in the cache (it holds " +
                                          (reader.frames() ? "frames 0-" + std::to_string(reader.frames() - 1) : "no frames") +
                                          " of " + std::to_string(s.scene.frameCount()) + "; finish it with `reel simulate " +
                                          opt.scene + " --cache " + opt.from + " --resume`)");
  return {};
}

// What tells a film's chunks from another film's (io::ChunkTag::film): the scene file's bytes, the
// seed, the picture's size and samples, the frame rate.
std::string filmId(const RenderOptions& opt, const Setup& s) {
  Hasher h;
  auto text = io::readFile(opt.scene, std::size_t{64} << 20);
  if (text.ok()) h.add(text.value().data(), text.value().size());
  const SceneDesc& d = s.scene;
  for (const long long v : {static_cast<long long>(d.seed), static_cast<long long>(d.render.width),
                            static_cast<long long>(d.render.height), static_cast<long long>(d.render.samples),
                            static_cast<long long>(d.fps)})
    h.add(&v, sizeof v);
  return h.hex();
}

io::TextChunks pngText(const Setup& s, int frame) {
  return {{"Software", std::string("reel ") + REEL_VERSION},
          {"reel:scene", s.scene.name},
          {"reel:frame", std::to_string(frame)},
          {"reel:seed", std::to_string(s.scene.seed)},
          {"reel:gl", std::string(s.ctx->backend()) + ": " + s.ctx->renderer()}};
}

// What to draw of the world's current frame: the scene's view (its camera moved by the World's
// rig) and the world's geometry.
DrawList frameList(const Setup& s) {
  DrawList list;
  setSceneView(s.scene, s.world->time(), list, s.world->cameraRig());
  s.world->draw(list);
  return list;
}

}  // namespace

namespace {

// Draws frames `ks` (ascending, within the film) of the set-up scene, handing each image to `take`
// as it is made: the world simulates forward once, from the farm cache (--cache) or the nearest
// frame the simulation cache holds.
template <class Take>
Status drawFrames(const RenderOptions& opt, Setup& s, const std::vector<int>& ks, Take&& take) {
  if (ks.empty()) return {};
  const int n = s.scene.frameCount();
  // With motion blur the shutter opens on frame k − 1: its draw list goes with frame k's.
  const bool blur = s.scene.render.shutter_deg > 0.0;
  CacheReader farm;
  if (!opt.from.empty())
    if (Status st = openFarmCache(opt, s, blur ? std::max(0, ks.front() - 1) : ks.front(), ks.back(), farm); !st) return st;
  std::optional<SimCache> cache = opt.from.empty() ? openCache(opt, n) : std::nullopt;
  if (cache) cache->restoreNearest(*s.world, blur && ks.front() > 0 ? ks.front() - 1 : ks.front());
  Progress progress(ks.back() - s.world->frame(), opt.quiet, "simulating frame");
  int done = 0;
  for (const int k : ks) {
    std::shared_ptr<const DrawList> before;
    const bool open_before = blur && k > 0;
    if (!opt.from.empty()) {
      if (open_before) {
        if (Status st = farm.restore(*s.world, k - 1); !st) return st;
        before = std::make_shared<const DrawList>(frameList(s));
      }
      if (Status st = farm.restore(*s.world, k); !st) return st;
    }
    while (s.world->frame() < k) {
      if (open_before && s.world->frame() == k - 1) before = std::make_shared<const DrawList>(frameList(s));
      if (Status st = s.world->advanceFrame(); !st) return st;
      if (cache) cache->offer(*s.world, s.world->frame() == k);
      progress.update(++done);
    }
    DrawList list = frameList(s);
    list.previous = before;
    Image img;
    if (Status st = s.renderer->draw(list, img); !st) return st;
    if (Status st = take(k, std::move(img)); !st) return st;
  }
  return {};
}

}  // namespace

int still(const RenderOptions& opt, double time, int frame) {
  Setup s;
  if (Status st = setup(opt, s); !st) return report(st.error());
  const int n = s.scene.frameCount();
  // A time is checked in seconds before it becomes a frame number (1e20 s has no int frame).
  const double kt = std::round(time * s.scene.fps);
  if (frame < 0 && !(kt >= 0 && kt <= n - 1))
    return report(Error(ErrorKind::BadInput, "--time " + formatNumber(time, 6) + " s is outside the film (0 to " +
                                                 formatNumber((n - 1) / static_cast<double>(s.scene.fps), 6) + " s)"));
  const int k = frame >= 0 ? frame : static_cast<int>(kt);
  if (k < 0 || k >= n)
    return report(Error(ErrorKind::BadInput, "frame " + std::to_string(k) + " is outside the film (frames 0.." +
                                                 std::to_string(n - 1) + ")"));
  const Status st = drawFrames(opt, s, {k}, [&](int, Image img) { return io::writePng(opt.outputs.at(0), img, pngText(s, k)); });
  return st ? 0 : report(st.error());
}

Status renderFrames(const RenderOptions& opt, const std::vector<int>& frames, std::vector<Image>& out) {
  Setup s;
  if (Status st = setup(opt, s); !st) return st;
  const int n = s.scene.frameCount();
  for (int k : frames)
    if (k < 0 || k >= n)
      return Error(ErrorKind::BadInput, opt.scene + ": frame " + std::to_string(k) + " is outside the film (frames 0.." +
                                            std::to_string(n - 1) + ")");
  std::vector<int> ks = frames;
  std::sort(ks.begin(), ks.end());
  ks.erase(std::unique(ks.begin(), ks.end()), ks.end());
  std::vector<Image> drawn;
  if (Status st = drawFrames(opt, s, ks, [&](int, Image img) { drawn.push_back(std::move(img)); return Status{}; }); !st)
    return st;
  out.clear();
  for (int k : frames) out.push_back(drawn[static_cast<std::size_t>(std::lower_bound(ks.begin(), ks.end(), k) - ks.begin())]);
  return {};
}

namespace {

// An output named by its form: a video file, or a PNG pattern with a run of '#' (frame k is file
// k + 1, zero-padded to the run's width).
struct Output {
  std::string path;
  bool video = false;
  std::size_t hash_pos = 0, hash_len = 0;
  std::unique_ptr<io::VideoWriter> writer;
  std::string framePath(int k) const {
    std::string num = std::to_string(k + 1);
    if (num.size() < hash_len) num.insert(0, hash_len - num.size(), '0');
    return path.substr(0, hash_pos) + num + path.substr(hash_pos + hash_len);
  }
};

Status parseOutput(const std::string& p, Output& o) {
  o.path = p;
  if (io::isVideoPath(p)) {
    o.video = true;
    return {};
  }
  std::string name = std::filesystem::path(p).filename().string();
  for (auto& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::size_t at = p.find('#');
  if (name.size() > 4 && name.substr(name.size() - 4) == ".png" && at != std::string::npos &&
      at >= p.size() - name.size()) {
    o.hash_pos = at;
    o.hash_len = p.find_first_not_of('#', at) - at;
    return {};
  }
  return Error(ErrorKind::BadInput, "output \"" + p + "\": expected NAME.mp4, NAME.webm, NAME.gif or a PNG pattern such as dir/name_####.png");
}

// A PNG already there from an earlier run, complete and of the right size.
bool validFrame(const std::string& path, int w, int h) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // (a FIFO would block the read)
  auto img = io::readPng(path);
  return img.ok() && img.value().width == w && img.value().height == h;
}


struct FrameImage {
  int k = 0;
  Image img;
};

// --frames A-B, within the film's N frames.
Status frameRange(const std::string& range, int n, int& first, int& last) {
  first = 0;
  last = n - 1;
  if (!range.empty()) {
    int a = -1, b = -1, used = 0;
    char dash = 0;
    if (std::sscanf(range.c_str(), "%d%c%d%n", &a, &dash, &b, &used) != 3 || dash != '-' ||
        used != static_cast<int>(range.size()) || a < 0 || b < a || b >= n)
      return Error(ErrorKind::BadInput, "--frames must be A-B with 0 <= A <= B <= " + std::to_string(n - 1) +
                                                   " (frame k shows time k/fps), got \"" + range + "\"");
    first = a;
    last = b;
  }
  return {};
}

// The outputs by their form; missing folders are created (a video's when it opens; a PNG
// pattern's now, so that an uncreatable one fails before any frame is simulated: '#' is only in
// the file name); videos open.
Status openOutputs(const RenderOptions& opt, const Setup& s, bool no_overwrite, const io::ChunkTag& tag,
                   std::vector<Output>& outs) {
  std::vector<std::string> paths = opt.outputs;
  if (paths.empty()) paths.push_back("render_out/" + io::safeFileName(s.scene.name) + ".mp4");
  outs.resize(paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i)
    if (Status st = parseOutput(paths[i], outs[i]); !st) return st;
  for (const auto& o : outs)
    if (!o.video)
      if (Status st = io::createParentFolders(o.path); !st) return st;
  const int W = s.scene.render.width, H = s.scene.render.height;
  for (auto& o : outs) {
    if (!o.video) continue;
    std::error_code ec;
    if (no_overwrite && std::filesystem::exists(o.path, ec))
      return Error(ErrorKind::BadInput, o.path + ": exists (a video cannot be resumed; remove it or drop --no-overwrite)");
    o.writer = std::make_unique<io::VideoWriter>();
    if (Status st = o.writer->open(o.path, W, H, s.scene.fps, 18, &tag); !st) return st;
  }
  return {};
}

// Simulation, drawing and encoding of frames [first, last] (those in `need`) on three threads
// joined by bounded queues, so a film takes about as long as its slowest stage.
// `times`: each thread's busy seconds (waits on the queues left out). `cache`: where the simulation
// starts from (the nearest frame at or before `first`) and what it leaves for later stills.
// `farm`: frames restored from a farm cache instead of simulated.
Status runPipeline(Setup& s, std::vector<Output>& outs, int first, int last, const std::vector<char>& need, int to_draw,
                   bool no_overwrite, bool quiet, FilmTimes& times, SimCache* cache, const CacheReader* farm) {
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  const int W = s.scene.render.width, H = s.scene.render.height;
  BoundedQueue<std::pair<int, DrawList>> lists(3);
  BoundedQueue<FrameImage> images(3);
  Status sim_status, enc_status;
  std::thread sim([&] {
    // With motion blur, each frame drawn takes the draw list of the frame before along (not
    // for frame 0), so a chunk or a range starts one frame early.
    const bool blur = s.scene.render.shutter_deg > 0.0;
    const int from = blur ? std::max(0, first - 1) : first;
    const int start = farm ? from : cache ? cache->restoreNearest(*s.world, from) : 0;
    auto wanted = [&](int k) { return k >= first && k <= last && need[static_cast<std::size_t>(k)]; };
    std::shared_ptr<const DrawList> before;  // frame before_k's list, without its own `previous`
    int before_k = -1;
    for (int k = start; k <= last; ++k) {
      const auto t0 = Clock::now();
      const bool draw = wanted(k), opens_next = blur && k < last && wanted(k + 1);
      if (farm) {
        if (!draw && !opens_next) continue;
        if (Status st = farm->restore(*s.world, k); !st) {
          sim_status = st;
          break;
        }
      } else if (k > start) {
        if (Status st = s.world->advanceFrame(); !st) {
          sim_status = st;
          break;
        }
        if (cache) cache->offer(*s.world);
      }
      if (!draw && !opens_next) {
        times.simulate += since(t0);
        continue;
      }
      if (!blur) {
        DrawList list = frameList(s);
        times.simulate += since(t0);
        if (!lists.push({k, std::move(list)})) break;
        continue;
      }
      auto now = std::make_shared<const DrawList>(frameList(s));
      times.simulate += since(t0);
      if (draw) {
        DrawList list = *now;  // with the frame before; `now` stays without it, so no chain grows
        if (before_k == k - 1) list.previous = before;
        if (!lists.push({k, std::move(list)})) break;
      }
      before = std::move(now);
      before_k = k;
    }
    lists.close();
  });
  std::thread enc([&] {
    Progress progress(to_draw, quiet);
    int done = 0;
    while (auto f = images.pop()) {
      const auto t0 = Clock::now();
      for (auto& o : outs) {
        Status st = o.video ? o.writer->write(f->img)
                            : (no_overwrite && validFrame(o.framePath(f->k), W, H))
                                  ? Status{}
                                  : io::writePng(o.framePath(f->k), f->img, pngText(s, f->k));
        if (!st) {
          enc_status = st;
          images.close();
          lists.close();
          return;
        }
      }
      times.encode += since(t0);
      progress.update(++done);
    }
  });
  Status render_status;
  while (auto item = lists.pop()) {
    FrameImage fi;
    fi.k = item->first;
    const auto t0 = Clock::now();
    if (Status st = s.renderer->draw(item->second, fi.img); !st) {
      render_status = st;
      lists.close();
      break;
    }
    times.draw += since(t0);
    if (!images.push(std::move(fi))) break;
  }
  images.close();
  sim.join();
  enc.join();
  // Videos keep every frame encoded so far when the simulation stopped early (exit 3); after a
  // drawing or encoding failure they are abandoned (no final file).
  // (A damaged farm cache is bad input, not a simulation that stopped: nothing is kept then.)
  if (enc_status.ok() && render_status.ok() && (sim_status.ok() || sim_status.error().kind != ErrorKind::BadInput)) {
    const auto t0 = Clock::now();
    for (auto& o : outs)
      if (o.video)
        if (Status st = o.writer->finish(); !st && enc_status.ok()) enc_status = st;
    times.encode += since(t0);
  }
  for (const Status* st : {&sim_status, &render_status, &enc_status})
    if (!st->ok()) return *st;
  return {};
}

}  // namespace

int render(const RenderOptions& opt, const std::string& range, bool no_overwrite, FilmTimes* times) {
  const auto t_start = std::chrono::steady_clock::now();
  Setup s;
  if (Status st = setup(opt, s); !st) return report(st.error());
  const int n = s.scene.frameCount();
  int first = 0, last = n - 1;
  std::string frames = range;
  if (!opt.chunk.empty()) {
    auto r = chunkFrames(opt.chunk, n);
    if (!r.ok()) return report(r.error());
    frames = r.value();
  }
  if (Status st = frameRange(frames, n, first, last); !st) return report(st.error());
  CacheReader farm;
  if (!opt.from.empty())
    // (with motion blur from the frame before the first: the shutter opens on it)
    if (Status st = openFarmCache(opt, s, s.scene.render.shutter_deg > 0.0 ? std::max(0, first - 1) : first, last, farm); !st)
      return report(st.error());
  std::vector<Output> outs;
  const io::ChunkTag tag{first, last, n, s.scene.name, filmId(opt, s), ""};
  if (Status st = openOutputs(opt, s, no_overwrite, tag, outs); !st) return report(st.error());
  const int W = s.scene.render.width, H = s.scene.render.height;
  // Frames that need drawing: all of them unless every output already has a valid PNG.
  std::vector<char> need(static_cast<std::size_t>(n), 0);
  int to_draw = 0;
  for (int k = first; k <= last; ++k) {
    bool any = false;
    for (const auto& o : outs)  // every frame's file checked before anything is simulated
      if (Status st = o.video ? Status{} : io::checkOutputTarget(o.framePath(k)); !st) return report(st.error());
    for (const auto& o : outs) any = any || o.video || !no_overwrite || !validFrame(o.framePath(k), W, H);
    need[static_cast<std::size_t>(k)] = any;
    to_draw += any;
  }

  FilmTimes measured;
  measured.frames = to_draw;
  measured.scene = s.scene.name;
  measured.width = s.scene.render.width;
  measured.height = s.scene.render.height;
  measured.samples = s.scene.render.samples;
  measured.setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (times) profile::enable(true);
  std::optional<SimCache> cache = opt.from.empty() ? openCache(opt, n) : std::nullopt;
  const Status ran = runPipeline(s, outs, first, last, need, to_draw, no_overwrite, opt.quiet, measured,
                                 cache ? &*cache : nullptr, opt.from.empty() ? nullptr : &farm);
  if (times) {
    measured.stages = profile::totals();
    profile::enable(false);
    measured.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    *times = measured;
  }
  if (!ran) return report(ran.error());
  if (!opt.quiet)
    for (const auto& o : outs)
      std::printf("%s\n", o.video ? o.path.c_str() : (o.framePath(first) + " .. " + o.framePath(last)).c_str());
  return 0;
}

}  // namespace reel::app

namespace reel::app {

int compare(const CompareOptions& o) {
  auto a = io::readPng(o.a);
  if (!a.ok()) return report(a.error());
  auto b = io::readPng(o.b);
  if (!b.ok()) return report(b.error());
  if (a.value().width != b.value().width || a.value().height != b.value().height)
    return report(Error(ErrorKind::BadInput, "the images differ in size: " + std::to_string(a.value().width) + "x" +
                                                 std::to_string(a.value().height) + " and " +
                                                 std::to_string(b.value().width) + "x" +
                                                 std::to_string(b.value().height)));
  Image diff;
  const ImageDiff d = compareImages(a.value(), b.value(), o.threshold, o.diff.empty() ? nullptr : &diff);
  // (a is the reference of the perceptual metric)
  const double s = ssim(a.value(), b.value());
  const FlipResult f = flip(a.value(), b.value());
  const bool ok = d.mean_abs <= o.max_mean && d.over_fraction <= o.max_fraction && s >= o.min_ssim && f.mean <= o.max_flip;
  std::printf("max %d, mean %.4f, PSNR %.2f dB, %lld pixels (%.4f%%) over %d, SSIM %.5f, FLIP %.4f (worst %.4f): %s\n",
              d.max_abs, d.mean_abs, d.psnr_db, d.over, 100.0 * d.over_fraction, o.threshold, s, f.mean, f.max,
              ok ? "within tolerance" : "NOT within tolerance");
  if (!o.diff.empty())
    if (Status st = io::writePng(o.diff, diff); !st) return report(st.error());
  return ok ? 0 : 1;
}

}  // namespace reel::app
