// BMP textures as MACSim accepts them: square, 2^n x 2^n pixels with n < 11.
#pragma once

#include <optional>
#include <string>

namespace macsim {

/// Why `path` is not a usable texture, or nullopt when it is a readable BMP of 2^n x 2^n
/// pixels with n < 11 (decoded with OpenCV).
std::optional<std::string> texture_problem(const std::string& path);
/// The same for a file's bytes already read (`path` names it in the message).
std::optional<std::string> texture_bytes_problem(const std::string& path, const std::string& bytes);

}  // namespace macsim
