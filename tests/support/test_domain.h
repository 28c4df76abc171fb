// DDS domain ids for tests: each call returns one no other test process on this machine holds.
#pragma once

namespace macsim::test {

/// A DDS domain id in 100..232, reserved (by a file lock) until this process exits.
int unique_test_domain();

}  // namespace macsim::test
