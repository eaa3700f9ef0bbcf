#include "taskmatrix/io/png.h"

#include <lodepng.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "taskmatrix/io/text_file.h"

namespace taskmatrix::io {

namespace {

void write_encoded(const std::filesystem::path& file, const std::vector<unsigned char>& png) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  write_file_atomically(file, {reinterpret_cast<const char*>(png.data()), png.size()});
}

std::vector<unsigned char> encode(const std::vector<unsigned char>& pixels, int width, int height,
                                  LodePNGColorType type, const std::string& what) {
  std::vector<unsigned char> png;
  const unsigned err = lodepng::encode(png, pixels, static_cast<unsigned>(width),
                                       static_cast<unsigned>(height), type, 8);
  if (err) throw std::runtime_error(what + ": cannot encode PNG: " + lodepng_error_text(err));
  return png;
}

}  // namespace

std::vector<std::uint8_t> encode_png(const core::RgbImage& image) {
  return encode(image.pixels, image.width, image.height, LCT_RGB, "image");
}

void write_png(const std::filesystem::path& file, const core::RgbImage& image) {
  write_encoded(file, encode(image.pixels, image.width, image.height, LCT_RGB, file.string()));
}

void write_depth_png(const std::filesystem::path& file, const core::DepthImage& image) {
  float lo = std::numeric_limits<float>::infinity(), hi = 0;
  for (float v : image.metres) {
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  std::vector<unsigned char> grey(image.metres.size(), 0);
  for (size_t i = 0; i < grey.size(); ++i) {
    const float v = image.metres[i];
    if (!std::isfinite(v)) continue;
    const float t = hi > lo ? (v - lo) / (hi - lo) : 0.0f;
    grey[i] = static_cast<unsigned char>(std::lround(255.0f - 215.0f * t));  // near 255, far 40
  }
  write_encoded(file, encode(grey, image.width, image.height, LCT_GREY, file.string()));
}

}  // namespace taskmatrix::io
