// SPDX-License-Identifier: GPL-3.0-or-later
// A slider with a numeric field for one real parameter: logarithmic (σa, σs, ℓd, scale span
// decades; seed 3.6.1 "the sliders are in logarithmic scale where appropriate") or linear (g, η,
// Rd, .bssrdf floats in [min, max]).
//
// The slider covers [min, max]; the field accepts any number that `accept` allows (a value outside
// the slider's range parks the slider at its end). Text that is not a number, or one `accept`
// refuses, is reported through rejected(message) and the field returns to the current value:
// the value never changes on bad input.
#pragma once

#include <QtWidgets/QWidget>

#include <functional>

class QLineEdit;
class QSlider;

namespace translucent::explorer {

class ValueSlider : public QWidget {
  Q_OBJECT

 public:
  enum class Scale { Linear, Log };
  // `accept(v)` returns an empty string for an acceptable value, else why not.
  ValueSlider(QString name, double min, double max, Scale scale, QWidget* parent = nullptr);

  double value() const { return value_; }
  // Sets the value shown without emitting valueChanged.
  void setValue(double v);
  void setAcceptor(std::function<QString(double)> accept) { accept_ = std::move(accept); }
  QSlider* slider() const { return slider_; }
  QLineEdit* field() const { return field_; }

 signals:
  void valueChanged(double value);     // a user edit (slider or field)
  void rejected(const QString& why);   // bad text in the field

 private:
  void fromSlider(int position);
  void fromField();
  int positionOf(double v) const;

  QString name_;
  double min_, max_;
  Scale scale_;
  double value_ = 0.0;
  QSlider* slider_;
  QLineEdit* field_;
  std::function<QString(double)> accept_;
};

}  // namespace translucent::explorer
