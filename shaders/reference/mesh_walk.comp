#version 450
// SPDX-License-Identifier: GPL-3.0-or-later
// The walk of src/reference/transport_impl.h (launch, tracePhoton, crossBoundary, reenter) in a
// closed triangle mesh on the GPU, one photon of one channel per invocation: emission from one
// of the lights (chosen with probability ∝ its flux in the channel: directional, point, beam
// or environment), entry at the first hit with the Fresnel transmittance as a weight and Snell
// refraction, exponential flights, at the boundary Fresnel reflection or an exit (scored), the
// flight in air after an exit and the re-entry into a non-convex body (Fresnel reflection off
// the outside traced, as on the CPU), analog absorption, Henyey-Greenstein scattering and the
// seed's long-path roulette. Ray queries: bvh.glsl (Embree-built BVH, watertight triangles).
//
// Random numbers: photon p of channel c reads the words of philox((p_lo, p_hi, m, c), Seed) for
// m = 0, 1, 2, ... in order, four per call: one sequential stream per photon that no other
// photon or channel touches, so the run does not depend on scheduling. An environment light's
// direction is drawn on the CPU (mesh_gpu.cpp: the map's own sampler, exact texel by texel, from
// philox((p_lo, p_hi, 0, 8 + c), Seed)) and read from EnvDirs.
//
// Outputs: one record per photon (entered, exited and escaped weight, scatterings, exits) and one
// per exit, appended through an atomic counter with the photon's index and the exit's rank in
// it; the CPU sorts them back into photon order and scores them as its own exits
// (mesh_tracer.cpp). When more exits come than the buffer holds, only the count grows: the CPU
// enlarges the buffer and traces the batch again (the same photons: the streams are counters).
//
// Positions in double (the CPU's), queries, flights and directions in float (Embree's and the
// lane walker's precision).
//
// Suspension: Mesa's llvmpipe ends every loop of an invocation (of each SIMD group of them)
// once their iterations add up to 65535, silently: a long walk would stop half-way, its light
// lost (the bunny or a large, little-absorbing cube lost 3% of their exitance so). So a walk
// counts its loop iterations (gWork) and, at the start of a free flight past WorkBudget, writes
// its state (position, direction, weight, stream position, tallies) to States and returns; the
// next dispatch (Phase 1) resumes it there, over the list of suspended walks only. The random
// words are the same whichever dispatch draws them, so a suspended walk is the walk that was not.
// The host sizes the budget from the driver and checks the largest count a dispatch saw
// (control[1]; walk_program.h: LoopLimit).
//
// Heterogeneous media (compiled with VOLUME defined: a second program, so that the homogeneous
// walk does not carry the tracking's code, 20% of its speed on llvmpipe): traceVolumePhoton of transport_impl.h. The free flight is delta
// tracking through the CPU's majorant grid (majorant_grid.h: a 3D DDA over the cells' bounds,
// rounded up to float on upload), the field evaluated at tentative collisions by fields.glsl in
// material space (q = scale Rᵀ (x − translate), x undeformed first when the body is deformed:
// common/deform.glsl, in float, Newton's method for a bend); the boundary
// is one ray query bounded by the collision found; a real collision absorbs with the local
// σa/σt and scatters with the local g; after a reflection or re-entry the tracking starts afresh
// (memoryless). Tentative collisions where the field exceeds the bound in force are counted.
layout(local_size_x = 64) in;
// An upper bound of the loop iterations the driver has counted for this invocation in this
// dispatch (every loop whose trip count is not a constant calls WALK_WORK() per iteration,
// bvh.glsl and fields.glsl included, and once before a loop that may run no iteration): llvmpipe
// charges a loop of k >= 1 iterations k or k + 1 (its exit), one that runs none 1
// (tests/reference/test_loop_limit.cpp), so 2 per call bounds it. The walk suspends at the start
// of a free flight once it exceeds WorkBudget (see "Suspension" below).
uint gWork = 0u;
#define WALK_WORK() gWork += 2u
#include "common/compute.glsl"
#include "reference/philox.glsl"
#include "reference/walk_math.glsl"
#include "reference/bvh.glsl"

struct PhotonOut {
  double entered, exited, escaped;
  uint scatters, exits;
};
struct ExitOut {
  double px, py, pz, weight;
  float nx, ny, nz, dx, dy, dz;
  uint photon, rank;
};
struct GpuLight {
  vec3 p;       // directional: the disc's centre; point: the position; beam: the origin;
                // environment: the bounding sphere's centre
  uint type;    // 0 directional, 1 point, 2 beam, 3 environment
  vec3 dir;     // directional: of flight (-towards the light); point: the cone's axis; beam: of flight
  float radius; // disc (directional, beam)
  vec3 t1;
  float cosMax; // point: the cone that holds the bounding sphere (-1: all directions)
  vec3 t2;
  float cdf;    // cumulative share of the channel's flux, this light included (last: 1)
};
layout(std430, binding = 0) writeonly buffer Photons { PhotonOut photons[]; };
layout(std430, binding = 3) writeonly buffer Exits { ExitOut exits[]; };
layout(std430, binding = 4) buffer ExitCounter { uint exitCount; };
layout(std430, binding = 5) readonly buffer Lights { GpuLight lights[]; };
// Per photon of the batch, towards the environment (xyz; w unused): environment lights only.
layout(std430, binding = 6) readonly buffer EnvDirs { vec4 envDirs[]; };
// A suspended walk's state, per photon of the batch (mesh_gpu.cpp: WalkState).
struct WalkState {
  double x, y, z, w;
  double entered, exited, escaped, pad;
  float dx, dy, dz;
  uint flags;  // kAlive: suspended, to be resumed; kOnSurface: the next ray starts on the boundary
  uint counter, used, scatters, exits;
};
// kSpecular: the photon met the boundary (reflected or re-entered) before its first scattering.
const uint kAlive = 1u, kOnSurface = 2u, kSpecular = 4u;
layout(std430, binding = 10) buffer States { WalkState states[]; };
// [0]: walks suspended by this dispatch; [1]: the largest gWork of an invocation.
layout(std430, binding = 11) buffer Control { uint control[]; };
// The photons (indices in the batch) this dispatch resumes (Phase 1: Count of them), and those
// it suspends, in the order they did (the next dispatch's list).
layout(std430, binding = 12) readonly buffer ResumeList { uint resumeList[]; };
layout(std430, binding = 13) writeonly buffer SuspendList { uint suspendList[]; };

uniform uvec2 Seed;
uniform uvec2 FirstPhoton;
uniform uint Count, Channel, LightCount, ExitCapacity;
uniform double Flux;    // what a photon of the channel carries
uniform bool Matched;   // η = 1
uniform float Eta;      // n_inside / n_outside
uniform float InvSigmaT, G, Epsilon;
uniform uvec2 AbsorbThreshold;  // (high, low): absorbed when a 64-bit word < threshold
uniform uint LongPath;
uniform uint Phase;       // 0: emit and walk Count photons; 1: resume the Count of ResumeList
// TransportOptions::after_specular_only (the camera method's complement): a photon that scatters
// or leaves before it meets the boundary again is scored nowhere (transport_impl.h: crossCounted).
uniform bool AfterSpecularOnly;
uniform uint WorkBudget;  // loop iterations after which a walk suspends at its next free flight

const uint kSurviveThreshold = 429496730u;  // walk.h: keep with probability 1/10 ...
const double kSurviveBoost = 4294967296.0lf / 429496730.0lf;  // ... and the exact inverse weight
const float kInf = kBvhInf;

// The photon's stream.
uint gLo, gHi, gCounter, gUsed;
uvec4 gWords;
uint nextWord() {
  if (gUsed == 4u) {
    gWords = philox4x32_10(uvec4(gLo, gHi, gCounter++, Channel), Seed);
    gUsed = 0u;
  }
  return gWords[gUsed++];
}
float uniformFloat() { return unitFromBits(nextWord()); }

double gEntered = 0.0lf, gExited = 0.0lf, gEscaped = 0.0lf;
uint gScatters = 0u, gExits = 0u;
bool gSpecular = false;  // kSpecular
uint gIndex;

void recordExit(dvec3 x, vec3 n, vec3 d, double w) {
  const uint k = atomicAdd(exitCount, 1u);
  if (k < ExitCapacity) {
    exits[k].px = x.x;
    exits[k].py = x.y;
    exits[k].pz = x.z;
    exits[k].weight = w;
    exits[k].nx = n.x;
    exits[k].ny = n.y;
    exits[k].nz = n.z;
    exits[k].dx = d.x;
    exits[k].dy = d.y;
    exits[k].dz = d.z;
    exits[k].photon = gIndex;
    // The exit's rank in its photon, with its scattering order (0, 1, 2: more) in the top two
    // bits (mesh_gpu.cpp; slab.h: ScatteringOrder).
    exits[k].rank = gExits | (min(gScatters, 2u) << 30);
  }
  ++gExits;
  gExited += w;
}

void finish() {
  photons[gIndex].entered = gEntered;
  photons[gIndex].exited = gExited;
  photons[gIndex].escaped = gEscaped;
  photons[gIndex].scatters = gScatters;
  photons[gIndex].exits = gExits;
}

#include "reference/boundary.glsl"

#ifdef VOLUME
#include "reference/delta_tracking.glsl"
#endif

// ---- The walk ------------------------------------------------------------------------------

// At the boundary point x with normal n, going along d (transport_impl.h: crossBoundary): 0 the
// photon reflected back inside (d updated), 1 it exited (scored) and re-entered (x, d the
// re-entry), 2 it escaped.
uint crossBoundary(inout dvec3 x, inout vec3 d, vec3 n, double w) {
  const float etaOut = 1.0 / Eta;
  const vec3 outward = dot(n, d) > 0.0 ? n : -n;
  const float cosIn = dot(d, outward);
  const float F = Matched ? 0.0 : fresnelReflectanceFloat(max(cosIn, 0.0), etaOut);
  if (F > 0.0 && uniformFloat() < F) {
    d = normalize(d - 2.0 * cosIn * outward);
    if (gScatters == 0u) gSpecular = true;
    return 0u;
  }
  const vec3 dOut =
      Matched ? d : refractDir(d, outward, Eta, refractedCosineFloat(max(cosIn, 0.0), etaOut));
  if (!(AfterSpecularOnly && gScatters == 0u && !gSpecular)) recordExit(x, outward, dOut, w);
  d = dOut;
  bool mirrored = false;
  if (reenter(x, d, mirrored)) {
    if (gScatters == 0u) gSpecular = true;
    return 1u;
  }
  gEscaped = w;
  return 2u;
}

// Henyey-Greenstein scattering (line 16) and the seed's long-path roulette (section 3.2): false
// when the roulette ends the photon.
bool scatter(float g, inout vec3 d, inout double w) {
  const float mu = sampleHgCosine(g, uniformFloat());
  d = scatterDirection(d, mu, uniformAzimuth(nextWord()));
  ++gScatters;
  if (LongPath != 0u && gScatters > LongPath) {
    if (nextWord() >= kSurviveThreshold) return false;
    w *= kSurviveBoost;
  }
  return true;
}

// Writes the walk's state for the next dispatch (Phase 1).
void suspend(dvec3 x, vec3 d, double w, bool onSurface) {
  WalkState st;
  st.x = x.x;
  st.y = x.y;
  st.z = x.z;
  st.w = w;
  st.entered = gEntered;
  st.exited = gExited;
  st.escaped = gEscaped;
  st.pad = 0.0lf;
  st.dx = d.x;
  st.dy = d.y;
  st.dz = d.z;
  st.flags = kAlive | (onSurface ? kOnSurface : 0u) | (gSpecular ? kSpecular : 0u);
  st.counter = gCounter;
  st.used = gUsed;
  st.scatters = gScatters;
  st.exits = gExits;
  states[gIndex] = st;
  suspendList[atomicAdd(control[0], 1u)] = gIndex;
}

// The walk from a free flight on: true when it ended (finish() written), false when suspended.
bool walk(dvec3 x, vec3 d, double w, bool onSurface) {
  float t;
  vec3 n;
  uint tri;
#ifdef VOLUME
  for (;;) {
    WALK_WORK();
    if (gWork > WorkBudget) {
      suspend(x, d, w, onSurface);
      return false;
    }
    // The first real collision ignoring the boundary, then the boundary up to there.
    float tc;
    const bool collided = track(x, d, tc);
    if (!bvhIntersect(vec3(x), d, onSurface ? Epsilon : 0.0, collided ? tc : kInf, t, n, tri)) {
      if (!collided) break;  // lost
      x += double(tc) * dvec3(d);
      onSurface = false;
      if (AfterSpecularOnly && gScatters == 0u && !gSpecular) break;
      // Absorption with the local albedo, at 2^-32 (the local coefficients are floats).
      if (double(nextWord()) * (1.0lf / 4294967296.0lf) * double(gLocalSigmaT) <
          double(gLocalA[Channel] * CoefficientScale))
        break;
      if (!scatter(gLocalG, d, w)) break;
      continue;
    }
    x += double(t) * dvec3(d);
    onSurface = true;
    if (crossBoundary(x, d, n, w) == 2u) break;
  }
#else
  for (;;) {
    WALK_WORK();
    if (gWork > WorkBudget) {
      suspend(x, d, w, onSurface);
      return false;
    }
    // Free flight (Algorithm 1 line 3), then advance or meet the boundary (lines 4-14).
    float s = -fastLog(unitOpenZeroFromBits(nextWord())) * InvSigmaT;
    bool escaped = false;
    for (;;) {
      WALK_WORK();
      if (!bvhIntersect(vec3(x), d, onSurface ? Epsilon : 0.0, s, t, n, tri)) {
        x += double(s) * dvec3(d);
        onSurface = false;
        break;
      }
      x += double(t) * dvec3(d);
      s = max(0.0, s - t);
      onSurface = true;
      // crossBoundary: leave with probability 1 - F, else reflect and fly on (lines 6-8); after
      // a re-entry the rest of the flight goes on from the re-entry point.
      const uint b = crossBoundary(x, d, n, w);
      if (b == 2u) {
        escaped = true;
        break;
      }
    }
    if (escaped) break;
    if (AfterSpecularOnly && gScatters == 0u && !gSpecular) break;
    // Analog absorption (line 15) to 2^-64, then Henyey-Greenstein scattering (line 16).
    const uint hiWord = nextWord();
    if (hiWord <= AbsorbThreshold.x) {
      if (hiWord < AbsorbThreshold.x) break;
      if (nextWord() < AbsorbThreshold.y) break;
    }
    if (!scatter(G, d, w)) break;
  }
#endif
  finish();
  return true;
}

void main() {
  uint i = linearInvocationIndex();
  if (i >= Count) return;
  if (Phase == 1u) i = resumeList[i];
  gIndex = i;
  gLo = FirstPhoton.x + i;
  gHi = FirstPhoton.y + (gLo < i ? 1u : 0u);

  if (Phase == 1u) {
    // Resume a suspended walk where it stopped (its stream at the same word).
    const WalkState st = states[i];
    if ((st.flags & kAlive) == 0u) return;
    states[i].flags = 0u;
    gEntered = st.entered;
    gExited = st.exited;
    gEscaped = st.escaped;
    gScatters = st.scatters;
    gSpecular = (st.flags & kSpecular) != 0u;
    gExits = st.exits;
    gCounter = st.counter;
    gUsed = st.used;
    if (gUsed < 4u) gWords = philox4x32_10(uvec4(gLo, gHi, gCounter - 1u, Channel), Seed);
    walk(dvec3(st.x, st.y, st.z), vec3(st.dx, st.dy, st.dz), st.w, (st.flags & kOnSurface) != 0u);
    atomicMax(control[1], gWork);
    return;
  }
  states[i].flags = 0u;
  gCounter = 0u;
  gUsed = 4u;

  // Emission (transport_impl.h: launch, emit).
  uint li = 0u;
  if (LightCount > 1u) {
    const float u = uniformFloat();
    WALK_WORK();  // the loop may run no iteration
    while (li + 1u < LightCount && lights[li].cdf <= u) {
      WALK_WORK();
      ++li;
    }
  }
  const GpuLight L = lights[li];
  vec3 o, d;
  if (L.type == 3u) {
    // A point of the disc that covers the bounding sphere, perpendicular to the direction, outside
    // it (transport_impl.h: emit, EnvironmentLight); any orthonormal frame of the direction will
    // do (the disc is uniform in rotation).
    const vec3 toEnv = envDirs[i].xyz;
    const float sgn = toEnv.z >= 0.0 ? 1.0 : -1.0;
    const float a = -1.0 / (sgn + toEnv.z), b = toEnv.x * toEnv.y * a;
    const vec3 t1 = vec3(1.0 + sgn * toEnv.x * toEnv.x * a, sgn * b, -sgn * toEnv.x);
    const vec3 t2 = vec3(b, sgn + toEnv.y * toEnv.y * a, -toEnv.y);
    const float r = L.radius * sqrt(uniformFloat());
    const vec2 cs = uniformAzimuth(nextWord());
    o = L.p + 2.0 * L.radius * toEnv + r * cs.x * t1 + r * cs.y * t2;
    d = -toEnv;
  } else if (L.type == 1u) {
    const float cosT = 1.0 - uniformFloat() * (1.0 - L.cosMax);
    const float sinT = sqrt(max(0.0, 1.0 - cosT * cosT));
    const vec2 cs = uniformAzimuth(nextWord());
    o = L.p;
    d = normalize(sinT * cs.x * L.t1 + sinT * cs.y * L.t2 + cosT * L.dir);
  } else {
    const float r = L.radius * sqrt(uniformFloat());
    const vec2 cs = uniformAzimuth(nextWord());
    o = L.p + r * cs.x * L.t1 + r * cs.y * L.t2;
    d = L.dir;
  }
  double w = Flux;
  float t;
  vec3 n;
  uint tri;
  if (!bvhIntersect(o, d, 0.0, kInf, t, n, tri)) {
    finish();
    atomicMax(control[1], gWork);
    return;
  }
  dvec3 x = dvec3(o) + double(t) * dvec3(d);
  {
    const vec3 inward = dot(n, d) > 0.0 ? n : -n;
    if (!Matched) {
      const float cosI = dot(d, inward);
      w *= 1.0lf - fresnelReflectanceDouble(double(max(cosI, 0.0)), double(Eta));
      d = refractDir(d, inward, 1.0 / Eta, refractedCosineFloat(max(cosI, 0.0), Eta));
    }
  }
  gEntered = w;
  // The next ray starts on the boundary: ignore hits closer than ε.
  walk(x, d, w, true);
  atomicMax(control[1], gWork);
}
