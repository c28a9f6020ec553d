// libFuzzer target: a mesh file through io::importMesh (pre-scan, assimp, checks). The first byte
// picks the format (the file's extension); the rest is the file. The file lies in a private
// folder, which is the only folder the import may read: an input that makes the importer open
// anything else (its own references: OBJ mtllib, glTF buffer uri) must be refused.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string dir = [] {
    char tmpl[] = "/tmp/reel-fuzz-mesh-XXXXXX";
    const char* d = mkdtemp(tmpl);
    if (!d) std::abort();
    return std::string(d);
  }();
  if (size < 1) return 0;
  const std::size_t kinds = std::size(reel::io::kMeshExtensions);
  const std::string path = dir + "/mesh" + reel::io::kMeshExtensions[data[0] % kinds];
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 1 && std::fwrite(data + 1, 1, size - 1, f) != size - 1) std::abort();
  std::fclose(f);
  (void)reel::io::importMesh(path, {dir});
  std::remove(path.c_str());
  return 0;
}
