// SPDX-License-Identifier: GPL-3.0-or-later
// "Copy command line": the `translucent render` invocation that reproduces the viewport's image
// from a saved scene file (round trip with the CLI, issue 6 section 2).
#pragma once

#include <QtCore/QString>

#include <filesystem>

namespace translucent::explorer {

// `<cli> render <scene> --technique <name> --width <w> --height <h> --exr <exr>`, with the
// arguments quoted for a POSIX shell where needed. The scene file holds everything else (mesh,
// material, lights, camera, technique settings, display); `cli` is the program name to print
// ("translucent" when it is on the PATH) and `exr` the output (omitted when empty).
QString renderCommandLine(const QString& cli, const std::filesystem::path& scene_file,
                          const QString& technique, int width, int height,
                          const QString& exr = QString());

// POSIX shell quoting: the word as is when it has only safe characters, else in single quotes.
QString shellQuote(const QString& word);

}  // namespace translucent::explorer
