// The rubcont version and commit written into every result file (root attributes `rubcont_version`
// and `rubcont_git`).
#pragma once

namespace rubcont {

// "MAJOR.MINOR.PATCH" of the build, from CMake's PROJECT_VERSION.
const char* Version();

// `git describe --tags --always --dirty` of the source tree when cmake configured the build
// ("v0.2.0-3-g1a2b3c4", "1a2b3c4-dirty"), or "unknown" when it was not a git checkout.
const char* GitDescribe();

}  // namespace rubcont
