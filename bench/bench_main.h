// One ending for every benchmark: an exception (a missing scene when run outside the repository
// root, a solve that fails) ends the program with the benchmark's name and the message on stderr,
// exit code 1, instead of std::terminate's "terminate called".
#pragma once

#include <cstdio>
#include <exception>

namespace rubcont {

template <class Body>
int RunBenchmark(const char* name, Body&& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
    return 1;
  }
}

}  // namespace rubcont
