// Loads world files (XML, tinyxml2) into a WorldSpec; errors name the file and line.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

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

/// Receives warnings ("FILE:LINE: message") about suspicious but loadable content.
using WarningSink = std::function<void(const std::string&)>;

/// Loads a world file; throws WorldFileError and never returns a half-loaded world.
WorldSpec load_world_file(const std::string& path, const WarningSink& warn = {});

/// Loads an environment file as an <IMPORT> of that id at the origin would, resolving material
/// names against `materials` too (for adding it to a running world).
WorldSpec load_environment_file(const std::string& path, const std::string& import_id,
                                const std::vector<MaterialSpec>& materials,
                                const WarningSink& warn = {});

/// Loads a world from XML text; `name` stands for the file in messages and relative paths.
WorldSpec load_world_string(const std::string& xml, const std::string& name,
                            const WarningSink& warn = {});

}  // namespace macsim
