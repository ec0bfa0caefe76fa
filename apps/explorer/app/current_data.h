// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's "Print current data" (empirical seed, appendix A: "print all current data"): the
// scene as JSON, then every parameter of its technique with the value it renders with (the
// scene's setting, else the default, marked "(default)"). An unknown technique is said in the
// text; nothing is thrown.
#pragma once

#include <QtCore/QString>

#include "translucent/scene/scene.h"

namespace translucent::explorer {

QString currentDataText(const scene::Scene& scene);

}  // namespace translucent::explorer
