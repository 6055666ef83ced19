// libFuzzer target for OFF meshes (issue 15): any bytes read as an OFF file must give a valid mesh
// or an InputError, never a crash, an allocation of gigabytes from a lying header, or undefined
// behaviour (a coordinate beyond float is UB to cast; -fsanitize=float-cast-overflow catches it).
#include <cstdint>

#include "base/errors.h"
#include "scenes/fuzz/fuzz_input_file.h"
#include "scenes/mesh.h"
#include "scenes/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = aoeval::fuzz::write_input(data, size, ".off");
  try {
    aoeval::TriangleMesh mesh = aoeval::load_off(path);
    aoeval::validate_mesh(mesh, path);  // what the loader promises: every index in range
  } catch (const aoeval::InputError&) {
  }
  return 0;
}
