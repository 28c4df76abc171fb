// Whether anyone opened a file while it was watched (inotify's IN_OPEN, any process): for
// checking that a FIFO a request named was never opened, not even for a moment.
#pragma once

#include <sys/inotify.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace macsim::test {

/// Watches files for opens from its construction on.
class OpenWatch {
 public:
  explicit OpenWatch(const std::vector<std::string>& paths)
      : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
    for (const std::string& path : paths) {
      watching_ = fd_ >= 0 && ::inotify_add_watch(fd_, path.c_str(), IN_OPEN) >= 0 && watching_;
    }
  }
  ~OpenWatch() {
    if (fd_ >= 0) ::close(fd_);
  }
  OpenWatch(const OpenWatch&) = delete;
  OpenWatch& operator=(const OpenWatch&) = delete;

  /// False if a file could not be watched (the checks would prove nothing).
  bool watching() const { return watching_; }
  /// True if a watched file was opened since the last call (or since the watch began).
  bool opened() {
    alignas(inotify_event) char events[4096];
    bool any = false;
    while (::read(fd_, events, sizeof events) > 0) any = true;
    return any;
  }

 private:
  int fd_;
  bool watching_ = true;
};

}  // namespace macsim::test
