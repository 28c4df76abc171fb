#include "macsim/images/image_files.h"

#include <dlfcn.h>

#include <filesystem>
#include <limits>

#include "image_codecs.h"

namespace macsim::images {
namespace {

using detail::ImageCodecs;

}  // namespace

std::string codecs_module_file() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&codecs_module_file), &info) == 0 ||
      info.dli_fname == nullptr)
    return {};
  std::error_code error;
  const auto object = std::filesystem::canonical(info.dli_fname, error);
  if (error) return {};
  return (object.parent_path() / ".." / "lib" / "macsim" / detail::kModuleFile)
      .lexically_normal()
      .string();
}

namespace {

/// The module, loaded at the first call; a failed load is tried again at the next call. Found
/// through the program's run path (lib/macsim of the build tree or of the installation), else
/// beside the program's bin/: a program under AddressSanitizer calls dlopen through the
/// sanitizer's library, whose run path is searched instead of the program's.
const ImageCodecs& codecs() {
  static const ImageCodecs* const loaded = [] {
    void* module = dlopen(detail::kModuleFile, RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr) {
      const std::string first_error = dlerror();
      const std::string beside = codecs_module_file();
      if (!beside.empty()) module = dlopen(beside.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (module == nullptr) {
        throw CodecsUnavailable(std::string("image files need ") + detail::kModuleFile +
                                " (lib/macsim/ of the installation), which did not load: " +
                                first_error);
      }
    }
    using Entry = const ImageCodecs* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(module, detail::kEntryPoint));
    if (entry == nullptr) {
      throw CodecsUnavailable(std::string(detail::kModuleFile) + " has no " +
                              detail::kEntryPoint + ": it is not this build's");
    }
    return entry();
  }();
  return *loaded;
}

}  // namespace

cv::Mat read_image(const std::string& path, Pixels pixels) {
  return codecs().read(path, pixels == Pixels::AsStored);
}

cv::Mat decode_image(const void* data, std::size_t size, Pixels pixels) {
  if (size == 0 || size > static_cast<std::size_t>(std::numeric_limits<int>::max())) return {};
  return codecs().decode(data, size, pixels == Pixels::AsStored);
}

bool write_image(const std::string& path, const cv::Mat& image) {
  return !image.empty() && codecs().write(path, image);
}

std::vector<unsigned char> encode_jpeg(const cv::Mat& image, int quality) {
  if (image.empty()) return {};
  return codecs().encode_jpeg(image, quality);
}

}  // namespace macsim::images
