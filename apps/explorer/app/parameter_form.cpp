// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/parameter_form.h"

#include <QtCore/QSignalBlocker>
#include <QtWidgets/QCheckBox>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QFormLayout>
#include <QtWidgets/QHBoxLayout>
#include <QtWidgets/QLabel>
#include <QtWidgets/QSlider>
#include <QtWidgets/QSpinBox>

#include <algorithm>
#include <cmath>

namespace translucent::explorer {

using techniques::ParameterInfo;
using techniques::ParameterType;
using techniques::ParameterValue;

namespace {

// A logarithmic slider needs a positive range; a range starting at 0 falls back to linear.
bool useLog(const ParameterInfo& p) { return p.logarithmic && p.min > 0.0 && p.max > p.min; }

// Decimals that show the smallest value of the range.
int decimalsFor(const ParameterInfo& p) {
  const double smallest = p.min > 0.0 ? p.min : std::max(1e-6, (p.max - p.min) / 1000.0);
  return std::clamp(int(std::ceil(-std::log10(smallest))) + 2, 2, 8);
}

ParameterValue fromSetting(const ParameterInfo& p, const scene::Setting& s) {
  try {
    if (const auto* b = std::get_if<bool>(&s)) return techniques::checkedValue(p, *b);
    if (const auto* d = std::get_if<double>(&s)) {
      if (p.type == ParameterType::Int) return techniques::checkedValue(p, int(std::lround(*d)));
      return techniques::checkedValue(p, *d);
    }
    return techniques::checkedValue(p, std::get<std::string>(s));
  } catch (const std::exception&) {
    return p.value;  // the technique reports a bad setting when it is applied
  }
}

}  // namespace

double sliderToValue(int position, double min, double max, bool logarithmic) {
  const double t = std::clamp(double(position) / kSliderSteps, 0.0, 1.0);
  if (logarithmic && min > 0.0) return min * std::pow(max / min, t);
  return min + t * (max - min);
}

int valueToSlider(double value, double min, double max, bool logarithmic) {
  if (!(max > min)) return 0;
  double t = 0.0;
  if (logarithmic && min > 0.0)
    t = std::log(std::max(value, min) / min) / std::log(max / min);
  else
    t = (value - min) / (max - min);
  return int(std::lround(std::clamp(t, 0.0, 1.0) * kSliderSteps));
}

ParameterForm::ParameterForm(std::vector<ParameterInfo> infos, QWidget* parent)
    : QWidget(parent), infos_(std::move(infos)) {
  auto* form = new QFormLayout(this);
  form->setContentsMargins(0, 0, 0, 0);
  for (const ParameterInfo& p : infos_) {
    const QString name = QString::fromStdString(p.name);
    QString tip = QString::fromStdString(p.help);
    if (!p.unit.empty()) tip += QStringLiteral(" [%1]").arg(QString::fromStdString(p.unit));
    QWidget* editor = nullptr;
    switch (p.type) {
      case ParameterType::Float: {
        auto* row = new QWidget;
        auto* h = new QHBoxLayout(row);
        h->setContentsMargins(0, 0, 0, 0);
        auto* slider = new QSlider(Qt::Horizontal);
        slider->setRange(0, kSliderSteps);
        auto* spin = new QDoubleSpinBox;
        spin->setRange(p.min, p.max);
        spin->setDecimals(decimalsFor(p));
        spin->setSingleStep((p.max - p.min) / 100.0);
        spin->setKeyboardTracking(false);
        h->addWidget(slider, 1);
        h->addWidget(spin);
        const bool log = useLog(p);
        const double lo = p.min, hi = p.max;
        connect(slider, &QSlider::valueChanged, this, [this, spin, name, lo, hi, log](int pos) {
          const double v = sliderToValue(pos, lo, hi, log);
          QSignalBlocker block(spin);
          spin->setValue(v);
          emit edited(name, scene::Setting(v));
        });
        connect(spin, &QDoubleSpinBox::valueChanged, this, [this, slider, name, lo, hi, log](double v) {
          QSignalBlocker block(slider);
          slider->setValue(valueToSlider(v, lo, hi, log));
          emit edited(name, scene::Setting(v));
        });
        setters_[p.name] = [slider, spin, lo, hi, log](const ParameterValue& v) {
          const double d = std::get<double>(v);
          QSignalBlocker b1(slider), b2(spin);
          spin->setValue(d);
          slider->setValue(valueToSlider(d, lo, hi, log));
        };
        slider->setObjectName(name + QStringLiteral("_slider"));
        spin->setObjectName(name);
        editor = row;
        break;
      }
      case ParameterType::Int: {
        auto* spin = new QSpinBox;
        spin->setRange(int(p.min), int(p.max));
        spin->setKeyboardTracking(false);
        connect(spin, &QSpinBox::valueChanged, this,
                [this, name](int v) { emit edited(name, scene::Setting(double(v))); });
        setters_[p.name] = [spin](const ParameterValue& v) {
          QSignalBlocker b(spin);
          spin->setValue(std::get<int>(v));
        };
        spin->setObjectName(name);
        editor = spin;
        break;
      }
      case ParameterType::Bool: {
        auto* box = new QCheckBox;
        connect(box, &QCheckBox::toggled, this,
                [this, name](bool v) { emit edited(name, scene::Setting(v)); });
        setters_[p.name] = [box](const ParameterValue& v) {
          QSignalBlocker b(box);
          box->setChecked(std::get<bool>(v));
        };
        box->setObjectName(name);
        editor = box;
        break;
      }
      case ParameterType::Enum: {
        auto* combo = new QComboBox;
        for (const auto& c : p.choices) combo->addItem(QString::fromStdString(c));
        connect(combo, &QComboBox::currentTextChanged, this, [this, name](const QString& v) {
          emit edited(name, scene::Setting(v.toStdString()));
        });
        setters_[p.name] = [combo](const ParameterValue& v) {
          QSignalBlocker b(combo);
          combo->setCurrentText(QString::fromStdString(std::get<std::string>(v)));
        };
        combo->setObjectName(name);
        editor = combo;
        break;
      }
    }
    editor->setToolTip(tip);
    auto* label = new QLabel(name);
    label->setToolTip(tip);
    form->addRow(label, editor);
  }
  setValues({});
}

void ParameterForm::setValues(const std::map<std::string, scene::Setting>& settings) {
  for (const ParameterInfo& p : infos_) {
    const auto it = settings.find(p.name);
    const ParameterValue v = it == settings.end() ? p.value : fromSetting(p, it->second);
    setters_.at(p.name)(v);
  }
}

}  // namespace translucent::explorer
