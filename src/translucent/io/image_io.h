// SPDX-License-Identifier: GPL-3.0-or-later
// HDR and LDR image output: OpenEXR (linear floats, exactly as computed) and PNG (tone mapped
// with an exposure in stops and a display gamma, as the seed's lit sphere widgets do, 3.6.2).
//
// Pixel data are interleaved RGB floats, row by row from the top.
//
// Every writer encodes the image in memory and writes it, with every write and the close checked,
// to a temporary file beside the target that is renamed over it only then: a failed write
// (ImageError naming the file) leaves no file and never truncates an existing one. A target that
// exists and is not a regular file (a device, a FIFO) is written in place.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace translucent::analysis {

// Thrown when an image cannot be written; the message names the file and the reason.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Extra RGB layers for an EXR file, stored as channels "<name>.R", "<name>.G", "<name>.B".
struct ExrLayer {
  std::string name;
  std::span<const float> rgb;
};

// Writes a float RGB OpenEXR file (channels R, G, B, then the extra layers); `attributes` are
// stored as string metadata (key, value), e.g. what the pixels mean and how they were computed.
void writeExr(const std::string& path, int width, int height, std::span<const float> rgb,
              std::span<const ExrLayer> layers = {},
              std::span<const std::pair<std::string, std::string>> attributes = {});

// How linear values become display values in [0, 1], before the gamma:
//   clamp     v 2^exposure clamped to [0, 1] (what a camera's sensor does);
//   reinhard  s / (1 + s) per channel, s = key v 2^exposure / average: the global operator of
//             Reinhard, Stark, Shirley & Ferwerda 2002 (Eq. 3, L/(1 + L)), scaled by the average
//             of the rendered pixels as Chang 2007 (section 3.3.3, "DirectX's HDR lighting")
//             applies it to translucent renderings (the thesis prints the operator inverted,
//             (1 + s)/s, which is not in [0, 1]). An image's average maps to key / (1 + key)
//             (0.5 at the default key 1), and no value reaches white.
enum class ToneOperator { Clamp, Reinhard };
const char* toString(ToneOperator op);
std::vector<std::string> toneOperatorNames();
// "clamp" or "reinhard"; ImageError naming `what` and the valid names otherwise.
ToneOperator parseToneOperator(std::string_view name, std::string_view what);

struct ToneMap {
  double exposure = 0.0;  // stops: values are multiplied by 2^exposure
  double gamma = 2.2;     // display gamma: v -> v^(1/gamma), after the operator
  ToneOperator op = ToneOperator::Clamp;
  double key = 1.0;       // reinhard: the display value of the average is key / (1 + key)
  // reinhard: the average linear value of the rendered pixels (withImageAverage); <= 0: 1.
  double average = 0.0;
};

// The tone map with `average` set to the mean of the values of the pixels that hold light (any
// channel > 0: the rendered pixels, not the empty background), before the exposure; 0 when none
// does. Only the reinhard operator reads it.
ToneMap withImageAverage(ToneMap tm, std::span<const float> rgb);

// Display value in [0, 1] of one linear value under a tone map: the operator (NaN and negative
// values to 0), then the power 1/gamma. The perceptual metrics (metrics.h) see images through it.
double toneMapValue(double value, const ToneMap& tm);
// The same as an 8-bit value (rounded), as written to PNG files (writePng sets the average of a
// reinhard tone map from the image when it is not set).
unsigned char toneMap(float value, const ToneMap& tm);

// Reads the first three channels of an image file (any format OpenImageIO reads) as linear
// floats; throws ImageError naming the file.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  std::vector<std::string> channel_names;  // all channels in the file
};
RgbImage readRgb(const std::string& path);

// Every channel of an EXR written by writeExr: R, G, B and the "<name>.R/G/B" layers, and the
// string attributes. Throws ImageError naming the file (also for a layer missing a channel).
struct LayeredImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  std::map<std::string, std::vector<float>> layers;
  std::map<std::string, std::string> attributes;
};
LayeredImage readExrLayers(const std::string& path);

// Writes an 8-bit RGB PNG of the tone-mapped image.
void writePng(const std::string& path, int width, int height, std::span<const float> rgb,
              const ToneMap& tm = {});

// Writes an 8-bit RGB PNG of pixels that are already 8-bit (interleaved, width*height*3), e.g. a
// false-colour map (colormap.h).
void writePng8(const std::string& path, int width, int height, std::span<const uint8_t> rgb8);

// Writes `bytes` to `file` (created or truncated) and closes it; false when any write, the flush
// or the close failed (a device such as /dev/full too); errno then holds the first failure's
// reason (ENOSPC, ENAMETOOLONG, EACCES: writeErrorText()). Shared with the CLI's outputs.
bool writeBytes(const std::string& file, std::string_view bytes);
// Why the last writeBytes() failed, from errno ("No space left on device").
std::string writeErrorText();

}  // namespace translucent::analysis
