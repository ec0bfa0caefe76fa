#include "reference/mc_compare.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "optics/medium.h"  // ParameterError

namespace translucent::reference {

namespace {
double relativeTo(double v, double mean) {
  return mean > 0.0 ? v / mean : std::numeric_limits<double>::quiet_NaN();
}
}  // namespace

double ImageComparison::relativeRmse() const { return relativeTo(rmse, mean_reference); }
double ImageComparison::relativeNoise() const { return relativeTo(noise_rmse, mean_reference); }
double ImageComparison::relativeSystematic() const {
  return relativeTo(systematic_rmse, mean_reference);
}

ImageComparison compareImages(const McImage& ref, const McImage& test) {
  if (ref.width() != test.width() || ref.height() != test.height() ||
      ref.channels() != test.channels())
    throw ParameterError(fmt::format(
        "image comparison: the reference is {}x{} with {} channel(s), the test image {}x{} with {}: "
        "expected the same size and channels",
        ref.width(), ref.height(), ref.channels(), test.width(), test.height(), test.channels()));
  ImageComparison c;
  c.width = ref.width();
  c.height = ref.height();
  c.relative.assign(static_cast<size_t>(c.width) * static_cast<size_t>(c.height),
                    std::numeric_limits<float>::quiet_NaN());
  const int nc = ref.channels();
  double sumR = 0.0, sumT = 0.0, sumD2 = 0.0, sumVar = 0.0;
  for (int y = 0; y < c.height; ++y) {
    for (int x = 0; x < c.width; ++x) {
      double r = 0.0, t = 0.0, d2 = 0.0, var = 0.0;
      bool any = false;
      for (int ch = 0; ch < nc; ++ch) {
        const Estimate er = ref.pixel(x, y, ch), et = test.pixel(x, y, ch);
        any = any || er.value != 0.0 || et.value != 0.0;
        r += er.value;
        t += et.value;
        d2 += (et.value - er.value) * (et.value - er.value);
        var += er.std_error * er.std_error + et.std_error * et.std_error;
      }
      if (!any) continue;
      ++c.pixels;
      sumR += r;
      sumT += t;
      sumD2 += d2;
      sumVar += var;
      if (r > 0.0)
        c.relative[static_cast<size_t>(y) * static_cast<size_t>(c.width) + static_cast<size_t>(x)] =
            static_cast<float>((t - r) / r);
    }
  }
  if (c.pixels == 0) return c;
  const double n = static_cast<double>(c.pixels) * nc;
  c.mean_reference = sumR / n;
  c.mean_test = sumT / n;
  c.rmse = std::sqrt(sumD2 / n);
  c.noise_rmse = std::sqrt(sumVar / n);
  c.systematic_rmse = std::sqrt(std::max(0.0, c.rmse * c.rmse - c.noise_rmse * c.noise_rmse));
  return c;
}

std::array<unsigned char, 3> differenceColor(float relative, float range) {
  if (!std::isfinite(relative) || !(range > 0.0f)) return {128, 128, 128};
  const float a = std::clamp(std::abs(relative) / range, 0.0f, 1.0f);
  // White fading to a saturated red (positive) or blue (negative): the other two channels drop.
  const auto fade = static_cast<unsigned char>(std::lround(255.0f * (1.0f - a)));
  const auto mid = static_cast<unsigned char>(std::lround(255.0f * (1.0f - 0.75f * a)));
  if (relative >= 0.0f) return {255, fade, fade};
  return {fade, mid, 255};
}

}  // namespace translucent::reference
