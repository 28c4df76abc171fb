#include "macsim/sim_core/texture.h"

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

namespace macsim {

std::optional<std::string> texture_problem(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) return "texture file '" + path + "' does not exist";
  char magic[2] = {};
  std::ifstream(path, std::ios::binary).read(magic, 2);
  if (magic[0] != 'B' || magic[1] != 'M') return "texture '" + path + "' is not a BMP file";
  const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) return "texture '" + path + "' cannot be decoded as a BMP image";
  const int w = image.cols, h = image.rows;
  const bool power_of_two = w > 0 && (w & (w - 1)) == 0;
  if (w != h || !power_of_two || w > 1024) {
    return "texture '" + path + "' is " + std::to_string(w) + "x" + std::to_string(h) +
           " pixels; textures must be 2^n x 2^n with n < 11 (1x1 up to 1024x1024)";
  }
  return std::nullopt;
}

}  // namespace macsim
