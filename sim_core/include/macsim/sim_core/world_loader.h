// Loads world files (XML, tinyxml2) into a WorldSpec; errors name the file and line.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "macsim/sim_core/world_bounds.h"
#include "macsim/sim_core/world_spec.h"

namespace macsim {

/// A world file that cannot be loaded: `what()` reads "FILE:LINE: message".
class WorldFileError : public std::runtime_error {
 public:
  WorldFileError(std::string file, int line, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  std::string message_;
};

/// Where a world's files are read from: the disk, or a set held in memory (tests, fuzzing).
class WorldFiles {
 public:
  virtual ~WorldFiles() = default;
  /// The bytes of the regular file at `path`, or nothing (missing, a directory, unreadable).
  virtual std::optional<std::string> read(const std::string& path) const = 0;
  /// One spelling per file (symlinks resolved where there are any), to find import cycles.
  virtual std::string identity(const std::string& path) const = 0;
};

/// The file system; never throws (a path it refuses reads as missing).
const WorldFiles& disk_files();

/// Told of every file read (its path as asked, its bytes): a recorded session embeds them.
using FileWatcher = std::function<void(const std::string& path, const std::string& bytes)>;

/// The files of `inner`, each one read told to a watcher first.
class WatchedFiles : public WorldFiles {
 public:
  WatchedFiles(const WorldFiles& inner, FileWatcher watcher)
      : inner_(inner), watcher_(std::move(watcher)) {}
  std::optional<std::string> read(const std::string& path) const override;
  std::string identity(const std::string& path) const override { return inner_.identity(path); }

 private:
  const WorldFiles& inner_;
  FileWatcher watcher_;
};

/// Files held in memory by their lexically normal path.
class MemoryFiles : public WorldFiles {
 public:
  void add(const std::string& path, std::string bytes);
  std::optional<std::string> read(const std::string& path) const override;
  std::string identity(const std::string& path) const override;

 private:
  std::map<std::string, std::string> files_;
};

/// How much one world may hold, so a generated or hostile file is refused fast instead of
/// exhausting memory; `macsim --max-objects`, `--max-import-depth`, `--max-imported-files`.
struct LoadLimits {
  std::size_t max_import_depth = bounds::kMaxImportDepth;      ///< <IMPORT>s nested
  std::size_t max_imported_files = bounds::kMaxImportedFiles;  ///< imports read in all
  std::size_t max_objects = bounds::kMaxObjects;               ///< objects, imported included
};

/// What a load may be told besides the file. Its warnings about suspicious but loadable content
/// ("FILE:LINE: warning: message") go to sim_core's log (log_sink.h).
struct LoadOptions {
  LoadLimits limits;                        ///< the caps on imports and objects
  const WorldFiles* files = &disk_files();  ///< where the file and its imports are read
};

/// Loads a world file; throws WorldFileError (or what `options.files` throws for a file it
/// refuses) and never returns a half-loaded world.
WorldSpec load_world_file(const std::string& path, const LoadOptions& options);
WorldSpec load_world_file(const std::string& path);

/// Loads an environment file as an <IMPORT> of that id at the origin would, resolving material
/// names against `materials` too (for adding it to a running world), reading through `files`.
WorldSpec load_environment_file(const std::string& path, const std::string& import_id,
                                const std::vector<MaterialSpec>& materials,
                                const WorldFiles& files = disk_files());

/// Loads an environment from XML text as load_environment_file would from a file called `name`
/// (it stands for the file in messages); the text imports nothing from disk.
WorldSpec load_environment_string(const std::string& xml, const std::string& import_id,
                                  const std::vector<MaterialSpec>& materials,
                                  const std::string& name);

/// Loads a world from XML text; `name` stands for the file in messages and relative paths.
WorldSpec load_world_string(const std::string& xml, const std::string& name,
                            const LoadOptions& options);
WorldSpec load_world_string(const std::string& xml, const std::string& name);

}  // namespace macsim
