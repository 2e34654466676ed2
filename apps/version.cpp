#include "apps/version.h"

namespace rubcont {

const char* Version() { return RUBCONT_VERSION; }

const char* GitDescribe() { return RUBCONT_GIT_DESCRIBE; }

}  // namespace rubcont
