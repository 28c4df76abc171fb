#include "support/child_process.h"

#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace macsim::test {

std::string bin(const std::string& program) { return std::string(MACSIM_BIN_DIR) + "/" + program; }

std::string source(const std::string& relative) {
  return std::string(MACSIM_SOURCE_DIR) + "/" + relative;
}

std::string build_path(const std::string& relative) {
  return std::string(MACSIM_BUILD_DIR) + "/" + relative;
}

namespace {
// Tests talk over the shipped loopback profile even when started by hand (ctest sets it too):
// no DDS packet leaves the machine, and every test process and child agrees on transports.
const bool kLoopbackProfile = [] {
  setenv("FASTRTPS_DEFAULT_PROFILES_FILE", source("deploy/dds/localhost.xml").c_str(), 0);
  return true;
}();
}  // namespace

TempDir::TempDir(const std::string& prefix) {
  std::string pattern = "/tmp/" + prefix + "XXXXXX";
  if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a directory " + pattern);
  path_ = pattern;
}

TempDir::~TempDir() { std::filesystem::remove_all(path_); }

ScopedEnv::ScopedEnv(const char* name, const std::string& value) : name_(name) {
  if (const char* old = std::getenv(name)) old_ = old;
  setenv(name, value.c_str(), 1);
}

ScopedEnv::~ScopedEnv() {
  if (old_) {
    setenv(name_, old_->c_str(), 1);
  } else {
    unsetenv(name_);
  }
}

}  // namespace macsim::test
