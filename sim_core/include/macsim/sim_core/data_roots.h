// The files a simulator reads on request (worlds, imports, textures): regular files under its
// data roots only, each at most a size; anything else is refused before it is opened, with one
// answer that does not say whether the file exists.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "macsim/sim_core/world_loader.h"

namespace macsim {

/// A file the simulator will not read; what() is the whole answer for the requester.
class FileRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The largest file read on request (a 1024 x 1024 BMP texture is 3 MiB, worlds are KiB).
inline constexpr std::size_t kMaxDataFileBytes = std::size_t(16) << 20;

/// WorldFiles limited to regular files of at most a size, under root folders or anywhere.
class DataRoots : public WorldFiles {
 public:
  /// Any regular file on disk (a program loading its own files): no roots, the rest applies.
  static std::shared_ptr<const DataRoots> anywhere();
  /// Only files under `folders`; throws std::invalid_argument naming one that is no folder or
  /// lies under /proc, /sys or /dev.
  explicit DataRoots(const std::vector<std::string>& folders,
                     std::size_t max_file_bytes = kMaxDataFileBytes);

  /// Roots that hold nothing but `files` and never look at the disk (a replayed session's
  /// files): a path is under them when `files` has it.
  static std::shared_ptr<const DataRoots> only(std::shared_ptr<const WorldFiles> files);
  /// These roots, telling `watcher` of every file they read (a recorded session embeds them);
  /// the watcher runs on the reading thread.
  std::shared_ptr<const DataRoots> watched(FileWatcher watcher) const;

  /// False for anywhere(): every path is under a root.
  bool restricted() const { return restricted_; }
  /// The roots, canonical (symlinks resolved), in the order given, without repeats.
  const std::vector<std::filesystem::path>& folders() const { return folders_; }
  /// True if `path` (relative to the working folder) lies under a root, both with `..` applied
  /// on paper and with symbolic links resolved; says nothing about whether it exists.
  bool contains(const std::string& path) const;
  /// The file's bytes; nothing if it is missing under a root; throws FileRefused for a path
  /// outside the roots, anything but a regular file (devices, FIFOs, sockets, folders, /proc),
  /// and a file larger than the cap.
  std::optional<std::string> read(const std::string& path) const override;
  std::string identity(const std::string& path) const override;

  /// The answer for a path outside the roots (the same whether it exists or not).
  static std::string outside_message(const std::string& path);
  /// Files under roots are opened with openat2(RESOLVE_BENEATH) from the root's folder, or,
  /// where the kernel lacks it (or `use` is false: tests), one component at a time without
  /// following a link: either way nothing swapped in during a read leads out of the root.
  static void use_openat2(bool use);

 private:
  DataRoots() = default;
  /// The path made absolute with `..` applied on paper (no system call looks at it).
  static std::optional<std::filesystem::path> lexical(const std::string& path);
  /// The canonical path of `path` if it lies under a root: first on paper, so that nothing on
  /// disk outside the roots is ever looked at, then with symbolic links resolved.
  std::optional<std::filesystem::path> inside(const std::string& path) const;

  bool restricted_ = false;
  std::vector<std::filesystem::path> folders_;    // canonical
  std::vector<std::filesystem::path> spellings_;  // each root as given and canonical
  std::size_t max_file_bytes_ = kMaxDataFileBytes;
  std::shared_ptr<const WorldFiles> only_;  // only(): these files, no disk
  FileWatcher watcher_;

  /// read() from the disk, as the roots allow.
  std::optional<std::string> read_disk(const std::string& path) const;
};

}  // namespace macsim
