// SPDX-License-Identifier: GPL-3.0-or-later
// Widgets generated from a technique's parameter list (techniques::ParameterInfo): Float -> slider
// and spin box (logarithmic slider when the parameter says so), Int -> spin box, Bool -> check
// box, Enum -> combo box. Every edit is reported as the scene setting it becomes.
#pragma once

#include <QtWidgets/QWidget>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "translucent/scene/scene.h"
#include "translucent/techniques/technique.h"

namespace translucent::explorer {

class ParameterForm : public QWidget {
  Q_OBJECT

 public:
  explicit ParameterForm(std::vector<techniques::ParameterInfo> infos, QWidget* parent = nullptr);

  // Shows these values (settings missing from the map show the parameter's default); emits
  // nothing.
  void setValues(const std::map<std::string, scene::Setting>& settings);
  const std::vector<techniques::ParameterInfo>& infos() const { return infos_; }

 signals:
  void edited(const QString& name, const translucent::scene::Setting& value);

 private:
  std::vector<techniques::ParameterInfo> infos_;
  std::map<std::string, std::function<void(const techniques::ParameterValue&)>> setters_;
};

// Slider position (0..kSliderSteps) <-> value, linear or logarithmic over [min, max].
inline constexpr int kSliderSteps = 1000;
double sliderToValue(int position, double min, double max, bool logarithmic);
int valueToSlider(double value, double min, double max, bool logarithmic);

}  // namespace translucent::explorer
