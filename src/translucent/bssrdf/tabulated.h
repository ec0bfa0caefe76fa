// SPDX-License-Identifier: GPL-3.0-or-later
// Tabulated (measured or path-traced) radial profiles as models (seed 3.1: "analytic and measured
// data"). A CSV file is a model wherever a model is named (bssrdf::model("skin1.csv")):
//
//   # units: mm                 (mm, cm, m or um: the unit of r; R is per unit² of the same unit)
//   # eta: 1.3                  (optional: the η the profile was measured or traced for)
//   r,R_r,R_g,R_b
//   0.005,1.234,2.345,3.456
//   ...
//
// or the CSV `translucent profile --out x.csv` writes (model,channel,r,value[,stderr]), whose
// "reference" rows (or the rows of its only model) give R per channel; there r is in mm unless a
// `# units:` line says otherwise (profile writes scene units, which are mm at the default scale 1).
//
// A table is one material: it ignores σa, σs and g. Its radii are in millimetres and are converted
// to scene units with the medium's scale (medium units are millimetres, as in the presets):
// r_scene = r_mm / scale, R_scene = R_mm · scale², so Rd is unchanged. Between samples R is
// interpolated linearly in (ln r, ln R) (linearly where a sample is 0), below the first sample it
// is held constant, and beyond the last it decays exponentially with the slope of ln R fitted over
// the last tenth of the samples (0 if that slope is not negative): Rd, sampling and the 95% radius
// come from the base class's quadrature of this function.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/bssrdf/profile.h"

namespace translucent::bssrdf {

// True when `name` names a tabulated profile (ends in .csv, any case).
bool isTabulatedFile(std::string_view name);

struct ProfileSamples {
  std::vector<double> r_mm;                 // strictly increasing radii >= 0 [mm]
  std::array<std::vector<double>, 3> R_mm;  // R per RGB channel [1/mm²], >= 0
  double eta = 0.0;                         // 0: not stated
  std::string source;                       // the file, for messages
};

// Reads and validates a table; throws ParameterError naming the file and line.
ProfileSamples readProfileSamples(const std::string& path);
// Writes `table` in the first format above (units mm) with `comment` lines (each prefixed "# ").
// Throws std::runtime_error naming the file when it cannot be written.
void writeProfileSamples(const std::string& path, const ProfileSamples& table,
                       const std::vector<std::string>& comment = {});

class TabulatedModel : public Model {
 public:
  explicit TabulatedModel(ProfileSamples table);
  std::string_view name() const override { return name_; }
  std::string_view description() const override { return description_; }
  // Needs a channel of a Medium (ScalarMedium::channel in 0..2); throws ParameterError otherwise.
  std::unique_ptr<RadialProfile> profile(const ScalarMedium& medium) const override;
  // A table has one Rd per channel, not a function of α': always throws ParameterError.
  double totalReflectance(double alpha_prime, double eta) const override;
  bool tabulated() const override { return true; }

  const ProfileSamples& table() const { return table_; }
  // R of channel c at r_mm [1/mm²], interpolated and extrapolated as described above.
  double Rmm(int c, double r_mm) const;

 private:
  ProfileSamples table_;
  std::string name_, description_;
  std::array<double, 3> tailSlope_{};  // d ln R / dr beyond the last sample [1/mm], <= 0
};

}  // namespace translucent::bssrdf
