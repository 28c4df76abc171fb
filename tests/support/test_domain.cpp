#include "support/test_domain.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <stdexcept>
#include <string>

namespace macsim::test {

int unique_test_domain() {
  // Start at a pid-dependent place so concurrent test processes rarely contend for a lock.
  constexpr int kFirst = 100, kCount = 133;
  const int offset = static_cast<int>(getpid()) % kCount;
  for (int i = 0; i < kCount; ++i) {
    const int domain = kFirst + (offset + i) % kCount;
    const std::string path = "/tmp/macsim-test-domain-" + std::to_string(domain) + ".lock";
    const int fd = open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) return domain;  // fd stays open: lock held
    close(fd);
  }
  throw std::runtime_error("no free DDS test domain in 100..232");
}

}  // namespace macsim::test
