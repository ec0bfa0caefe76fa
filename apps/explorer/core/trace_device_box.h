// SPDX-License-Identifier: GPL-3.0-or-later
// The path tracers' device choice of the docks (the lit spheres' tracer, the pencil plot's
// reference): a combo box of "auto", "cpu" and "gpu" (its items' data: the words
// reference::openTraceDevice takes), with the tooltip that says what each means. Header-only
// and widgets only, as pixel_image_view.h: for the docks, not for core's own target.
#pragma once

#include <QtCore/QCoreApplication>
#include <QtWidgets/QComboBox>

namespace translucent::explorer {

// `what`: what it traces, for the tooltip ("the path tracer", "the reference").
inline QComboBox* makeTraceDeviceBox(const QString& objectName, const QString& what,
                                     QWidget* parent = nullptr) {
  auto tr = [](const char* s) { return QCoreApplication::translate("TraceDeviceBox", s); };
  auto* box = new QComboBox(parent);
  box->setObjectName(objectName);
  box->addItem(tr("Auto"), QStringLiteral("auto"));
  box->addItem(tr("CPU"), QStringLiteral("cpu"));
  box->addItem(tr("GPU"), QStringLiteral("gpu"));
  box->setToolTip(tr("Where %1 runs. GPU: an OpenGL 4.5 compute shader (its own random streams: "
                     "the same result within its errors, not bit for bit). Auto: the GPU on a "
                     "hardware GPU, else the CPU, which is faster than a software renderer")
                      .arg(what));
  return box;
}

}  // namespace translucent::explorer
