// libFuzzer target: a scene file's text through the scene loader (parse, validate every key, load
// the assets it names). Any crash, sanitizer report, leak or hang is a finding; a refusal
// (BadInput) is the expected answer to nearly every input. Building the world is left out: a
// valid scene may take seconds to build (a face settles), which would read as a hang. Run it from
// scenes/ so that the scenes' asset paths (meshes/...) resolve: docs/fuzzing.md.
#include <cstddef>
#include <cstdint>
#include <string>

#include "app/body_kinds.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)reel::app::parseScene(text, "fuzz.json");
  return 0;
}
