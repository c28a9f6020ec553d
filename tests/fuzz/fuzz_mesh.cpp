// libFuzzer target: a mesh file through io::importMesh (pre-scan, assimp, checks). The first byte
// picks the format (the file's extension); the rest is the file. The file lies in a private
// folder, which is the only folder the import may read: an input that makes the importer open
// anything else (its own references: OBJ mtllib, glTF buffer uri) must be refused.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_files.h"
#include "io/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::size_t kinds = std::size(reel::io::kMeshExtensions);
  const std::string path = reel::fuzz::put(std::string("mesh") + reel::io::kMeshExtensions[data[0] % kinds],
                                           {reinterpret_cast<const char*>(data + 1), size - 1});
  (void)reel::io::importMesh(path, {reel::fuzz::privateDir()});
  std::remove(path.c_str());
  return 0;
}
