#include "support/test_domain.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace macsim::test {

namespace {

/// Locks `domain` for this process (the descriptor stays open); -1 if another holds it.
int lock_domain(int domain) {
  const std::string path = "/tmp/macsim-test-domain-" + std::to_string(domain) + ".lock";
  const int fd = open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0666);
  if (fd < 0) return -1;
  if (flock(fd, LOCK_EX | LOCK_NB) == 0) return fd;
  close(fd);
  return -1;
}

}  // namespace

int unique_test_domain() { return unique_test_domains(1); }

int unique_test_domains(int count) {
  // Start at a pid-dependent place so concurrent test processes rarely contend for a lock.
  constexpr int kFirst = 100, kCount = 133;
  const int offset = static_cast<int>(getpid()) % kCount;
  for (int i = 0; i < kCount; ++i) {
    const int first = kFirst + (offset + i) % kCount;
    if (first + count > kFirst + kCount) continue;
    std::vector<int> held;
    for (int d = first; d < first + count; ++d) {
      const int fd = lock_domain(d);
      if (fd < 0) break;
      held.push_back(fd);
    }
    if (static_cast<int>(held.size()) == count) return first;
    for (int fd : held) close(fd);  // releases the locks
  }
  throw std::runtime_error("no free DDS test domains in 100..232");
}

}  // namespace macsim::test
