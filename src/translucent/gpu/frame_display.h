// SPDX-License-Identifier: GPL-3.0-or-later
// Showing a linear RGB image on screen: the image is uploaded to a float texture and drawn over a
// whole framebuffer (any FBO, e.g. a QOpenGLWidget's), tone mapped exactly like the CLI's PNG
// output (analysis::toneMap): v -> clamp(v 2^exposure, 0, 1)^(1/gamma), or Reinhard's
// s/(1 + s) with s = key v 2^exposure / average; NaN and negative -> 0.
// A smaller image is stretched with bilinear filtering (the explorer's half-resolution frames
// while the view moves, seed 3.6.4).
//
// This header includes no GL header, so that Qt translation units may use it (Qt's GL headers
// and libepoxy's clash). Every call needs a current OpenGL 4.5 core context: the one that was
// current when the FrameDisplay was created (its GL objects belong to that context).
#pragma once

#include <memory>
#include <span>
#include <string>

#include "translucent/io/image_io.h"

namespace translucent::gpu {

// What the context current on the calling thread is (GL_VERSION, GL_RENDERER, ...), read through
// libepoxy. Needs some current OpenGL context.
struct CurrentContextInfo {
  int major = 0, minor = 0;
  bool core_profile = false;
  std::string version, renderer;
  bool atLeast45Core() const { return core_profile && (major > 4 || (major == 4 && minor >= 5)); }
};
CurrentContextInfo currentContextInfo();

class FrameDisplay {
 public:
  // Builds the tone-mapping program; throws GlError when it cannot (the message says why).
  FrameDisplay();
  ~FrameDisplay();  // the creating context must be current
  FrameDisplay(const FrameDisplay&) = delete;
  FrameDisplay& operator=(const FrameDisplay&) = delete;

  // Uploads an image: interleaved linear RGB floats, rows from the top, width*height*3 values
  // (GlError otherwise).
  void upload(std::span<const float> rgb, int width, int height);
  bool hasImage() const;

  // Draws the uploaded image over the viewport (0, 0, width, height) of `framebuffer`, tone
  // mapped; clears to black when no image was uploaded. Leaves the framebuffer bound and the program and vertex array unbound.
  void draw(unsigned framebuffer, int width, int height, double exposure, double gamma) const;
  // The same with any tone map (analysis::ToneMap: clamp or reinhard; a reinhard map without an
  // average takes the uploaded image's, analysis::withImageAverage).
  void draw(unsigned framebuffer, int width, int height, const analysis::ToneMap& tm) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace translucent::gpu
