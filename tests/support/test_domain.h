// DDS domain ids for tests: each call returns one no other test process on this machine holds.
#pragma once

namespace macsim::test {

/// A DDS domain id in 100..232, reserved (by a file lock) until this process exits.
int unique_test_domain();
/// `count` consecutive such ids; the first.
int unique_test_domains(int count);

}  // namespace macsim::test
