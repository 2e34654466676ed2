// A fixture for the layering check: including a lower folder is allowed. Never compiled.
#pragma once

#include "solvers/kernel.h"
