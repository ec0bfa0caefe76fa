// SPDX-License-Identifier: GPL-3.0-or-later
// Real-time rendering techniques: the small interface every technique implements, and the typed
// parameter descriptors from which the command line (and a GUI) build their options and widgets.
//
// Life of a technique:
//   auto t = techniques::make("pointcloud");          // techniques/registry.h
//   for (const auto& p : t->parameters()) ...          // name, type, range, default, help
//   t->setParameter("epsilon", 0.1);                   // checked against the descriptor
//   t->prepare(scene, context);                        // load, sample, upload (current GL context)
//   techniques::Frame f = t->render({});               // linear RGB + per-pass GPU times
//
// A technique owns GL objects once prepared: destroy it while its context is alive and current
// (create the gpu::Context before the technique).
//
// prepare() may be called again with an edited scene; a technique keeps what it can (a point
// cloud stays as long as the mesh, its placement and the point count do). Parameters may change
// between frames; render() redoes only the work they invalidate.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/gpu/context.h"
#include "translucent/optics/medium.h"
#include "translucent/scene/scene.h"

namespace translucent::techniques {

enum class ParameterType { Float, Int, Bool, Enum };
const char* toString(ParameterType type);

// A parameter's value: Float -> double, Int -> int, Bool -> bool, Enum -> std::string.
using ParameterValue = std::variant<double, int, bool, std::string>;

// Describes one parameter: enough for a command-line option or a widget (slider, spin box, check
// box, combo box) with its range and help text.
struct ParameterInfo {
  std::string name;  // identifier: lower case, words joined by '_' ("shadow_map_size")
  ParameterType type = ParameterType::Float;
  double min = 0.0, max = 0.0;       // Float and Int: inclusive range
  ParameterValue value;              // the default
  std::vector<std::string> choices;  // Enum: the valid values
  std::string unit;                  // "" when dimensionless ("sr", "texels", "scene units")
  std::string help;                  // one sentence
  bool logarithmic = false;          // Float: a slider should be logarithmic (seed 3.6.1)
  // A quality parameter: the values `translucent compare --sweep` renders to plot error against
  // GPU time (equal-time and equal-error comparisons). Empty: not a quality parameter.
  std::vector<double> sweep;

  static ParameterInfo floating(std::string name, double def, double min, double max,
                                std::string help, std::string unit = "", bool log = false);
  static ParameterInfo integer(std::string name, int def, int min, int max, std::string help,
                               std::string unit = "");
  static ParameterInfo boolean(std::string name, bool def, std::string help);
  static ParameterInfo enumeration(std::string name, std::string def,
                                   std::vector<std::string> choices, std::string help);
  // The same descriptor declared a quality parameter swept over `values` (each in range).
  ParameterInfo withSweep(std::vector<double> values) &&;
};

// Converts `value` to the parameter's type and checks it (range, finiteness, choices): ints are
// accepted for Float; whole doubles for Int; for every type, text as typed on a command line
// ("0.5", "12", "true"/"false"/"on"/"off"/"1"/"0", an enum value). Throws ParameterError naming
// the parameter, the value and what was expected.
ParameterValue checkedValue(const ParameterInfo& info, const ParameterValue& value);
std::string toString(const ParameterValue& value);

// A technique's parameter values, checked against its descriptors. Techniques own one.
class ParameterSet {
 public:
  explicit ParameterSet(std::vector<ParameterInfo> infos);
  const std::vector<ParameterInfo>& infos() const { return infos_; }
  const ParameterInfo& info(std::string_view name) const;  // ParameterError listing valid names
  // Sets a checked value; returns true when it differs from the current one.
  bool set(std::string_view name, const ParameterValue& value);
  const ParameterValue& get(std::string_view name) const;
  double getFloat(std::string_view name) const { return std::get<double>(get(name)); }
  int getInt(std::string_view name) const { return std::get<int>(get(name)); }
  bool getBool(std::string_view name) const { return std::get<bool>(get(name)); }
  const std::string& getEnum(std::string_view name) const { return std::get<std::string>(get(name)); }

 private:
  std::vector<ParameterInfo> infos_;
  std::map<std::string, ParameterValue, std::less<>> values_;
};

// GPU time of one pass of a frame.
struct PassTime {
  std::string name;
  double ms = 0.0;
  int depth = 0;  // nesting level (sub-passes of a pass have depth 1)
};

struct FrameRequest {
  int width = 0, height = 0;  // 0: the scene camera's resolution
  // Batch rendering: finish the progressive work (e.g. all environment samples) in this frame,
  // so that it is converged; interactive use leaves it false and renders frame after frame.
  bool converge = false;
  // False: the frame stays on the GPU (Frame::rgb and the layers are left empty, the passes are
  // timed as usual). For benchmarks of the GPU work of back-to-back frames, as a viewer that
  // draws from GPU memory would render them; reading images back stalls the pipeline.
  bool readback = true;
  // Also the technique's inspection views (Frame::views), which cost a read-back of their own:
  // for the explorer's views dock and `translucent render --debug-dir`.
  bool views = false;
};

// An image a technique shows about its own state, of its own size (e.g. tsis: the irradiance
// atlas with the frame's samples drawn over it, seed Fig. 3.1): display-ready RGB in [0, 1]
// (rows from the top), shown as it is (no exposure, gamma 1).
struct FrameView {
  int width = 0, height = 0;
  std::vector<float> rgb;
  std::string description;
};

// A curve plot a technique shows about its own state (e.g. splatting: the minimal effective
// rendering radius over resolution, Chen et al. 2012 Fig. 3b): written by `translucent render
// --debug-dir` as SVG and CSV.
struct FramePlot {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  struct Series {
    std::string label;
    std::vector<double> x, y;
  };
  std::vector<Series> series;
};

// One rendered frame: linear RGB radiance [W/(unit² sr) per unit light flux], rows from the top.
struct Frame {
  int width = 0, height = 0;
  std::vector<float> rgb;
  // Extra images of the same size (RGB), e.g. "exitance" (radiant exitance B).
  std::map<std::string, std::vector<float>> layers;
  // Inspection views (only when FrameRequest::views; none for most techniques).
  std::map<std::string, FrameView> views;
  std::map<std::string, FramePlot> plots;  // as views (FrameRequest::views)
  std::vector<PassTime> passes;
  // False while a progressive technique is still accumulating (render again to refine).
  bool converged = true;
  std::vector<std::string> notes;  // what the technique wants the user to know (cache use, ...)
  double totalMs() const;          // sum of the depth-0 passes
};

class Technique {
 public:
  virtual ~Technique() = default;
  virtual std::string_view name() const = 0;
  virtual std::string_view description() const = 0;

  virtual const std::vector<ParameterInfo>& parameters() const = 0;
  // Throws ParameterError for an unknown name or a value of the wrong type or out of range.
  virtual void setParameter(std::string_view name, const ParameterValue& value) = 0;
  virtual ParameterValue parameter(std::string_view name) const = 0;

  // Loads the scene's mesh, material and lights and uploads what the technique needs. The
  // context must be current. Throws ParameterError, geometry::MeshError, gpu::GlError, ... with
  // a message naming the file or parameter at fault.
  virtual void prepare(const scene::Scene& scene, gpu::Context& gl) = 0;
  // Renders one frame of the prepared scene.
  virtual Frame render(const FrameRequest& request) = 0;
  // A new camera for the prepared scene without prepare() (issue 14 §6: orbiting keeps every
  // light-dependent result: shadow maps, irradiance, the environment map and its accumulated
  // samples). Returns false when the technique cannot take it that way; the caller then
  // prepares the scene with the new camera. Throws ParameterError for an invalid camera.
  virtual bool setCamera(const reference::Camera& camera) {
    (void)camera;
    return false;
  }
};

// Applies a scene's technique settings (scene.settings) with setParameter.
void applySettings(Technique& technique, const scene::Scene& scene);

// The convention of the technique's radiance (Frame::rgb): its `radiance_convention` parameter,
// else Jensen (the techniques without one compute no radiance from an exitance, or compute
// Ft B / π). `translucent compare` and the explorer's Compare dock convert the reference by it.
bssrdf::ExitConvention radianceConvention(const Technique& technique);

}  // namespace translucent::techniques
