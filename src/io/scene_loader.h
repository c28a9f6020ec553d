// Loading and validating `reel/1` scene files (DESIGN 4, 9).
#pragma once

#include <memory>
#include <span>
#include <string>

#include "core/error.h"
#include "core/scene.h"

namespace reel::io {

class Obj;

// A body kind's reader: the kind's keys of one `bodies` entry (`entry`; the keys every body has,
// name, type, material and node_radius, are read by the loader). It may set defaults of `body`
// (its material) and reads the scene's top-level keys from `scene` (read before any body).
using BodyReader = std::shared_ptr<const BodyParams> (*)(Obj& entry, BodyDesc& body, const SceneDesc& scene);
struct BodyReaderRow {
  const char* type;
  BodyReader read;
};

// Limits that keep a bad scene from exhausting the machine.
inline constexpr std::size_t kMaxSceneBytes = 64u << 20;     // scene file size
inline constexpr long long kMaxBodyNodes = 4'194'304;         // nodes of one body (2048 x 2048)
inline constexpr long long kMaxSceneNodes = 4'194'304;        // nodes of all bodies together
inline constexpr long long kMaxSceneSprings = 16'777'216;     // springs of all bodies together
inline constexpr double kMinNodeMass = 1e-12;                 // kg: lighter nodes overflow 1/m
inline constexpr std::size_t kMaxTextureBytes = 64u << 20;
inline constexpr std::size_t kMaxTexturePixels = 16u << 20;  // 4096 x 4096

// Parses and validates a scene file. On failure the Error (BadInput) lists every problem found,
// one line each: "file:line:col: ..." for syntax errors, "file: /json/path: ..." otherwise.
// `kinds`: the body kinds (app/body_kinds.h: bodyReaders()).
Result<SceneDesc> loadScene(const std::string& path, std::span<const BodyReaderRow> kinds);
// The same from text already in memory; `file` names it in messages and anchors asset paths.
Result<SceneDesc> parseScene(const std::string& text, const std::string& file, std::span<const BodyReaderRow> kinds);

}  // namespace reel::io
