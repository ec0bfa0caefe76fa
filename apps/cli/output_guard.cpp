#include "output_guard.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <system_error>
#include <variant>

#include "geometry/atomic_file.h"
#include "optics/medium.h"
#include "scene/scene.h"

namespace translucent::cli {
namespace fs = std::filesystem;

namespace {

// The same file? weakly_canonical resolves "./x", "a/../x" and symbolic links of existing
// parents; equivalent also catches hard links and links to the file itself.
bool sameFile(const fs::path& a, const fs::path& b) {
  // Absolute first: weakly_canonical leaves a relative path whose first part does not exist
  // relative ("x.json"), but makes "./x.json" absolute, so the two would differ.
  std::error_code ec1, ec2;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec1), ec1);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, ec2), ec2);
  if (!ec1 && !ec2 && ca == cb) return true;
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}

}  // namespace

CLI::Option* outputOption(CLI::Option* option) {
  return option->check(CLI::Validator(
      [](std::string& value) -> std::string {
        return value.empty() ? "empty path: expected a file name" : "";
      },
      "FILE"));
}

void OutputSet::output(std::string option, std::string path) {
  if (!path.empty()) outputs_.emplace_back(std::move(option), std::move(path));
}

void OutputSet::input(std::string what, const fs::path& path) {
  std::error_code ec;
  if (!path.empty() && fs::exists(path, ec)) inputs_.emplace_back(std::move(what), path);
}

void OutputSet::sceneInputs(const fs::path& scene_file, const scene::Scene& s) {
  if (!scene_file.empty()) input("the scene", scene_file);
  input("the scene's mesh", s.mesh_file);
  input("the scene's BSSRDF model", s.model);
  for (const scene::Light& l : s.lights) {
    if (const auto* f = std::get_if<scene::FilteredDirectionalLight>(&l.emitter))
      input("a light's filter texture", f->texture);
    if (const auto* e = std::get_if<scene::EnvironmentLight>(&l.emitter))
      input("the environment map", e->file);
  }
}

void OutputSet::check() const {
  for (size_t i = 0; i < outputs_.size(); ++i) {
    const auto& [option, path] = outputs_[i];
    std::error_code ec;
    if (fs::is_directory(path, ec))
      throw ParameterError(fmt::format("{} '{}': is a folder: expected a file name", option, path));
    const fs::path dir = fs::path(path).parent_path().empty() ? fs::path(".")
                                                                : fs::path(path).parent_path();
    if (!fs::is_directory(dir, ec))
      throw ParameterError(fmt::format("{} '{}': cannot write: folder '{}' does not exist",
                                       option, path, dir.string()));
    // The temporary file is created in the folder, so the folder must be writable even when the
    // target itself is (a device is written directly and needs only its own permission).
    const bool special = fs::exists(path, ec) && !fs::is_regular_file(path, ec);
    if (special ? ::access(path.c_str(), W_OK) != 0 : ::access(dir.c_str(), W_OK) != 0)
      throw ParameterError(fmt::format("{} '{}': cannot write: {} is not writable", option, path,
                                       special ? "the file" : fmt::format("folder '{}'", dir.string())));
    for (const auto& [what, in] : inputs_)
      if (sameFile(path, in))
        throw ParameterError(fmt::format("{} '{}': is {} of this run ('{}'): refusing to "
                                         "overwrite an input; choose another output file",
                                         option, path, what, in.string()));
    for (size_t j = 0; j < i; ++j)
      if (sameFile(path, outputs_[j].second) && !special)
        throw ParameterError(fmt::format("{} '{}' and {} '{}' are the same file: each output "
                                         "needs its own file",
                                         outputs_[j].first, outputs_[j].second, option, path));
  }
}

void writeTextOutput(const std::string& option, const std::string& path, std::string_view text) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec) && !fs::is_directory(path, ec)) {
    // A device or FIFO: written in place (renaming would replace the device node); every byte
    // and the close are checked, so /dev/full is an error.
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) throw ParameterError(fmt::format("{} '{}': cannot open for writing", option, path));
    const bool wrote = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    const bool flushed = std::fflush(f) == 0;
    const bool closed = std::fclose(f) == 0;
    if (!(wrote && flushed && closed))
      throw ParameterError(fmt::format("{} '{}': write failed (device full?)", option, path));
    return;
  }
  const std::string why = geometry::writeFileAtomically(path, text);
  if (!why.empty()) throw ParameterError(fmt::format("{} '{}': write failed: {}", option, path, why));
}

void writeOutput(const std::string& path, const std::function<void(const std::string&)>& write) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec) && !fs::is_directory(path, ec)) {
    write(path);
    return;
  }
  static int counter = 0;
  const fs::path p(path);
  const std::string tmp = (p.parent_path() / fmt::format(".{}.tmp-{}-{}{}", p.stem().string(),
                                                          ::getpid(), counter++,
                                                          p.extension().string()))
                              .string();
  try {
    write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string message = ec.message();
    fs::remove(tmp, ec);
    throw ParameterError(fmt::format("cannot write '{}': {}", path, message));
  }
}

}  // namespace translucent::cli
