// File helpers: bounded reads, asset resolution within allowed roots, output folders, and atomic
// writes (write NAME.part, then rename onto NAME: a reader never sees a half-written final file).
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"

namespace reel::io {

// Reads a whole file of at most max_bytes.
Result<std::string> readFile(const std::string& path, std::size_t max_bytes);

// The folders a scene's assets may come from: the scene's folder, the current directory's
// `assets/` and the installed/source one; canonical, so that a path is checked against them with
// insideRoots.
std::vector<std::string> assetRoots(const std::string& scene_file);
// PATH (made canonical, following links) lies inside one of the roots.
bool insideRoots(const std::string& path, const std::vector<std::string>& roots);

// Resolves an asset path from a scene: relative to the scene's folder, then to the `assets/`
// folders (the current directory's and the installed/source one). The resolved file must exist,
// stay inside one of those roots, have one of the given extensions and be at most max_bytes.
// The error is one line: the path and the reason.
Result<std::string> resolveAsset(const std::string& scene_file, const std::string& path,
                                 const std::vector<std::string>& extensions, std::size_t max_bytes);

// Every asset resolveAsset has found since the last clear, in order (for the simulation cache's
// key: a scene's result depends on its meshes and textures too). Thread-safe.
std::vector<std::string> resolvedAssets();
void clearResolvedAssets();

// Creates the missing folders above an output PATH (as `mkdir -p` does), so that every output
// (PNG, video, dump) may name a new folder. The error (exit-4 kind) names PATH, the folder and why.
Status createParentFolders(const std::string& path);

// An output PATH (and its PATH.part) may be new or a regular file (or a link to one); a device
// node, FIFO, socket or folder there is refused (exit-4 kind) instead of being renamed over
// (`--dump /dev/full` as root would replace the device) or blocking (a FIFO).
Status checkOutputTarget(const std::string& path);

// What a file that is there but not a regular file is, in words: "a folder", "a device", "a FIFO",
// "a socket" or "not a regular file".
std::string kindInWords(const std::filesystem::file_status& st);

// Where an output named PATH is written: PATH itself, or, when PATH is a symbolic link, the file it
// finally points to (its .part file beside that file). Renaming over PATH would replace the link
// (`-o /dev/stdout` as root replaced the system's link with a PNG); writing through it is what a
// user who names a link means. A link to a device or FIFO is refused by checkOutputTarget.
std::string writeThrough(const std::string& path);

// A scene name as a file name: letters, digits, '-', '_' and a '.' between letters kept; each
// run of anything else (a '/', "..", spaces) becomes one '_'; never empty, at most 100 bytes. Default outputs use it, so a
// `name` of "../../x" stays inside render_out/.
std::string safeFileName(const std::string& name);

class AtomicFile {
 public:
  AtomicFile() = default;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();  // an uncommitted file is removed
  // Creates PATH's missing folders and opens PATH.part for writing (exit-4 kind of error when it
  // cannot). `shared`: PATH is in a cache that other processes or threads may write the same file
  // into at once (the simulation cache), so the part file's name is this writer's own
  // (PATH.<pid>-<n>.part); the last rename wins, and every writer's file is whole.
  Status open(const std::string& path, bool shared = false);
  std::FILE* get() const { return f_; }
  // Appends bytes; the error (exit-4 kind) names PATH and the reason (a full disk).
  Status write(const std::string& bytes);
  // Flushes, closes and renames PATH.part onto PATH; removes the part file on failure.
  Status commit();
  void abandon();

 private:
  std::FILE* f_ = nullptr;
  std::string path_, part_;
};

}  // namespace reel::io
