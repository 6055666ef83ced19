// libFuzzer target for scene files (issue 15): any bytes given to `--scene FILE.json` must end in a
// loaded scene or an InputError (exit 2 with a message), never a crash, a hang, an undefined
// behaviour (ASan + UBSan with float-cast-overflow) or any other exception. Run by
// tools/sanitize.sh for a bounded time, seeded with scenes/corpus/*.json and the bad-input corpus.
#include <cstdint>
#include <cstdlib>
#include <exception>

#include "base/errors.h"
#include "scenes/fuzz/fuzz_input_file.h"
#include "scenes/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = aoeval::fuzz::write_input(data, size, ".json");
  try {
    aoeval::Scene scene = aoeval::load_scene_file(path);
    (void)scene;
  } catch (const aoeval::InputError&) {
    // the expected answer to bad input
  }
  return 0;  // any other exception escapes and libFuzzer reports it as a crash
}
