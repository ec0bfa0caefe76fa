// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/command_line.h"

#include <QtCore/QRegularExpression>
#include <QtCore/QStringList>

namespace translucent::explorer {

QString shellQuote(const QString& word) {
  static const QRegularExpression safe(QStringLiteral("^[A-Za-z0-9_./:=+,@%-]+$"));
  if (!word.isEmpty() && safe.match(word).hasMatch()) return word;
  QString quoted = word;
  quoted.replace(QLatin1Char('\''), QStringLiteral("'\\''"));
  return QLatin1Char('\'') + quoted + QLatin1Char('\'');
}

QString renderCommandLine(const QString& cli, const std::filesystem::path& scene_file,
                          const QString& technique, int width, int height, const QString& exr) {
  QStringList words = {shellQuote(cli), QStringLiteral("render"),
                       shellQuote(QString::fromStdString(scene_file.string())),
                       QStringLiteral("--technique"), shellQuote(technique),
                       QStringLiteral("--width"), QString::number(width),
                       QStringLiteral("--height"), QString::number(height)};
  if (!exr.isEmpty()) words << QStringLiteral("--exr") << shellQuote(exr);
  return words.join(QLatin1Char(' '));
}

}  // namespace translucent::explorer
