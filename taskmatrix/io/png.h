// PNG files of rendered images (lodepng): colour as RGB, depth as 8-bit grey.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "taskmatrix/core/scene_view.h"

namespace taskmatrix::io {

// The PNG file's bytes. Throws std::runtime_error when lodepng cannot encode the image.
std::vector<std::uint8_t> encode_png(const core::RgbImage& image);

// Write atomically, making the parent folder. Depth is written as grey, near bright (255),
// far dark (40), scaled to [near, far] of the finite pixels; nothing hit is black. Throw
// std::runtime_error naming the file on failure.
void write_png(const std::filesystem::path& file, const core::RgbImage& image);
void write_depth_png(const std::filesystem::path& file, const core::DepthImage& image);

}  // namespace taskmatrix::io
