#include "macsim/dds/shared_memory.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>

namespace macsim::dds {

namespace fs = std::filesystem;

namespace {

bool is_fast_dds_file(const std::string& name) {
  return name.rfind("fastrtps_", 0) == 0 || name.rfind("fast_datasharing_", 0) == 0 ||
         name.rfind("sem.fastrtps_", 0) == 0;
}

/// The thing a file belongs to: a segment or port and its lock files (`_el`, `_sl`) and mutex
/// (`sem.` ... `_mutex`) are one; none of them goes while any of them is in use.
std::string group_of(std::string name) {
  if (name.rfind("sem.", 0) == 0) name.erase(0, 4);
  for (const std::string suffix : {"_mutex", "_el", "_sl"}) {
    if (name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      name.erase(name.size() - suffix.size());
    }
  }
  return name;
}

/// The files of `folder` some process maps or holds open (those of this user's processes at
/// least: other users' /proc entries may be unreadable, and their files are not ours to remove).
std::set<std::string> files_in_use(const fs::path& folder) {
  std::set<std::string> used;
  const std::string prefix = folder.string() + "/";
  std::error_code error;
  for (const auto& process : fs::directory_iterator("/proc", error)) {
    const std::string pid = process.path().filename();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream maps(process.path() / "maps");
    for (std::string line; std::getline(maps, line);) {
      const auto at = line.find(prefix);
      if (at != std::string::npos) used.insert(group_of(line.substr(at + prefix.size())));
    }
    std::error_code fd_error;
    for (const auto& fd : fs::directory_iterator(process.path() / "fd", fd_error)) {
      std::error_code link_error;
      const std::string target = fs::read_symlink(fd.path(), link_error).string();
      if (!link_error && target.rfind(prefix, 0) == 0) {
        used.insert(group_of(target.substr(prefix.size())));
      }
    }
  }
  return used;
}

}  // namespace

SharedMemoryCleanup clean_stale_shared_memory(std::chrono::seconds min_age, bool dry_run,
                                              const std::string& folder) {
  SharedMemoryCleanup result;
  const std::set<std::string> used = files_in_use(folder);
  const auto now = fs::file_time_type::clock::now();
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename();
    if (!is_fast_dds_file(name)) continue;
    struct stat info {};
    if (::stat(entry.path().c_str(), &info) != 0 || info.st_uid != ::geteuid()) continue;
    if (used.count(group_of(name))) {
      ++result.in_use;
      continue;
    }
    std::error_code time_error;
    const auto modified = fs::last_write_time(entry.path(), time_error);
    if (time_error || now - modified < min_age) continue;  // perhaps being set up right now
    std::error_code remove_error;
    if (dry_run || fs::remove(entry.path(), remove_error)) result.removed.push_back(name);
  }
  return result;
}

}  // namespace macsim::dds
