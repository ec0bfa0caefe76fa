// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/reference/camera.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/optics/fresnel.h"

namespace translucent::reference {

namespace {
bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
}  // namespace

void Camera::validate() const {
  if (!finite3(position) || !finite3(look_at) || !finite3(up))
    throw ParameterError("camera: position, look_at and up must be finite");
  const glm::dvec3 f = look_at - position;
  if (!(glm::length(f) > 0.0))
    throw ParameterError("camera: look_at equals position: expected a point to look at");
  if (!(glm::length(glm::cross(f, up)) > 1e-12 * glm::length(f) * glm::length(up)))
    throw ParameterError("camera: up is zero or parallel to the viewing direction");
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw ParameterError(fmt::format(
        "camera: resolution is {}x{}: expected width and height in [1, 16384]", width, height));
  // A field of view of 1e-320 degrees rendered black and one of 179.99999 NaN metrics: the
  // bounds are far outside any camera a picture is made with.
  if (projection == Projection::Pinhole && !(fov >= 1e-3 && fov <= 179.0))
    throw ParameterError(fmt::format("camera: fov is {}: expected degrees in [0.001, 179]", fov));
  if (projection == Projection::Orthographic && !(std::isfinite(view_height) && view_height > 0.0))
    throw ParameterError(
        fmt::format("camera: view_height is {}: expected a finite value > 0", view_height));
}

CameraModel::CameraModel(const Camera& camera) : camera_(camera) {
  camera_.validate();
  forward_ = glm::normalize(camera_.look_at - camera_.position);
  right_ = glm::normalize(glm::cross(forward_, camera_.up));
  up_ = glm::cross(right_, forward_);
  pixel_ = camera_.projection == Camera::Projection::Pinhole
               ? 2.0 * std::tan(0.5 * camera_.fov * std::numbers::pi / 180.0) / camera_.height
               : camera_.view_height / camera_.height;
}

bool CameraModel::project(const glm::dvec3& p, double& px, double& py) const {
  const glm::dvec3 q = p - camera_.position;
  const double z = glm::dot(q, forward_);
  double x = glm::dot(q, right_), y = glm::dot(q, up_);
  if (camera_.projection == Camera::Projection::Pinhole) {
    if (!(z > 0.0)) return false;
    x /= z;
    y /= z;
  }
  px = x / pixel_ + 0.5 * camera_.width;
  py = 0.5 * camera_.height - y / pixel_;
  return px >= 0.0 && py >= 0.0 && px < camera_.width && py < camera_.height;
}

void CameraModel::toCamera(const glm::dvec3& p, glm::dvec3& dir, double& dist) const {
  if (camera_.projection == Camera::Projection::Pinhole) {
    dir = camera_.position - p;
    dist = glm::length(dir);
    dir /= dist;
  } else {
    dir = -forward_;
    dist = glm::dot(p - camera_.position, forward_);
  }
}

void CameraModel::ray(double px, double py, glm::dvec3& origin, glm::dvec3& dir) const {
  const double x = (px - 0.5 * camera_.width) * pixel_, y = (0.5 * camera_.height - py) * pixel_;
  if (camera_.projection == Camera::Projection::Pinhole) {
    origin = camera_.position;
    dir = glm::normalize(forward_ + x * right_ + y * up_);
  } else {
    origin = camera_.position + x * right_ + y * up_;
    dir = forward_;
  }
}

double CameraModel::pixelMeasure(int i, int j) const {
  if (camera_.projection == Camera::Projection::Orthographic) return pixel_ * pixel_;
  // Solid angle of the rectangle [x0, x1] x [y0, y1] on the plane at distance 1:
  // Ω = F(x1,y1) - F(x0,y1) - F(x1,y0) + F(x0,y0), F(x, y) = atan(x y / sqrt(1 + x² + y²)).
  auto F = [](double x, double y) { return std::atan(x * y / std::sqrt(1.0 + x * x + y * y)); };
  const double x0 = (i - 0.5 * camera_.width) * pixel_, x1 = x0 + pixel_;
  const double y1 = (0.5 * camera_.height - j) * pixel_, y0 = y1 - pixel_;
  return F(x1, y1) - F(x0, y1) - F(x1, y0) + F(x0, y0);
}

// ---------------------------------------------------------------------------------------------

class ImageTally::Deposits final : public ExitTally::Block {
 public:
  // One photon's scores into one (pixel, channel), by scattering order (slab.h).
  struct Deposit {
    size_t index;  // McImage index (pixel, channel)
    std::array<double, kScatteringOrders> exitance{}, radiance{}, cone{};
    double total(const std::array<double, kScatteringOrders>& v) const { return v[0] + v[1] + v[2]; }
  };
  explicit Deposits(const ImageTally& t) : t_(t) {}

  void record(const ExitRecord& e) override {
    const CameraModel& cam = t_.camera_;
    glm::dvec3 v;
    double dist;
    cam.toCamera(e.position, v, dist);
    const double cosO = glm::dot(e.normal, v);
    if (!(cosO > 0.0) || !(dist > 0.0)) return;
    double px, py;
    if (!cam.project(e.position, px, py)) return;
    if (t_.body_.occluded(e.position, v, t_.body_.epsilon(), dist)) return;
    const int i = static_cast<int>(px), j = static_cast<int>(py);
    const size_t pix = static_cast<size_t>(j) * static_cast<size_t>(cam.camera().width) +
                       static_cast<size_t>(i);
    const double measure = t_.measure_[pix];
    const bool pinhole = cam.camera().projection == Camera::Projection::Pinhole;
    const double score = e.weight * cosO / (pinhole ? dist * dist * measure : measure);
    const double eta = t_.etas_[static_cast<size_t>(e.channel)];
    const double ft = eta == 1.0 ? 1.0 : fresnelTransmittance(cosO, eta);
    Deposit d;
    d.index = t_.images_.exitance.index(i, j, e.channel);
    const size_t k = static_cast<size_t>(e.order);
    d.exitance[k] = score;
    d.radiance[k] = score * ft / std::numbers::pi;
    d.cone[k] = glm::dot(e.direction, v) >= t_.cosCone_ ? score / (cosO * t_.coneMeasure_) : 0.0;
    photon_.push_back(d);
  }

  // A photon's scores into one (pixel, channel) are summed into one sample before the image
  // squares it (the per-photon second moment, transport.h); so are its scores of each order for
  // the orders' images. A photon rarely scores more than twice, so the quadratic search is
  // cheaper than sorting.
  void endPhoton() override {
    const size_t first = deposits.size();
    for (const Deposit& d : photon_) {
      auto same = std::find_if(deposits.begin() + static_cast<std::ptrdiff_t>(first),
                               deposits.end(), [&](const Deposit& o) { return o.index == d.index; });
      if (same == deposits.end()) {
        deposits.push_back(d);
      } else {
        for (size_t k = 0; k < kScatteringOrders; ++k) {
          same->exitance[k] += d.exitance[k];
          same->radiance[k] += d.radiance[k];
          same->cone[k] += d.cone[k];
        }
      }
    }
    if (deposits.size() - first > 1) ++severalPixels;
    photon_.clear();
  }

  std::vector<Deposit> deposits;  // per photon, per (pixel, channel): the summed scores
  uint64_t severalPixels = 0;     // photons that scored into more than one (pixel, channel)

 private:
  const ImageTally& t_;
  std::vector<Deposit> photon_;  // the current photon's scores
};

ImageTally::ImageTally(const Body& body, const Camera& camera, std::vector<double> etas,
                       double cone_half_angle_degrees, double photon_flux, bool split_orders)
    : body_(body), camera_(camera), etas_(std::move(etas)) {
  if (etas_.empty()) throw ParameterError("image tally: no channels");
  if (!(cone_half_angle_degrees > 0.0 && cone_half_angle_degrees <= 90.0))
    throw ParameterError(fmt::format(
        "cone half-angle is {} degrees: expected a value in (0, 90]", cone_half_angle_degrees));
  coneHalfAngle_ = cone_half_angle_degrees * std::numbers::pi / 180.0;
  cosCone_ = std::cos(coneHalfAngle_);
  coneMeasure_ = std::numbers::pi * std::sin(coneHalfAngle_) * std::sin(coneHalfAngle_);
  const int w = camera_.camera().width, h = camera_.camera().height;
  const int nc = static_cast<int>(etas_.size());
  measure_.resize(static_cast<size_t>(w) * static_cast<size_t>(h));
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      measure_[static_cast<size_t>(j) * static_cast<size_t>(w) + static_cast<size_t>(i)] =
          camera_.pixelMeasure(i, j);
  // A typical score: a photon's flux over the measure of the centre pixel (and the squared
  // distance to the body, for a pinhole camera): the grid of the images' exact sums.
  const double centre = measure_[static_cast<size_t>(h / 2) * static_cast<size_t>(w) +
                                 static_cast<size_t>(w / 2)];
  glm::dvec3 toCam;
  double dist = 1.0;
  camera_.toCamera(body_.bounds().center, toCam, dist);
  const bool pinhole = camera_.camera().projection == Camera::Projection::Pinhole;
  const double typical = photon_flux / (centre * (pinhole && dist > 0.0 ? dist * dist : 1.0));
  images_.exitance = McImage(w, h, nc, McImage::Statistics::PerPhoton, FixedScale::around(typical));
  images_.radiance = images_.exitance;
  images_.cone_radiance = images_.exitance;
  // The orders' images on the same grid as the totals', so that (exact sums) they add up to them.
  if (split_orders) orders_.emplace(std::array<CameraImages, kScatteringOrders>{images_, images_, images_});
}

std::unique_ptr<ExitTally::Block> ImageTally::newBlock() const {
  return std::make_unique<Deposits>(*this);
}

void ImageTally::merge(Block& block) {
  auto& deposits = static_cast<Deposits&>(block);
  severalPixelPhotons_ += deposits.severalPixels;
  for (const auto& d : deposits.deposits) {
    images_.exitance.add(d.index, d.total(d.exitance));
    images_.radiance.add(d.index, d.total(d.radiance));
    const double cone = d.total(d.cone);
    if (cone != 0.0) images_.cone_radiance.add(d.index, cone);
    if (!orders_) continue;
    for (size_t k = 0; k < kScatteringOrders; ++k) {
      CameraImages& o = (*orders_)[k];
      if (d.exitance[k] != 0.0) o.exitance.add(d.index, d.exitance[k]);
      if (d.radiance[k] != 0.0) o.radiance.add(d.index, d.radiance[k]);
      if (d.cone[k] != 0.0) o.cone_radiance.add(d.index, d.cone[k]);
    }
  }
}

const CameraImages& ImageTally::orderImages(ScatteringOrder order) const {
  if (!orders_)
    throw std::logic_error("ImageTally::orderImages: the tally does not split scattering orders");
  return (*orders_)[static_cast<size_t>(order)];
}

namespace {
// Calls f(image, name) for the three images of `images`, named `<prefix>.exitance` etc.
template <class Images, class F>
void forEachImage(Images& images, const std::string& prefix, F&& f) {
  f(images.exitance, prefix + ".exitance");
  f(images.radiance, prefix + ".radiance");
  f(images.cone_radiance, prefix + ".cone_radiance");
}
}  // namespace

void ImageTally::write(RunState& state, const std::string& prefix) const {
  forEachImage(images_, prefix, [&](const McImage& im, const std::string& n) { im.write(state, n); });
  if (orders_)
    for (ScatteringOrder o : kAllScatteringOrders)
      forEachImage((*orders_)[static_cast<size_t>(o)], prefix + ".order." + toString(o),
                   [&](const McImage& im, const std::string& n) { im.write(state, n); });
  state.putCounts(prefix + ".several_pixel_photons", {severalPixelPhotons_});
}

void ImageTally::read(const RunState& state, const std::string& prefix) {
  forEachImage(images_, prefix, [&](McImage& im, const std::string& n) { im.read(state, n); });
  if (orders_)
    for (ScatteringOrder o : kAllScatteringOrders)
      forEachImage((*orders_)[static_cast<size_t>(o)], prefix + ".order." + toString(o),
                   [&](McImage& im, const std::string& n) { im.read(state, n); });
  severalPixelPhotons_ = state.getCounts(prefix + ".several_pixel_photons", 1)[0];
}

void ImageTally::addPhotons(std::span<const uint64_t> photons) {
  auto add = [&](CameraImages& images) {
    forEachImage(images, "", [&](McImage& im, const std::string&) {
      for (size_t c = 0; c < photons.size(); ++c) im.addCount(static_cast<int>(c), photons[c]);
    });
  };
  add(images_);
  if (orders_)
    for (CameraImages& o : *orders_) add(o);
}

}  // namespace translucent::reference
