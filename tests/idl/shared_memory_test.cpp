// The shared-memory clean-up on a folder of its own: stale Fast DDS files go, files a live
// process holds open or maps stay (with the lock files and mutex of their segment or port),
// young files and other programs' files stay, a dry run removes nothing.
#include "macsim/dds/shared_memory.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "support/child_process.h"

namespace macsim::dds {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

void make(const fs::path& file, bool old = true) {
  std::ofstream(file) << std::string(4096, 'x');
  if (old) fs::last_write_time(file, fs::file_time_type::clock::now() - 1h);
}

bool removed(const SharedMemoryCleanup& c, const std::string& name) {
  return std::find(c.removed.begin(), c.removed.end(), name) != c.removed.end();
}

TEST(SharedMemory, StaleFilesGoAndFilesInUseStay) {
  test::TempDir dir("macsim_shm_test");
  const fs::path d = dir.path();
  make(d / "fastrtps_0123456789abcdef");  // a killed participant's segment and its lock
  make(d / "fastrtps_0123456789abcdef_el");
  make(d / "fast_datasharing_01.0f.00.00.00.00.00.01.00.00.00.00_0.0.1.3");
  make(d / "fastrtps_port7411");  // a port someone maps: it stays, lock and mutex too
  make(d / "fastrtps_port7411_el");
  make(d / "sem.fastrtps_port7411_mutex");
  make(d / "fastrtps_fedcba9876543210_el");  // a lock held open: its segment stays
  make(d / "fastrtps_fedcba9876543210");
  make(d / "fast_datasharing_young", false);  // being set up right now
  make(d / "someone_elses_segment");

  const int mapped_fd = open((d / "fastrtps_port7411").c_str(), O_RDWR);
  void* mapped = mmap(nullptr, 4096, PROT_READ, MAP_SHARED, mapped_fd, 0);
  ASSERT_NE(mapped, MAP_FAILED);
  const int held = open((d / "fastrtps_fedcba9876543210_el").c_str(), O_RDONLY);
  ASSERT_GE(held, 0);

  const auto dry = clean_stale_shared_memory(2s, true, d);
  EXPECT_EQ(dry.removed.size(), 3u);
  EXPECT_TRUE(fs::exists(d / "fastrtps_0123456789abcdef"));  // a dry run removes nothing

  const auto done = clean_stale_shared_memory(2s, false, d);
  EXPECT_EQ(done.removed.size(), 3u);
  for (const char* gone : {"fastrtps_0123456789abcdef", "fastrtps_0123456789abcdef_el",
                           "fast_datasharing_01.0f.00.00.00.00.00.01.00.00.00.00_0.0.1.3"}) {
    EXPECT_TRUE(removed(done, gone)) << gone;
    EXPECT_FALSE(fs::exists(d / gone)) << gone;
  }
  for (const char* kept : {"fastrtps_port7411", "fastrtps_port7411_el", "sem.fastrtps_port7411_mutex",
                           "fastrtps_fedcba9876543210_el", "fastrtps_fedcba9876543210",
                           "fast_datasharing_young", "someone_elses_segment"}) {
    EXPECT_TRUE(fs::exists(d / kept)) << kept;
  }
  EXPECT_EQ(done.in_use, 5);
  munmap(mapped, 4096);
  close(mapped_fd);
  close(held);
}

}  // namespace
}  // namespace macsim::dds
