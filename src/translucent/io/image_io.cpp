// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/io/image_io.h"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "translucent/io/oiio_plugin.h"
#include "translucent/io/output_guard.h"

namespace translucent::analysis {
namespace {

void checkSize(const std::string& path, int width, int height, size_t values) {
  if (width < 1 || height < 1)
    throw ImageError(fmt::format("cannot write '{}': image size {}x{}: expected at least 1x1",
                                 path, width, height));
  const size_t expected = static_cast<size_t>(width) * static_cast<size_t>(height) * 3;
  if (values != expected)
    throw ImageError(fmt::format("cannot write '{}': {} values for a {}x{} RGB image: expected {}",
                                 path, values, width, height, expected));
}

std::string_view asText(const std::vector<unsigned char>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

// A temporary name beside `path`, unique per process and call; hidden, so that a listing of the
// folder during the write does not show a half-written image.
std::string temporaryName(const std::string& path) {
  static std::atomic<uint64_t> counter{0};
  return io::temporaryBeside(path, fmt::format(".tmp-{}-{}", ::getpid(), counter.fetch_add(1)));
}


// OpenImageIO, from its module (oiio_plugin.h), loaded on the first image read or written; a
// module that cannot be loaded is reported as the failure to read or write `path`.
const io::OiioApi& oiio(const std::string& path, const char* verb) {
  try {
    return io::plugin<io::OiioApi>("oiio");
  } catch (const io::PluginError& e) {
    throw ImageError(fmt::format("cannot {} '{}': {}", verb, path, e.what()));
  }
}

// The image is encoded in memory (OpenImageIO's PNG writer does not report failed writes, e.g.
// on a full disk) and the bytes are written with every call checked, to a temporary file that
// is renamed over `path` only when all of them succeeded: a failed or interrupted write leaves
// nothing behind and never truncates an existing image. A target that exists and is not a
// regular file (/dev/stdout, a FIFO, /dev/full) is written in place, since renaming would
// replace the device node; its errors are reported too.
// `request` describes the pixels; its path is set here.
void write(const std::string& path, io::OiioEncodeRequest request) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw ImageError(fmt::format("cannot write '{}': it is a folder: expected a file name", path));
  const io::OiioApi& api = oiio(path, "write");
  request.path = path.c_str();
  std::vector<unsigned char> bytes;
  std::string error;
  if (!api.encode(request, &bytes, &error))
    throw ImageError(fmt::format("cannot write '{}': {}", path, error));
  if (bytes.empty()) throw ImageError(fmt::format("cannot write '{}': the encoder produced nothing", path));

  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) {
    if (!writeBytes(path, asText(bytes)))
      throw ImageError(fmt::format("cannot write '{}': {}", path, writeErrorText()));
    return;
  }
  const std::string tmp = temporaryName(path);
  if (!writeBytes(tmp, asText(bytes))) {
    const std::string why = writeErrorText();
    fs::remove(tmp, ec);
    throw ImageError(fmt::format("cannot write '{}': {}", path, why));
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string message = ec.message();
    fs::remove(tmp, ec);
    throw ImageError(fmt::format("cannot write '{}': {}", path, message));
  }
}

}  // namespace

bool writeBytes(const std::string& file, std::string_view bytes) {
  errno = 0;
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) return false;
  int first = 0;  // the first failure's errno: the close after a failed write may set another
  const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  if (!wrote) first = errno;
  const bool flushed = std::fflush(f) == 0;
  if (!flushed && first == 0) first = errno;
  const bool closed = std::fclose(f) == 0;
  if (!closed && first == 0) first = errno;
  errno = first;
  return wrote && flushed && closed;
}

std::string writeErrorText() {
  return errno != 0 ? std::strerror(errno) : std::string("write failed");
}

void writeExr(const std::string& path, int width, int height, std::span<const float> rgb,
              std::span<const ExrLayer> layers,
              std::span<const std::pair<std::string, std::string>> attributes) {
  checkSize(path, width, height, rgb.size());
  for (const auto& l : layers) checkSize(path + " (layer " + l.name + ")", width, height, l.rgb.size());
  const int channels = 3 * (1 + static_cast<int>(layers.size()));
  std::vector<std::string> names = {"R", "G", "B"};
  for (const auto& l : layers)
    for (const char* c : {"R", "G", "B"}) names.push_back(l.name + "." + c);
  std::vector<const char*> nameText;
  for (const auto& n : names) nameText.push_back(n.c_str());
  std::vector<io::OiioStringAttribute> attributeText = {{"compression", "zip"}};
  for (const auto& [key, value] : attributes) attributeText.push_back({key.c_str(), value.c_str()});
  // Interleave the base image and the layers pixel by pixel.
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  std::vector<float> data(pixels * static_cast<size_t>(channels));
  for (size_t p = 0; p < pixels; ++p) {
    float* dst = &data[p * static_cast<size_t>(channels)];
    for (size_t c = 0; c < 3; ++c) dst[c] = rgb[3 * p + c];
    for (size_t l = 0; l < layers.size(); ++l)
      for (size_t c = 0; c < 3; ++c) dst[3 * (l + 1) + c] = layers[l].rgb[3 * p + c];
  }
  write(path, {nullptr, width, height, channels, nameText.data(), true, data.data(),
               attributeText.data(), attributeText.size()});
}

// Checks before reading an image file: a directory or an empty file gets its own message
// (OpenImageIO's is "could not find a format reader"), and a header's size is checked before
// anything is allocated for it (a corrupt header can claim 0, negative or billions of pixels).
// An OpenEXR header's attribute sizes against the file's size, before OpenEXR reads it: an
// attribute whose declared size runs past the end of the file cannot be valid, and OpenEXR 3.1
// allocates that size first (fuzz_image, 2026-12-02: a 402-byte file declaring a 1.9 GB string
// attribute took 13 s and 2 GB to refuse). Only the first header's attribute list is walked
// (name, type name, int32 size, value); anything this walk does not understand is left to
// OpenEXR.
static void checkExrHeader(const std::string& path, std::uintmax_t fileSize) {
  std::ifstream f(path, std::ios::binary);
  char magic[4] = {};
  if (!f.read(magic, 4) || !(magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01))
    return;
  f.seekg(8);  // magic, version and flags
  auto readName = [&](std::string& out) {
    out.clear();
    for (int i = 0; i < 256; ++i) {
      const int c = f.get();
      if (c == std::char_traits<char>::eof()) return false;
      if (c == 0) return true;
      out.push_back(static_cast<char>(c));
    }
    return false;  // longer than OpenEXR allows: OpenEXR says why
  };
  for (int attribute = 0; attribute < 100000; ++attribute) {
    std::string name, type;
    if (!readName(name) || name.empty()) return;  // end of the header (or not walkable)
    if (!readName(type)) return;
    unsigned char b[4];
    if (!f.read(reinterpret_cast<char*>(b), 4)) return;
    const auto size = static_cast<int32_t>(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 |
                                           uint32_t(b[3]) << 24);
    const auto pos = static_cast<std::uintmax_t>(f.tellg());
    const std::uintmax_t remaining = fileSize > pos ? fileSize - pos : 0;
    if (size < 0 || static_cast<std::uintmax_t>(size) > remaining)
      throw ImageError(fmt::format("cannot read '{}': OpenEXR header attribute '{}' ({}) declares {} "
                                   "bytes, more than the {} left in the file: expected a valid "
                                   "OpenEXR header", path, name, type, size, remaining));
    f.seekg(size, std::ios::cur);
  }
}

static void checkImageFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ImageError(fmt::format("cannot read '{}': it is a directory: expected an image file", path));
  if (std::filesystem::exists(path, ec) && std::filesystem::is_regular_file(path, ec)) {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size == 0)
      throw ImageError(fmt::format("cannot read '{}': the file is empty: expected an image", path));
    if (!ec) checkExrHeader(path, size);
  }
}
static void checkImageSize(const std::string& path, const io::OiioImageInfo& spec) {
  constexpr long long kMaxPixels = 1LL << 28;  // 3 GiB of float RGB
  const long long pixels = static_cast<long long>(spec.width) * spec.height;
  if (spec.width < 1 || spec.height < 1 || spec.depth > 1 || pixels > kMaxPixels)
    throw ImageError(fmt::format("cannot read '{}': image size {}x{}{}: expected at least 1x1 "
                                 "and at most {} pixels", path, spec.width, spec.height,
                                 spec.depth > 1 ? fmt::format("x{}", spec.depth) : "", kMaxPixels));
}

namespace {

// An image file opened by the module, closed when it goes out of scope.
class OpenedImage {
 public:
  explicit OpenedImage(const std::string& path) : api_(oiio(path, "read")) {
    std::string error;
    image_ = api_.open_image(path.c_str(), &info_, &error);
    if (image_ == nullptr) throw ImageError(fmt::format("cannot read '{}': {}", path, error));
  }
  ~OpenedImage() { api_.close_image(image_); }
  OpenedImage(const OpenedImage&) = delete;
  OpenedImage& operator=(const OpenedImage&) = delete;

  const io::OiioImageInfo& info() const { return info_; }
  // The first `channels` channels as interleaved floats; false with the reason in `error`.
  bool read(int channels, float* out, std::string& error) const {
    return api_.read_pixels(image_, channels, out, &error);
  }

 private:
  const io::OiioApi& api_;
  io::OiioImageInfo info_;
  void* image_ = nullptr;
};

}  // namespace

RgbImage readRgb(const std::string& path) {
  checkImageFile(path);
  const OpenedImage in(path);
  const io::OiioImageInfo& spec = in.info();
  checkImageSize(path, spec);
  if (spec.channels < 3)
    throw ImageError(fmt::format("cannot read '{}': {} channel(s): expected at least R, G, B",
                                 path, spec.channels));
  RgbImage img;
  img.width = spec.width;
  img.height = spec.height;
  img.channel_names = spec.channel_names;
  img.rgb.resize(static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) * 3);
  if (std::string message; !in.read(3, img.rgb.data(), message))
    throw ImageError(fmt::format("cannot read '{}': {}", path, message));
  return img;
}

LayeredImage readExrLayers(const std::string& path) {
  checkImageFile(path);
  const OpenedImage in(path);
  const io::OiioImageInfo& spec = in.info();
  checkImageSize(path, spec);
  const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  const auto nc = static_cast<size_t>(spec.channels);
  std::vector<float> data(pixels * nc);
  if (std::string message; !in.read(spec.channels, data.data(), message))
    throw ImageError(fmt::format("cannot read '{}': {}", path, message));
  LayeredImage img;
  img.width = spec.width;
  img.height = spec.height;
  for (const auto& [key, value] : spec.string_attributes) img.attributes[key] = value;
  // Channel c of layer `name` ("" for the base image) -> its position in the file.
  auto channel = [&](const std::string& name, const char* c) -> size_t {
    const std::string full = name.empty() ? c : name + "." + c;
    for (size_t i = 0; i < nc; ++i)
      if (spec.channel_names[i] == full) return i;
    throw ImageError(fmt::format("cannot read '{}': no channel '{}'", path, full));
  };
  std::vector<std::string> names = {""};
  for (const auto& n : spec.channel_names)
    if (n.size() > 2 && n.ends_with(".R")) names.push_back(n.substr(0, n.size() - 2));
  for (const std::string& name : names) {
    const size_t idx[3] = {channel(name, "R"), channel(name, "G"), channel(name, "B")};
    std::vector<float>& out = name.empty() ? img.rgb : img.layers[name];
    out.resize(pixels * 3);
    for (size_t p = 0; p < pixels; ++p)
      for (size_t c = 0; c < 3; ++c) out[3 * p + c] = data[p * nc + idx[c]];
  }
  return img;
}

const char* toString(ToneOperator op) {
  return op == ToneOperator::Reinhard ? "reinhard" : "clamp";
}

std::vector<std::string> toneOperatorNames() { return {"clamp", "reinhard"}; }

ToneOperator parseToneOperator(std::string_view name, std::string_view what) {
  if (name == "clamp") return ToneOperator::Clamp;
  if (name == "reinhard") return ToneOperator::Reinhard;
  throw ImageError(fmt::format("{} '{}': expected a tone map operator: clamp or reinhard", what, name));
}

ToneMap withImageAverage(ToneMap tm, std::span<const float> rgb) {
  double sum = 0.0;
  size_t values = 0;
  for (size_t p = 0; p + 2 < rgb.size(); p += 3) {
    const float r = rgb[p], g = rgb[p + 1], b = rgb[p + 2];
    if (!(r > 0.0f || g > 0.0f || b > 0.0f)) continue;  // background (or NaN)
    for (const float v : {r, g, b})
      if (std::isfinite(v) && v > 0.0f) sum += double(v);
    values += 3;
  }
  tm.average = values > 0 ? sum / double(values) : 0.0;
  return tm;
}

double toneMapValue(double value, const ToneMap& tm) {
  double v = value * std::exp2(tm.exposure);
  if (!(v > 0.0)) return 0.0;  // also NaN
  if (tm.op == ToneOperator::Reinhard) {
    const double s = tm.key * v / (tm.average > 0.0 ? tm.average : 1.0);
    v = std::isinf(s) ? 1.0 : s / (1.0 + s);
  } else {
    v = std::min(v, 1.0);
  }
  return std::pow(v, 1.0 / tm.gamma);
}

unsigned char toneMap(float value, const ToneMap& tm) {
  return static_cast<unsigned char>(
      std::lround(255.0 * toneMapValue(static_cast<double>(value), tm)));
}

void writePng(const std::string& path, int width, int height, std::span<const float> rgb,
              const ToneMap& tm) {
  checkSize(path, width, height, rgb.size());
  if (!std::isfinite(tm.exposure))
    throw ImageError(fmt::format("cannot write '{}': exposure is {}: expected a finite number of "
                                 "stops", path, tm.exposure));
  if (!(std::isfinite(tm.gamma) && tm.gamma > 0.0))
    throw ImageError(fmt::format("cannot write '{}': gamma is {}: expected a finite value > 0",
                                 path, tm.gamma));
  if (!(std::isfinite(tm.key) && tm.key > 0.0))
    throw ImageError(fmt::format("cannot write '{}': tone map key is {}: expected a finite value > 0",
                                 path, tm.key));
  const ToneMap t = tm.op == ToneOperator::Reinhard && !(tm.average > 0.0) ? withImageAverage(tm, rgb) : tm;
  std::vector<unsigned char> data(rgb.size());
  for (size_t i = 0; i < rgb.size(); ++i) data[i] = toneMap(rgb[i], t);
  write(path, {nullptr, width, height, 3, nullptr, false, data.data(), nullptr, 0});
}

void writePng8(const std::string& path, int width, int height, std::span<const uint8_t> rgb8) {
  checkSize(path, width, height, rgb8.size());
  write(path, {nullptr, width, height, 3, nullptr, false, rgb8.data(), nullptr, 0});
}

}  // namespace translucent::analysis
