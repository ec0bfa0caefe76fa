// SPDX-License-Identifier: GPL-3.0-or-later
// The interface of the OpenImageIO module (oiio_module.cpp -> libtranslucent_oiio.so, loaded by
// plugins.h): what image_io.cpp and analysis/colormap.cpp need of OpenImageIO. Header-only
// types; no function throws. An error is returned as false (or nullptr) with the reason in
// *error, without the file name: the caller's message names the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "translucent/io/plugins.h"

namespace translucent::io {

struct OiioStringAttribute {
  const char* key;
  const char* value;
};

// An image to encode, in the format named by the extension of `path` (which is not opened).
struct OiioEncodeRequest {
  const char* path;
  int width, height, channels;
  const char* const* channel_names;  // `channels` names, or nullptr for OpenImageIO's defaults
  bool float_pixels;                 // float, else 8-bit unsigned; interleaved, rows from the top
  const void* pixels;
  const OiioStringAttribute* attributes;  // stored as string metadata (e.g. "compression")
  size_t attribute_count;
};

// What an opened image file's header says.
struct OiioImageInfo {
  int width = 0, height = 0, depth = 0, channels = 0;
  std::vector<std::string> channel_names;
  std::vector<std::pair<std::string, std::string>> string_attributes;
};

struct OiioApi {
  static constexpr uint32_t kAbiVersion = 1;
  PluginHeader header;
  // Encodes the image in memory (writers that do not report failed writes to a file cannot hide
  // them: the caller writes the bytes).
  bool (*encode)(const OiioEncodeRequest& request, std::vector<unsigned char>* bytes,
                 std::string* error) noexcept;
  // Opens an image file and reads its header; the handle is for read_pixels and close_image.
  void* (*open_image)(const char* path, OiioImageInfo* info, std::string* error) noexcept;
  // The first `channels` channels of the first subimage as interleaved floats, into `out`
  // (width * height * channels values).
  bool (*read_pixels)(void* image, int channels, float* out, std::string* error) noexcept;
  void (*close_image)(void* image) noexcept;
  // Draws `text` into an 8-bit RGB image (interleaved, rows from the top), its top at row y and
  // at x by align_x (-1: starts at x, 0: centred on x, 1: ends at x), in `font` (a font name or
  // file) of `font_size` pixels, blended over the pixels in colour `ink` (0..1).
  bool (*render_text)(unsigned char* rgb8, int width, int height, int x, int y, const char* text,
                      int font_size, const char* font, const float* ink, int align_x,
                      std::string* error) noexcept;
};

}  // namespace translucent::io
