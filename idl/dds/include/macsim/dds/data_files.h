// Where a program finds the project's shared data (worlds, DDS profiles, the web page).
#pragma once

#include <string>

namespace macsim::dds {

/// `<prefix>/share/macsim/<relative>`, the prefix being the folder above this program's `bin/`:
/// the same rule in the build tree (build/share/macsim) and in an installation (/usr/share/macsim).
std::string data_file(const std::string& relative);

}  // namespace macsim::dds
