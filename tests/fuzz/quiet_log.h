// The LLVMFuzzerInitialize of the fuzzers that drive sim_core: its log silenced, since a refused
// input, the expected case, would print a line each run. Included by one source per fuzzer.
#pragma once

#include <string>

#include "macsim/sim_core/log_sink.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  macsim::set_log_sink([](macsim::LogLevel, const std::string&) {});
  return 0;
}
