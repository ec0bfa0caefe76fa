// SPDX-License-Identifier: GPL-3.0-or-later
// libtranslucent_oiio.so: image encoding, reading and text rendering through OpenImageIO, behind
// the table of oiio_plugin.h. Loaded with dlopen on the first image read or written (plugins.h),
// so that OpenImageIO and its dependencies are mapped only in processes that use images. Uses no
// library of ours: only the header-only interface.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <exception>
#include <memory>

#include "translucent/io/oiio_plugin.h"

namespace {

using translucent::io::OiioApi;
using translucent::io::OiioEncodeRequest;
using translucent::io::OiioImageInfo;

// Every entry point catches everything: an exception must not cross the dlopen boundary.
template <typename F>
bool guarded(std::string* error, F&& f) noexcept {
  try {
    return f();
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "unknown error";
  }
  return false;
}

bool encode(const OiioEncodeRequest& r, std::vector<unsigned char>* bytes,
            std::string* error) noexcept {
  return guarded(error, [&] {
    const OIIO::TypeDesc type = r.float_pixels ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(r.width, r.height, r.channels, type);
    if (r.channel_names != nullptr)
      spec.channelnames.assign(r.channel_names, r.channel_names + r.channels);
    for (size_t i = 0; i < r.attribute_count; ++i)
      spec.attribute(r.attributes[i].key, r.attributes[i].value);
    auto out = OIIO::ImageOutput::create(r.path);  // the format from the target's extension
    if (!out) {
      *error = OIIO::geterror();
      return false;
    }
    OIIO::Filesystem::IOVecOutput memory(*bytes);
    if (!out->supports("ioproxy") || !out->set_ioproxy(&memory)) {
      *error = std::string("the ") + out->format_name() + " writer cannot write to memory";
      return false;
    }
    if (!out->open(r.path, spec)) {
      *error = out->geterror();
      return false;
    }
    if (!out->write_image(type, r.pixels)) {
      *error = out->geterror();
      out->close();
      return false;
    }
    if (!out->close()) {
      *error = out->geterror();
      return false;
    }
    return true;
  });
}

void* openImage(const char* path, OiioImageInfo* info, std::string* error) noexcept {
  try {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
      *error = OIIO::geterror();
      return nullptr;
    }
    const OIIO::ImageSpec& spec = in->spec();
    info->width = spec.width;
    info->height = spec.height;
    info->depth = spec.depth;
    info->channels = spec.nchannels;
    info->channel_names = spec.channelnames;
    info->string_attributes.clear();
    for (const auto& p : spec.extra_attribs)
      if (p.type() == OIIO::TypeDesc::STRING)
        info->string_attributes.emplace_back(p.name().string(), p.get_string());
    return in.release();
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "unknown error";
  }
  return nullptr;
}

bool readPixels(void* image, int channels, float* out, std::string* error) noexcept {
  return guarded(error, [&] {
    auto* in = static_cast<OIIO::ImageInput*>(image);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, out)) {
      *error = in->geterror();
      return false;
    }
    return true;
  });
}

void closeImage(void* image) noexcept {
  std::unique_ptr<OIIO::ImageInput> in(static_cast<OIIO::ImageInput*>(image));
  if (in) {
    try {
      in->close();
    } catch (...) {
      // Closing a file only read from: nothing to report.
    }
  }
}

bool renderText(unsigned char* rgb8, int width, int height, int x, int y, const char* text,
                int font_size, const char* font, const float* ink, int align_x,
                std::string* error) noexcept {
  return guarded(error, [&] {
    // An ImageBuf over the caller's pixels: the text is blended into them in place.
    OIIO::ImageBuf buf(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8), rgb8);
    const auto align = align_x < 0   ? OIIO::ImageBufAlgo::TextAlignX::Left
                       : align_x > 0 ? OIIO::ImageBufAlgo::TextAlignX::Right
                                     : OIIO::ImageBufAlgo::TextAlignX::Center;
    if (!OIIO::ImageBufAlgo::render_text(buf, x, y, text, font_size, font, {ink, 3}, align,
                                         OIIO::ImageBufAlgo::TextAlignY::Top)) {
      *error = buf.geterror();
      return false;
    }
    return true;
  });
}

constexpr OiioApi kApi{{OiioApi::kAbiVersion}, encode, openImage, readPixels, closeImage,
                       renderText};

}  // namespace

extern "C" __attribute__((visibility("default"))) const void* translucent_oiio_plugin() {
  // No thread pools, OpenImageIO's or OpenEXR's: their worker threads do not survive a fork(),
  // and `translucent compare` forks the process that renders each technique after it has read
  // or written a reference's EXR. A child that then read an EXR (an environment map) queued
  // its work to a pool whose threads exist only in the parent and waited forever. Reading and
  // writing stay on the calling thread (the images here are small).
  static const bool configured = [] {
    OIIO::attribute("threads", 1);
    OIIO::attribute("exr_threads", -1);  // -1: no OpenEXR thread pool at all
    return true;
  }();
  (void)configured;
  return &kApi;
}
