// Image files (PNG, JPEG, BMP...) read and written through OpenCV's imgcodecs, which a program
// loads only when it first reads or writes one: loading it (with GDAL and the rest it links)
// costs every process about 0.2 s of CPU at its start, and most of them never touch a file.
#pragma once

#include <opencv2/core/mat.hpp>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace macsim::images {

/// How a file's pixels come back: 8-bit BGR (alpha and depth dropped), or as stored.
enum class Pixels { Bgr, AsStored };

/// The image in the file at `path`; empty when it cannot be read or decoded (as cv::imread).
cv::Mat read_image(const std::string& path, Pixels pixels = Pixels::Bgr);

/// The image whose file's bytes are `data`; empty when they do not decode (as cv::imdecode).
cv::Mat decode_image(const void* data, std::size_t size, Pixels pixels = Pixels::Bgr);

/// Writes `image` to `path` in the format of its extension; false when it cannot or it is empty.
bool write_image(const std::string& path, const cv::Mat& image);

/// `image` as a JPEG file's bytes at `quality` (0-100); empty when it cannot be encoded.
std::vector<unsigned char> encode_jpeg(const cv::Mat& image, int quality);

/// Where the codecs' module lies beside this program: lib/macsim/ above its bin/ (empty if unknown).
std::string codecs_module_file();

/// The codecs could not be loaded (an installation without lib/macsim/libmacsim_image_codecs.so).
struct CodecsUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace macsim::images
