// Fast DDS's shared-memory files that killed participants leave in /dev/shm, found and removed.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace macsim::dds {

/// What a clean-up found among Fast DDS's files in the shared-memory folder.
struct SharedMemoryCleanup {
  std::vector<std::string> removed;  ///< stale files deleted (or, on a dry run, to delete)
  int in_use = 0;                    ///< files a live process maps or holds open
};

/// Removes this user's Fast DDS shared-memory files (fastrtps_* segments, ports and locks,
/// fast_datasharing_* segments, sem.fastrtps_* mutexes) that no live process maps or holds
/// open (a segment or port counts with its lock files and mutex) and that are older than
/// `min_age`: what a participant killed before it could close
/// its transports leaves behind. Other users' files and files in use are never touched.
SharedMemoryCleanup clean_stale_shared_memory(
    std::chrono::seconds min_age = std::chrono::seconds(2), bool dry_run = false,
    const std::string& folder = "/dev/shm");

}  // namespace macsim::dds
