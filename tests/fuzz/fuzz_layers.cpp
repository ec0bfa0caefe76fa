// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for the layers file of `translucent pathtrace slab --layers FILE` (the
// layered-slab reference, reference/layered_slab.h): parseSlabLayers, then the checks the CLI
// and the Python binding run before tracing (makeSlabRun), then a few photons of the run.
//
// The input is the file's text. A ParameterError is the expected outcome for a malformed file or
// one whose numbers lead nowhere; anything else (a crash, a sanitizer report, another exception,
// a hang) is a finding. A file that is accepted must give a run that ends: makeSlabRun is asked
// for the CLI's default 1e6 photons (so its estimate of the walks' length bites as it does for a
// user), and 8 of them are then traced on one thread, which must finish within the fuzzer's
// timeout and give finite tallies that add up to at most 1 per photon. Tracing is part of the
// target because an accepted file that makes the run hang is the failure a user would see.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "translucent/optics/medium.h"  // ParameterError
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/slab_request.h"

namespace {
bool unitInterval(const translucent::reference::Estimate& e) {
  return std::isfinite(e.value) && std::isfinite(e.std_error) && e.value >= -1e-12 &&
         e.value <= 1.0 + 1e-9 && e.std_error >= 0.0;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace translucent::reference;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const std::vector<SlabLayer> layers = parseSlabLayers(text, "fuzz.json");
    if (layers.empty()) std::abort();  // refused by the parser
    SlabRequest request;
    request.eta = 1.4;
    request.threads = 1;
    SlabRun run = makeSlabRun(request, layers, "fuzz.json");
    if (!run.layered || run.layered->layers.size() != layers.size()) std::abort();
    run.options.photons = 8;
    const SlabResult r = traceSlabRun(run);
    if (r.photons != 8) std::abort();
    if (!unitInterval(r.diffuse_reflectance) || !unitInterval(r.transmittance) ||
        !unitInterval(r.absorbed) || !unitInterval(r.specular_reflectance))
      std::abort();
    const double sum = r.specular_reflectance.value + r.diffuse_reflectance.value +
                       r.transmittance.value + r.absorbed.value;
    if (!(sum <= 1.0 + 1e-9)) std::abort();
  } catch (const translucent::ParameterError&) {
  }
  return 0;
}
