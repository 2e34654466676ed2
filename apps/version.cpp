#include "apps/version.h"

namespace rubcont {

const char* Version() { return RUBCONT_VERSION; }

}  // namespace rubcont
