// The codecs' module: OpenCV's imgcodecs behind the functions image_files.cpp loads.
#include <opencv2/imgcodecs.hpp>

#include "image_codecs.h"

namespace {

using macsim::images::detail::ImageCodecs;

int read_flags(bool as_stored) { return as_stored ? cv::IMREAD_UNCHANGED : cv::IMREAD_COLOR; }

const ImageCodecs kCodecs{
    [](const std::string& path, bool as_stored) { return cv::imread(path, read_flags(as_stored)); },
    [](const void* data, std::size_t size, bool as_stored) {
      const cv::Mat bytes(1, static_cast<int>(size), CV_8U, const_cast<void*>(data));
      return cv::imdecode(bytes, read_flags(as_stored));
    },
    [](const std::string& path, const cv::Mat& image) { return cv::imwrite(path, image); },
    [](const cv::Mat& image, int quality) {
      std::vector<unsigned char> jpeg;
      if (!cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality})) jpeg.clear();
      return jpeg;
    },
};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ImageCodecs* macsim_image_codecs_v1() {
  return &kCodecs;
}
