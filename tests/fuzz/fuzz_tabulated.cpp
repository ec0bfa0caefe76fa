// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for tabulated radial profiles (bssrdf/tabulated.h): a CSV file that is a model
// wherever a model is named (`--model skin1.csv`, bssrdf::model("skin1.csv")), read by
// readProfileSamples and then used through TabulatedModel as a renderer uses it.
//
// The input is the file's text, written to a temporary .csv file (the reader reads by name). A
// ParameterError is the expected outcome for a malformed table; anything else (a crash, a
// sanitizer report, another exception, a hang) is a finding. A table that is accepted must be
// what its header promises (increasing radii >= 0, values >= 0, as many values as radii per
// channel) and usable: for each channel at two scales, Rd, the 95% radius, a sample and its
// density are finite, Rd > 0 (the reader refuses all-zero channels) and R(r) >= 0 (a NaN or a
// negative R would make non-finite or negative pixels, silently).
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "translucent/bssrdf/tabulated.h"
#include "translucent/optics/medium.h"  // ParameterError

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace translucent;
  using namespace translucent::bssrdf;
  static const std::string file =
      (std::filesystem::temp_directory_path() /
       ("translucent_fuzz_tabulated_" + std::to_string(::getpid()) + ".csv"))
          .string();
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    ProfileSamples table = readProfileSamples(file);
    const size_t n = table.r_mm.size();
    if (n < 2) std::abort();
    for (size_t i = 0; i < n; ++i) {
      if (!(std::isfinite(table.r_mm[i]) && table.r_mm[i] >= 0.0)) std::abort();
      if (i > 0 && !(table.r_mm[i] > table.r_mm[i - 1])) std::abort();
    }
    for (const auto& ch : table.R_mm) {
      if (ch.size() != n) std::abort();
      for (double v : ch)
        if (!(std::isfinite(v) && v >= 0.0)) std::abort();
    }
    if (!(table.eta >= 0.0 && std::isfinite(table.eta))) std::abort();
    const TabulatedModel model(std::move(table));
    for (int c = 0; c < 3; ++c) {
      for (double scale : {1.0, 37.0}) {
        ScalarMedium m;
        m.channel = c;
        m.scale = scale;
        const auto p = model.profile(m);
        const double rd = p->Rd();
        if (!(std::isfinite(rd) && rd > 0.0)) std::abort();
        const double r95 = p->radiusForFraction(0.95);
        if (!(std::isfinite(r95) && r95 >= 0.0)) std::abort();
        for (double u : {0.0, 0.5, 0.999}) {
          const RadialSample s = p->sample(u);
          if (!(std::isfinite(s.r) && s.r >= 0.0 && std::isfinite(s.pdf) && s.pdf >= 0.0))
            std::abort();
        }
        for (double r : {0.0, r95, 2.0 * r95 + 1.0}) {
          const double R = p->R(r);
          if (!(std::isfinite(R) && R >= 0.0)) std::abort();
          if (!std::isfinite(p->pdf(r))) std::abort();
        }
      }
    }
  } catch (const ParameterError&) {
  }
  std::error_code ec;
  std::filesystem::remove(file, ec);
  return 0;
}
