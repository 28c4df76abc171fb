#include "macsim/sim_core/data_roots.h"

#include <fcntl.h>
#include <linux/openat2.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>

namespace macsim {

namespace fs = std::filesystem;

namespace {

/// True if `canonical` is `folder` or lies below it (both canonical).
bool is_under(const fs::path& canonical, const fs::path& folder) {
  auto p = canonical.begin();
  for (auto f = folder.begin(); f != folder.end(); ++f, ++p) {
    if (f->empty()) continue;  // a trailing separator
    if (p == canonical.end() || *p != *f) return false;
  }
  return true;
}

/// The kernel's pseudo file systems and device nodes: never read, whatever the roots say.
bool special(const fs::path& canonical) {
  for (const char* folder : {"/proc", "/sys", "/dev"}) {
    if (is_under(canonical, folder)) return true;
  }
  return false;
}

std::string quoted(const std::string& path) { return "'" + path + "'"; }

/// Closes a descriptor on every way out.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::atomic<bool> g_openat2{true};  // false once the kernel said it has none (or a test)

/// The flags a file under a root is opened with: read only, without blocking (a FIFO swapped
/// in), no terminal, the last component no link.
constexpr int kOpenFlags = O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC;

/// Opens `relative` (no `..`, no link: a canonical path's tail) beneath the folder `root`
/// holds; -1 with errno set (EXDEV, ELOOP: a link or `..` met that leaves it).
int open_beneath(int root, const fs::path& relative) {
  if (g_openat2.load(std::memory_order_relaxed)) {
    open_how how{};
    how.flags = kOpenFlags;
    how.resolve = RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS;
    const long fd = ::syscall(SYS_openat2, root, relative.c_str(), &how, sizeof how);
    if (fd >= 0 || errno != ENOSYS) return static_cast<int>(fd);
    g_openat2.store(false);  // a kernel older than 5.6
  }
  // One component at a time, none followed if it is a link: what canonical() resolved has
  // none, so a link met here was swapped in since, and is refused wherever it stands.
  int at = ::dup(root);
  if (at < 0) return -1;
  const std::vector<fs::path> parts(relative.begin(), relative.end());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const bool last = i + 1 == parts.size();
    if (parts[i] == ".." || parts[i] == "." || parts[i].empty()) {
      ::close(at);
      errno = EXDEV;
      return -1;
    }
    const int next = ::openat(at, parts[i].c_str(),
                              last ? kOpenFlags : O_PATH | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    const int saved = errno;
    ::close(at);
    if (next < 0) {
      errno = saved == ENOTDIR ? ELOOP : saved;  // a link where a folder was
      return -1;
    }
    at = next;
  }
  return at;
}

}  // namespace

void DataRoots::use_openat2(bool use) { g_openat2.store(use); }

std::shared_ptr<const DataRoots> DataRoots::anywhere() {
  static const std::shared_ptr<const DataRoots> everywhere(new DataRoots());
  return everywhere;
}

DataRoots::DataRoots(const std::vector<std::string>& folders, std::size_t max_file_bytes)
    : restricted_(true), max_file_bytes_(max_file_bytes) {
  for (const std::string& folder : folders) {
    std::error_code error;
    const auto given = lexical(folder);
    const fs::path canonical =
        given ? fs::weakly_canonical(*given, error).lexically_normal() : fs::path();
    if (!given || error || !fs::is_directory(canonical, error)) {
      throw std::invalid_argument("data root " + quoted(folder) + " is no folder");
    }
    if (special(canonical) || canonical.parent_path() == canonical) {
      throw std::invalid_argument("data root " + quoted(folder) +
                                  " would open the file system's root, /proc, /sys or /dev");
    }
    for (const fs::path& spelling : {*given, canonical}) {
      if (std::find(spellings_.begin(), spellings_.end(), spelling) == spellings_.end()) {
        spellings_.push_back(spelling);
      }
    }
    if (std::find(folders_.begin(), folders_.end(), canonical) == folders_.end()) {
      folders_.push_back(canonical);
    }
  }
}

std::optional<fs::path> DataRoots::lexical(const std::string& path) {
  if (path.empty() || path.find('\0') != std::string::npos) return std::nullopt;
  std::error_code error;
  fs::path normal = fs::absolute(path, error).lexically_normal();
  if (error) return std::nullopt;
  if (normal.filename().empty() && normal.has_parent_path() && normal != normal.root_path()) {
    normal = normal.parent_path();  // "dir/" names dir
  }
  return normal;
}

std::optional<fs::path> DataRoots::inside(const std::string& path) const {
  const auto normal = lexical(path);
  if (!normal) return std::nullopt;
  const auto under_any = [](const fs::path& p, const std::vector<fs::path>& roots) {
    return std::any_of(roots.begin(), roots.end(),
                       [&p](const fs::path& root) { return is_under(p, root); });
  };
  if (restricted_ && !under_any(*normal, spellings_)) return std::nullopt;
  std::error_code error;
  const fs::path canonical = fs::weakly_canonical(*normal, error).lexically_normal();
  if (error) return std::nullopt;
  if (restricted_ && !under_any(canonical, folders_)) return std::nullopt;
  return canonical;
}

std::shared_ptr<const DataRoots> DataRoots::only(std::shared_ptr<const WorldFiles> files) {
  std::shared_ptr<DataRoots> roots(new DataRoots());
  roots->restricted_ = true;
  roots->only_ = std::move(files);
  return roots;
}

std::shared_ptr<const DataRoots> DataRoots::watched(FileWatcher watcher) const {
  auto roots = std::shared_ptr<DataRoots>(new DataRoots(*this));
  roots->watcher_ = std::move(watcher);
  return roots;
}

bool DataRoots::contains(const std::string& path) const {
  if (only_) return only_->read(path).has_value();
  const auto canonical = inside(path);
  return canonical && !special(*canonical);
}

std::string DataRoots::outside_message(const std::string& path) {
  return quoted(path) +
         " is outside the folders this simulator reads files from (its data roots: the loaded "
         "world's folder, the shipped worlds and each --data-path)";
}

std::optional<std::string> DataRoots::read(const std::string& path) const {
  std::optional<std::string> bytes;
  if (only_) {
    bytes = only_->read(path);  // a file the recorded run did not read is missing here
  } else {
    bytes = read_disk(path);
  }
  if (bytes && watcher_) watcher_(path, *bytes);
  return bytes;
}

std::optional<std::string> DataRoots::read_disk(const std::string& path) const {
  const auto canonical = inside(path);
  if (!canonical) throw FileRefused(outside_message(path));
  if (special(*canonical)) {
    throw FileRefused(quoted(path) + " is a kernel or device file (/proc, /sys, /dev): not read");
  }
  // What the path is, looked at without opening it (a FIFO would block an open).
  struct stat seen {};
  if (::lstat(canonical->c_str(), &seen) != 0) {
    if (errno == ENOENT || errno == ENOTDIR) return std::nullopt;
    throw FileRefused(quoted(path) + " cannot be read: " + std::strerror(errno));
  }
  if (S_ISLNK(seen.st_mode)) {
    // Resolution left a symbolic link: it points nowhere, maybe outside a root.
    throw FileRefused(restricted_ ? outside_message(path)
                                  : quoted(path) + " is a symbolic link to nothing");
  }
  if (!S_ISREG(seen.st_mode)) {
    throw FileRefused(quoted(path) +
                      " is not a regular file (a folder, device, FIFO or socket): not read");
  }
  const auto too_large = [&] {
    return FileRefused(quoted(path) + " is larger than the " +
                       std::to_string(max_file_bytes_ >> 20) + " MiB a file read on request may be");
  };
  if (std::size_t(seen.st_size) > max_file_bytes_) throw too_large();
  // Opened without following a link and without blocking, then checked to be what was seen;
  // under a root, beneath the root's own folder, so that a folder on the way swapped for a
  // link since it was resolved cannot lead out of it.
  const fs::path* root = nullptr;
  for (const fs::path& folder : folders_) {
    if (is_under(*canonical, folder) && (!root || std::distance(folder.begin(), folder.end()) >
                                                      std::distance(root->begin(), root->end())))
      root = &folder;
  }
  int fd = -1;
  if (root) {
    const Descriptor folder{::open(root->c_str(), O_PATH | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)};
    const fs::path relative = canonical->lexically_relative(*root);
    fd = folder.fd < 0 ? -1 : open_beneath(folder.fd, relative);
    if (fd < 0 && (errno == EXDEV || errno == ELOOP)) throw FileRefused(outside_message(path));
  } else {
    fd = ::open(canonical->c_str(), kOpenFlags);
  }
  const Descriptor file{fd};
  if (file.fd < 0) {
    if (errno == ENOENT) return std::nullopt;
    throw FileRefused(quoted(path) + " cannot be read: " + std::strerror(errno));
  }
  struct stat opened {};
  if (::fstat(file.fd, &opened) != 0 || !S_ISREG(opened.st_mode) ||
      opened.st_ino != seen.st_ino || opened.st_dev != seen.st_dev) {
    throw FileRefused(quoted(path) + " changed while it was opened: not read");
  }
  std::string bytes;
  char buffer[1 << 16];
  while (true) {
    const ssize_t got = ::read(file.fd, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw FileRefused(quoted(path) + " cannot be read: " + std::strerror(errno));
    if (got == 0) break;
    bytes.append(buffer, std::size_t(got));
    if (bytes.size() > max_file_bytes_) throw too_large();
  }
  return bytes;
}

std::string DataRoots::identity(const std::string& path) const {
  if (only_) return only_->identity(path);
  if (const auto canonical = inside(path)) return canonical->string();
  const auto normal = lexical(path);
  return normal ? normal->string() : path;
}

}  // namespace macsim
