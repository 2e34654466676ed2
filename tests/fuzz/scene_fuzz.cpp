// Fuzz target of the scene loader (issue 17): any text either loads or is refused with a
// SceneError (exit code 2 at the CLI); nothing else may happen — no other exception, no crash, no
// sanitizer report. A scene that loads must survive a round trip: its resolved TOML (what result
// files store) loads again and resolves to the same text, and its description can be printed.
//
// Built two ways (tests/CMakeLists.txt): with libFuzzer (scripts/fuzz.sh, clang's
// -fsanitize=fuzzer, RUBCONT_FUZZ=ON), and in every build as `scene_fuzz_replay`, which feeds the
// committed corpus (tests/fuzz/corpus/ and scenes/) through the same function under ctest.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "apps/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 65536) return 0;  // a scene is a few kB; longer inputs only slow the search
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rubcont::Scene scene;
  try {
    scene = rubcont::ParseScene(text, "fuzz input", "fuzz");
  } catch (const rubcont::SceneError&) {
    return 0;  // refused with a message: the expected answer to bad input
  }
  const std::string resolved = rubcont::ResolvedSceneToml(scene);
  const rubcont::Scene again = rubcont::ParseScene(resolved, "fuzz input", "fuzz");
  if (rubcont::ResolvedSceneToml(again) != resolved) {
    std::fprintf(stderr, "scene_fuzz: the resolved scene does not reproduce itself:\n%s\n",
                 resolved.c_str());
    std::abort();
  }
  (void)rubcont::DescribeScene(scene);
  return 0;
}
