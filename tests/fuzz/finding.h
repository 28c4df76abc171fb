// How a fuzzer reports what it found: a message on stderr, then an abort (libFuzzer keeps the
// input that made it).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace macsim::fuzz {

/// Reports `what` and aborts.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "finding: %s\n", what.c_str());
  std::abort();
}

}  // namespace macsim::fuzz
