// The rubcont version written into every result file (root attribute `rubcont_version`).
#pragma once

namespace rubcont {

// "MAJOR.MINOR.PATCH" of the build, from CMake's PROJECT_VERSION.
const char* Version();

}  // namespace rubcont
