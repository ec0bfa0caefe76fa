// SPDX-License-Identifier: GPL-3.0-or-later
// An image scaled to the widget, keeping its aspect ratio, nearest-neighbour (the pixels of a
// Monte Carlo image are worth seeing), centred on a dark background; "computing…" before the
// first. Header-only and widgets only: for the docks (the lit spheres, Compare), not for core's
// own target, which has no Qt Widgets.
#pragma once

#include <QtGui/QImage>
#include <QtGui/QPainter>
#include <QtWidgets/QWidget>

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>

#include "translucent/io/image_io.h"  // toneMap

namespace translucent::explorer {

class PixelImageView : public QWidget {
 public:
  explicit PixelImageView(QWidget* parent = nullptr) : QWidget(parent) {
    setMinimumSize(96, 96);
    setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Expanding);
  }
  void setImage(QImage image) {
    image_ = std::move(image);
    update();
  }
  QSize sizeHint() const override { return {256, 256}; }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.fillRect(rect(), QColor(24, 24, 24));
    if (image_.isNull()) {
      p.setPen(QColor(160, 160, 160));
      p.drawText(rect(), Qt::AlignCenter, tr("computing…"));
      return;
    }
    const QSize s = image_.size().scaled(size(), Qt::KeepAspectRatio);
    const QRect target(QPoint((width() - s.width()) / 2, (height() - s.height()) / 2), s);
    p.drawImage(target, image_);
  }

 private:
  QImage image_;
};

// Linear RGB (rows from the top) as displayed: analysis::toneMap with this exposure [stops] and
// gamma, the same mapping as the viewport and the CLI's PNGs.
inline QImage toneMappedImage(std::span<const float> rgb, int w, int h, double exposure,
                              double gamma) {
  QImage img(w, h, QImage::Format_RGB888);
  const analysis::ToneMap tm{exposure, gamma};
  const size_t row = 3 * static_cast<size_t>(w);
  for (int y = 0; y < h; ++y) {
    uchar* line = img.scanLine(y);
    for (size_t x = 0; x < row; ++x) line[x] = analysis::toneMap(rgb[static_cast<size_t>(y) * row + x], tm);
  }
  return img;
}

// 8-bit RGB (interleaved, rows from the top; analysis::falseColor's output) as an image.
inline QImage rgb8Image(std::span<const uint8_t> rgb, int w, int h) {
  QImage img(w, h, QImage::Format_RGB888);
  const size_t row = 3 * static_cast<size_t>(w);
  for (int y = 0; y < h; ++y)
    std::copy_n(rgb.data() + static_cast<size_t>(y) * row, row, img.scanLine(y));
  return img;
}

}  // namespace translucent::explorer
