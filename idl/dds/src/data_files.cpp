#include "macsim/dds/data_files.h"

#include <filesystem>

namespace macsim::dds {

std::string data_file(const std::string& relative) {
  std::error_code error;
  const auto self = std::filesystem::canonical("/proc/self/exe", error);
  const std::filesystem::path prefix = error ? std::filesystem::path("..") : self.parent_path() / "..";
  return (prefix / "share" / "macsim" / relative).lexically_normal().string();
}

}  // namespace macsim::dds
