// What the codecs' module (image_codecs_module.cpp, linked with OpenCV's imgcodecs) hands the
// programs that load it (image_files.cpp). Both sides are built from this header in one build.
#pragma once

#include <opencv2/core/mat.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace macsim::images::detail {

/// The module's functions; `as_stored` keeps a file's channels and depth (else 8-bit BGR).
struct ImageCodecs {
  cv::Mat (*read)(const std::string& path, bool as_stored);
  cv::Mat (*decode)(const void* data, std::size_t size, bool as_stored);
  bool (*write)(const std::string& path, const cv::Mat& image);
  std::vector<unsigned char> (*encode_jpeg)(const cv::Mat& image, int quality);
};

/// The file name programs load the module by (through their run path), and its entry point.
inline constexpr const char* kModuleFile = "libmacsim_image_codecs.so";
inline constexpr const char* kEntryPoint = "macsim_image_codecs_v1";

}  // namespace macsim::images::detail
