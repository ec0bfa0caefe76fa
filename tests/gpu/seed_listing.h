// SPDX-License-Identifier: GPL-3.0-or-later
// The seed's listing A.2 (bssrdf-explorer appendix A.2, "Diffusion dipole *.bssrdf"), verbatim
// as transcribed in the seed, and the same listing with the transcription's LaTeX artifacts
// (\text{}, \exp, \cdot) undone so that it is valid GLSL. Line numbers are those of the listing.
#pragma once

namespace translucent::testing {

inline constexpr const char* kSeedListingA2 = R"( analytic radial no_wi no_wo
:: begin parameters
float Multiplier 0.0 10.0 1.0
:: end parameters
::begin initializer
vec3 Lu;
vec3 AlphaPrime;
vec3 SigmaTr;
float A;
void init() {
  float Fdr = -1.44/(IOR*IOR) + 0.71/IOR + 0.668 + 0.0636*IOR;
 A = (1.0 + Fdr)/(1.0 - Fdr);
  vec3 SigmaSPrime = SigmaS *(1.0 - G);
  vec3 SigmaTPrime = SigmaSPrime + SigmaA;
  SigmaTr = sqrt (3.0 * SigmaA * SigmaTPrime);
  AlphaPrime = SigmaSPrime/SigmaTPrime;
 Lu = 1.0/SigmaTPrime;
}
::end initializer
:: begin diffuseReflectance
vec3 DiffuseReflectance(vec3 AlphaPrime) {
  vec3 T = sqrt (3.0*(1.0 - \text{AlphaPrime}));
  return AlphaPrime *0.5*(1.0 + \exp(-4.0/3.0*A*T))*\exp(-T);
}
:: end diffuseReflectance
:: begin shader
vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {
  vec3 R = vec3(dot(Xi - Xo, Xi - Xo));
  vec3 Zr = Lu;
  vec3 Zv = Lu * (1.0 + 4.0/3.0 * A);
  vec3 Dr = sqrt(R + Zr*Zr);
  vec3 Dv = sqrt(R + Zv*Zv);
  vec3 C1 = Zr * (SigmaTr + 1.0/Dr);
  vec3 C2 = Zv*(SigmaTr + 1.0/Dv);
  vec3 FluenceR = C1 \cdot exp(-SigmaTr \cdot Dr)/(Dr \cdot Dr);
  vec3 FluenceV = C2*exp(-SigmaTr*Dv)/(Dv*Dv);
  return Multiplier/(4.0*PI)*AlphaPrime*(FluenceR + FluenceV);
}
::end shader
)";

inline constexpr const char* kSeedListingA2Glsl = R"( analytic radial no_wi no_wo
:: begin parameters
float Multiplier 0.0 10.0 1.0
:: end parameters
::begin initializer
vec3 Lu;
vec3 AlphaPrime;
vec3 SigmaTr;
float A;
void init() {
  float Fdr = -1.44/(IOR*IOR) + 0.71/IOR + 0.668 + 0.0636*IOR;
 A = (1.0 + Fdr)/(1.0 - Fdr);
  vec3 SigmaSPrime = SigmaS *(1.0 - G);
  vec3 SigmaTPrime = SigmaSPrime + SigmaA;
  SigmaTr = sqrt (3.0 * SigmaA * SigmaTPrime);
  AlphaPrime = SigmaSPrime/SigmaTPrime;
 Lu = 1.0/SigmaTPrime;
}
::end initializer
:: begin diffuseReflectance
vec3 DiffuseReflectance(vec3 AlphaPrime) {
  vec3 T = sqrt (3.0*(1.0 - AlphaPrime));
  return AlphaPrime *0.5*(1.0 + exp(-4.0/3.0*A*T))*exp(-T);
}
:: end diffuseReflectance
:: begin shader
vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {
  vec3 R = vec3(dot(Xi - Xo, Xi - Xo));
  vec3 Zr = Lu;
  vec3 Zv = Lu * (1.0 + 4.0/3.0 * A);
  vec3 Dr = sqrt(R + Zr*Zr);
  vec3 Dv = sqrt(R + Zv*Zv);
  vec3 C1 = Zr * (SigmaTr + 1.0/Dr);
  vec3 C2 = Zv*(SigmaTr + 1.0/Dv);
  vec3 FluenceR = C1 * exp(-SigmaTr * Dr)/(Dr * Dr);
  vec3 FluenceV = C2*exp(-SigmaTr*Dv)/(Dv*Dv);
  return Multiplier/(4.0*PI)*AlphaPrime*(FluenceR + FluenceV);
}
::end shader
)";

}  // namespace translucent::testing
