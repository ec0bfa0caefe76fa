// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/surface_maps.h"

#include "translucent/material/parse_context.h"

#include <algorithm>
#include <cmath>

#include "translucent/io/image_io.h"
#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/optics/inversion.h"

namespace translucent::material {

LocalMedium TexelMedia::at(const glm::dvec2& uv) const {
  const double x = std::clamp(uv.x, 0.0, 1.0) * width - 0.5;
  const double y = std::clamp(uv.y, 0.0, 1.0) * height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double tx = x - fx, ty = y - fy;
  auto texel = [&](double i, double j) -> const LocalMedium& {
    const int xi = std::clamp(static_cast<int>(i), 0, width - 1);
    const int yi = std::clamp(static_cast<int>(j), 0, height - 1);
    return texels[static_cast<size_t>(yi) * static_cast<size_t>(width) + static_cast<size_t>(xi)];
  };
  const LocalMedium top = LocalMedium::mix(texel(fx, fy), texel(fx + 1, fy), tx);
  const LocalMedium bottom = LocalMedium::mix(texel(fx, fy + 1), texel(fx + 1, fy + 1), tx);
  return LocalMedium::mix(top, bottom, ty);
}

LocalMedium TexelMedia::mean() const {
  LocalMedium m;
  const double n = static_cast<double>(std::max<size_t>(texels.size(), 1));
  for (const LocalMedium& t : texels) {
    for (size_t c = 0; c < 3; ++c) {
      m.sigma_a[c] += t.sigma_a[c] / n;
      m.sigma_s[c] += t.sigma_s[c] / n;
    }
    m.g += t.g / n;
  }
  return m;
}

namespace {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

Image readImage(const JsonReader& r, const std::filesystem::path& file, const std::string& key) {
  try {
    analysis::RgbImage img = analysis::readRgb(file.string());
    return {img.width, img.height, std::move(img.rgb)};
  } catch (const std::exception& e) {
    r.fail(key, e.what());
  }
}

// A file or a value per texel (number or [r, g, b], each >= 0 here; ranges checked later).
MapSource parseSource(const ParseContext& c, const json& mat, const char* name,
                      const std::string& key) {
  const std::string k = key + "." + name;
  if (!mat.contains(name)) c.reader.fail(k, "required (an image file, a number or [r, g, b])");
  const json& j = mat.at(name);
  if (j.is_string()) return c.resolve(j.get<std::string>(), k);
  return c.reader.rgb(j, k);
}

json sourceJson(const MapSource& s, const PathWriter& written) {
  if (const auto* p = std::get_if<std::filesystem::path>(&s)) return written(*p);
  return rgbJson(std::get<Rgb>(s));
}

const char* fileOr(const MapSource& s) {
  return std::holds_alternative<std::filesystem::path>(s) ? "file" : "value";
}

double parseG(const JsonReader& r, const json& mat, const std::string& key) {
  const double g = r.number(mat, "g", key, 0.0);
  if (!(std::abs(g) < 1.0)) r.fail(key + ".g", fmt::format("is {}: expected |g| < 1", g));
  return g;
}

std::string texelWhere(const std::string& what, int x, int y, size_t c) {
  return fmt::format("{}: texel ({}, {}) {}", what, x, y, kChannelNames[c]);
}

}  // namespace

MapDesc parseMap(const ParseContext& c, const json& mat, const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"sigma_a", "sigma_s_prime", "g"}));
  MapDesc d;
  d.sigma_a = c.resolve(r.string(mat, "sigma_a", key), key + ".sigma_a");
  d.sigma_s_prime = c.resolve(r.string(mat, "sigma_s_prime", key), key + ".sigma_s_prime");
  d.g = parseG(r, mat, key);
  const Image a = readImage(r, d.sigma_a, key + ".sigma_a");
  const Image s = readImage(r, d.sigma_s_prime, key + ".sigma_s_prime");
  if (a.width != s.width || a.height != s.height)
    r.fail(key + ".sigma_s_prime", fmt::format("'{}' is {} x {} and '{}' {} x {}: expected images "
                                               "of one size", d.sigma_a.string(), a.width,
                                               a.height, d.sigma_s_prime.string(), s.width,
                                               s.height));
  auto data = std::make_shared<TexelMedia>();
  data->width = a.width;
  data->height = a.height;
  data->texels.resize(static_cast<size_t>(a.width) * static_cast<size_t>(a.height));
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const size_t t = static_cast<size_t>(y) * static_cast<size_t>(a.width) + static_cast<size_t>(x);
      LocalMedium& m = data->texels[t];
      m.g = d.g;
      for (size_t ch = 0; ch < 3; ++ch) {
        const double sa = static_cast<double>(a.rgb[3 * t + ch]), sp = static_cast<double>(s.rgb[3 * t + ch]);
        if (!std::isfinite(sa) || sa < 0.0)
          r.fail(key + ".sigma_a", fmt::format("'{}' {} is {}: expected a finite value >= 0",
                                               d.sigma_a.string(), texelWhere("", x, y, ch).substr(2), sa));
        if (!std::isfinite(sp) || sp < 0.0 || !(sa + sp > 0.0))
          r.fail(key + ".sigma_s_prime",
                 fmt::format("'{}' {} is {} (sigma_a {}): expected a finite value >= 0 with "
                             "sigma_a + sigma_s' > 0", d.sigma_s_prime.string(),
                             texelWhere("", x, y, ch).substr(2), sp, sa));
        m.sigma_a[ch] = sa;
        m.sigma_s[ch] = sp / (1.0 - d.g);
      }
    }
  d.data = data;
  return d;
}

AlbedoInverter::AlbedoInverter(const std::string& model, double eta) {
  const bssrdf::Model* m = nullptr;
  try {
    m = &bssrdf::model(model);
  } catch (const std::exception& e) {
    throw ParameterError(e.what());
  }
  constexpr int kN = 1025;
  rd_.resize(kN);
  for (int i = 0; i < kN; ++i) {
    const double s = static_cast<double>(i) / (kN - 1);
    rd_[static_cast<size_t>(i)] = m->totalReflectance(1.0 - s * s, eta);
  }
  for (size_t i = 1; i < rd_.size(); ++i)
    if (!(rd_[i] < rd_[i - 1]) && !(rd_[i] == 0.0 && rd_[i - 1] == 0.0))
      throw ParameterError(fmt::format("model '{}': Rd(α') is not increasing (η {}): cannot "
                                       "invert it", model, eta));
}

double AlbedoInverter::alphaPrime(double rd, const std::string& what) const {
  if (!(rd > 0.0 && rd < rd_.front()))
    throw ParameterError(fmt::format("{} is {}: expected Rd in (0, {:.6g}), the range the model "
                                     "reaches at this η", what, rd, rd_.front()));
  // rd_ decreases with i: the first entry at or below rd.
  const auto it = std::lower_bound(rd_.begin(), rd_.end(), rd, std::greater<double>());
  const size_t i = static_cast<size_t>(it - rd_.begin());  // rd_[i] <= rd < rd_[i-1], i >= 1
  const double n = static_cast<double>(rd_.size() - 1);
  double s;
  if (i >= rd_.size()) {
    s = 1.0;
  } else {
    const double r0 = rd_[i - 1], r1 = rd_[i];
    const double t = r0 > r1 ? (r0 - rd) / (r0 - r1) : 0.0;
    s = (static_cast<double>(i - 1) + t) / n;
  }
  return std::clamp(1.0 - s * s, 0.0, 1.0);
}

TexelMedia invertRdMap(const AlbedoInverter& inv, int width, int height,
                       const std::vector<float>& rd, const std::vector<float>& ld, double g,
                       const std::string& rd_what, const std::string& ld_what) {
  TexelMedia out;
  out.width = width;
  out.height = height;
  out.texels.resize(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t t = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      LocalMedium& m = out.texels[t];
      m.g = g;
      for (size_t c = 0; c < 3; ++c) {
        const double l = static_cast<double>(ld[3 * t + c]);
        if (!std::isfinite(l) || !(l > 0.0))
          throw ParameterError(fmt::format("{} is {}: expected ℓd > 0 [medium units]",
                                           texelWhere(ld_what, x, y, c), l));
        const double a = inv.alphaPrime(static_cast<double>(rd[3 * t + c]), texelWhere(rd_what, x, y, c));
        const ReducedCoefficients k = coefficientsFromAlbedo(a, l);
        m.sigma_a[c] = k.sigma_a;
        m.sigma_s[c] = k.sigma_s_prime / (1.0 - g);
      }
    }
  return out;
}

RdMapDesc parseRdMap(const ParseContext& c, const json& mat, const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"rd", "ld", "g"}));
  RdMapDesc d;
  d.rd = parseSource(c, mat, "rd", key);
  d.ld = parseSource(c, mat, "ld", key);
  d.g = parseG(r, mat, key);
  if (bssrdf::hasBssrdfExtension(c.model))
    r.fail(key + ".model", fmt::format("'{}': rd_map inverts Rd with a registered model; a "
                                       ".bssrdf file's inversion needs the GPU (translucent "
                                       "invert): expected one of {}", c.model,
                                       fmt::join(bssrdf::modelNames(), ", ")));
  // Both sources as images of one size (a value: every texel).
  Image rd, ld;
  const auto* rdFile = std::get_if<std::filesystem::path>(&d.rd);
  const auto* ldFile = std::get_if<std::filesystem::path>(&d.ld);
  if (rdFile) rd = readImage(r, *rdFile, key + ".rd");
  if (ldFile) ld = readImage(r, *ldFile, key + ".ld");
  if (rdFile && ldFile && (rd.width != ld.width || rd.height != ld.height))
    r.fail(key + ".ld", fmt::format("'{}' is {} x {} and '{}' {} x {}: expected images of one "
                                    "size", rdFile->string(), rd.width, rd.height,
                                    ldFile->string(), ld.width, ld.height));
  const int w = rdFile ? rd.width : (ldFile ? ld.width : 1);
  const int h = rdFile ? rd.height : (ldFile ? ld.height : 1);
  auto fill = [&](Image& img, const MapSource& s) {
    if (std::holds_alternative<Rgb>(s)) {
      const Rgb v = std::get<Rgb>(s);
      img.width = w;
      img.height = h;
      img.rgb.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 3);
      for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = static_cast<float>(v[i % 3]);
    }
  };
  fill(rd, d.rd);
  fill(ld, d.ld);
  auto what = [&](const MapSource& s, const char* name) {
    const auto* p = std::get_if<std::filesystem::path>(&s);
    return p ? fmt::format("{}: {}.{} '{}'", r.what, key, name, p->string())
             : fmt::format("{}: {}.{} ({})", r.what, key, name, fileOr(s));
  };
  try {
    const AlbedoInverter inv(c.model, c.eta);
    d.data = std::make_shared<const TexelMedia>(
        invertRdMap(inv, w, h, rd.rgb, ld.rgb, d.g, what(d.rd, "rd"), what(d.ld, "ld")));
  } catch (const ParameterError& e) {
    if (std::string(e.what()).starts_with(r.what)) throw;
    r.fail(key + ".model", e.what());
  }
  return d;
}

SurfaceCheckerDesc parseSurfaceChecker(const ParseContext& c, const json& mat,
                                       const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"cells", "media"}));
  SurfaceCheckerDesc d;
  const std::string k = key + ".cells";
  if (!mat.contains("cells")) r.fail(k, "required (a number or [nu, nv], squares across the atlas)");
  const json& j = mat["cells"];
  if (j.is_number()) {
    d.cells = glm::dvec2(r.number(j, k));
  } else {
    if (!j.is_array() || j.size() != 2)
      r.fail(k, fmt::format("{}: expected a number or [nu, nv]", JsonReader::describe(j)));
    d.cells = {r.number(j[0], k + "[0]"), r.number(j[1], k + "[1]")};
  }
  if (!(d.cells.x > 0.0 && d.cells.y > 0.0))
    r.fail(k, fmt::format("is [{}, {}]: expected each > 0", d.cells.x, d.cells.y));
  d.media = parseMediaArray(r, mat, "media", key, 2);
  return d;
}

void writeMap(const MapDesc& d, json& mat, const PathWriter& written) {
  mat["sigma_a"] = written(d.sigma_a);
  mat["sigma_s_prime"] = written(d.sigma_s_prime);
  mat["g"] = d.g;
}

void writeRdMap(const RdMapDesc& d, json& mat, const PathWriter& written) {
  mat["rd"] = sourceJson(d.rd, written);
  mat["ld"] = sourceJson(d.ld, written);
  mat["g"] = d.g;
}

void writeSurfaceChecker(const SurfaceCheckerDesc& d, json& mat) {
  mat["cells"] = json::array({d.cells.x, d.cells.y});
  mat["media"] = json::array({toJson(d.media[0]), toJson(d.media[1])});
}

SurfaceCheckerMap::SurfaceCheckerMap(const SurfaceCheckerDesc& d)
    : cells_(d.cells), media_{d.media.at(0).medium, d.media.at(1).medium} {}

LocalMedium SurfaceCheckerMap::at(const glm::dvec2& uv) const {
  const double s = std::floor(uv.x * cells_.x) + std::floor(uv.y * cells_.y);
  return media_[std::fmod(std::abs(s), 2.0) == 1.0 ? 1 : 0];
}

}  // namespace translucent::material
