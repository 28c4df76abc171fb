#include "macsim/sim_core/texture.h"

#include <opencv2/core.hpp>

#include "macsim/images/image_files.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim {

std::optional<std::string> texture_problem(const std::string& path, const WorldFiles& files) {
  const auto bytes = files.read(path);
  if (!bytes) return "texture file '" + path + "' does not exist";
  return texture_bytes_problem(path, *bytes);
}

std::optional<std::string> texture_bytes_problem(const std::string& path,
                                                 const std::string& bytes) {
  if (bytes.size() < 2 || bytes[0] != 'B' || bytes[1] != 'M') {
    return "texture '" + path + "' is not a BMP file";
  }
  // A header that promises more than the file holds is refused here, before OpenCV's decoder
  // (which would log its own complaint on stderr).
  const auto u32 = [&](std::size_t at) {
    return std::size_t(uint8_t(bytes[at])) | std::size_t(uint8_t(bytes[at + 1])) << 8 |
           std::size_t(uint8_t(bytes[at + 2])) << 16 | std::size_t(uint8_t(bytes[at + 3])) << 24;
  };
  if (bytes.size() < 54 || u32(2) > bytes.size() || u32(10) >= bytes.size()) {
    return "texture '" + path + "' is a truncated BMP file";
  }
  cv::Mat image;
  try {
    image = images::decode_image(bytes.data(), bytes.size(), images::Pixels::AsStored);
  } catch (const cv::Exception&) {
  } catch (const images::CodecsUnavailable& e) {
    return "texture '" + path + "' cannot be checked: " + e.what();
  }
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
