// A fixture for the layering check (tests/CMakeLists.txt): a kernel that includes a header of a
// folder above its own. Never compiled.
#pragma once

#include "shooting/orbit.h"
#include "solvers/types.h"
