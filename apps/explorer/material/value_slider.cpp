// SPDX-License-Identifier: GPL-3.0-or-later
#include "material/value_slider.h"

#include <QtCore/QSignalBlocker>
#include <QtWidgets/QHBoxLayout>
#include <QtWidgets/QLineEdit>
#include <QtWidgets/QSlider>

#include <algorithm>
#include <cmath>

namespace translucent::explorer {
namespace {
constexpr int kSteps = 1000;  // slider positions
}

ValueSlider::ValueSlider(QString name, double min, double max, Scale scale, QWidget* parent)
    : QWidget(parent), name_(std::move(name)), min_(min), max_(max), scale_(scale) {
  slider_ = new QSlider(Qt::Horizontal, this);
  slider_->setRange(0, kSteps);
  field_ = new QLineEdit(this);
  field_->setMaximumWidth(90);
  auto* row = new QHBoxLayout(this);
  row->setContentsMargins(0, 0, 0, 0);
  row->addWidget(slider_, 1);
  row->addWidget(field_);
  connect(slider_, &QSlider::valueChanged, this, &ValueSlider::fromSlider);
  connect(field_, &QLineEdit::editingFinished, this, &ValueSlider::fromField);
  setValue(min);
}

int ValueSlider::positionOf(double v) const {
  double t = 0.0;
  if (scale_ == Scale::Log)
    t = v > 0.0 ? std::log(v / min_) / std::log(max_ / min_) : 0.0;
  else
    t = (v - min_) / (max_ - min_);
  return static_cast<int>(std::lround(std::clamp(t, 0.0, 1.0) * kSteps));
}

void ValueSlider::setValue(double v) {
  value_ = v;
  const QSignalBlocker a(slider_), b(field_);
  slider_->setValue(positionOf(v));
  field_->setText(QString::number(v, 'g', 6));
}

void ValueSlider::fromSlider(int position) {
  const double t = static_cast<double>(position) / kSteps;
  const double v = scale_ == Scale::Log ? min_ * std::pow(max_ / min_, t) : min_ + t * (max_ - min_);
  if (accept_ && !accept_(v).isEmpty()) {
    setValue(value_);
    return;
  }
  value_ = v;
  {
    const QSignalBlocker b(field_);
    field_->setText(QString::number(v, 'g', 6));
  }
  emit valueChanged(v);
}

void ValueSlider::fromField() {
  const QString text = field_->text().trimmed();
  bool ok = false;
  const double v = text.toDouble(&ok);
  QString why;
  if (!ok || !std::isfinite(v))
    why = QStringLiteral("%1: '%2' is not a finite number").arg(name_, text);
  else if (accept_)
    why = accept_(v);
  if (!why.isEmpty()) {
    setValue(value_);  // the field shows the value in use again
    emit rejected(why);
    return;
  }
  if (v == value_) return;
  setValue(v);
  emit valueChanged(v);
}

}  // namespace translucent::explorer
