// BMP textures as MACSim accepts them: square, 2^n x 2^n pixels with n < 11.
#pragma once

#include <optional>
#include <string>

namespace macsim {

class WorldFiles;

/// Why `path` (read through `files`) is not a usable texture, or nullopt when it is a readable
/// BMP of 2^n x 2^n pixels with n < 11 (decoded with OpenCV); a refused file throws as `files`.
std::optional<std::string> texture_problem(const std::string& path, const WorldFiles& files);
/// The same for a file's bytes already read (`path` names it in the message).
std::optional<std::string> texture_bytes_problem(const std::string& path, const std::string& bytes);

}  // namespace macsim
