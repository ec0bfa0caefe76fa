// SPDX-License-Identifier: GPL-3.0-or-later
// Prints the classical dipole's total diffuse reflectance Rd (Jensen et al. 2001) for the Marble
// preset, per colour channel, through the installed headers and Translucent::bssrdf.
#include <cstdio>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/presets.h"

int main() {
  const translucent::Medium marble = translucent::preset("Marble").medium();
  const auto rgb = translucent::bssrdf::profiles(translucent::bssrdf::model("dipole"), marble);
  std::printf("dipole Rd Marble: %.6f %.6f %.6f\n", rgb[0]->Rd(), rgb[1]->Rd(), rgb[2]->Rd());
  return 0;
}
