// SPDX-License-Identifier: GPL-3.0-or-later
// Window depth -> distance in front of the eye, for any projection whose clip z and w are affine
// in eye z (perspective and orthographic; techniques/empirical/shading.h linearDepth). The seed's
// zNear/zFar formula (appendix C.2.4) assumes a perspective matrix.
#pragma once
float eyeDistance(float windowDepth, mat4 P) {
  const float ndc = 2.0 * windowDepth - 1.0;
  return -(P[3][2] - ndc * P[3][3]) / (ndc * P[2][3] - P[2][2]);
}
