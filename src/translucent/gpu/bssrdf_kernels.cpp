// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/bssrdf_kernels.h"

#include <fmt/format.h>

#include <cstdlib>

#include "translucent/gpu/compute.h"
#include "translucent/io/resources.h"


namespace translucent::gpu {
namespace {

const char* kernelFile(BssrdfKernel kernel) {
  switch (kernel) {
    case BssrdfKernel::Profile: return "bssrdf/profile.comp";
    case BssrdfKernel::DiffuseReflectance: return "bssrdf/diffuse_reflectance.comp";
    case BssrdfKernel::Directional: return "bssrdf/directional.comp";
  }
  return "";
}

}  // namespace

ShaderPreprocessor bssrdfPreprocessor(const bssrdf::BssrdfFile& file) {
  ShaderPreprocessor pp;

  // Parameters: one uniform per declaration, each on its declaration's line.
  SourceFile params;
  params.path = file.path;
  for (const auto& p : file.parameters) {
    const char* type = std::holds_alternative<bssrdf::FloatParameter>(p.spec)  ? "float"
                       : std::holds_alternative<bssrdf::BoolParameter>(p.spec) ? "bool"
                                                                               : "vec3";
    params.text += fmt::format("uniform {} {};\n", type, p.name);
    params.line_numbers.push_back(p.line);
  }
  pp.addVirtualFile("bssrdf:parameters", std::move(params));

  auto section = [&](const std::optional<bssrdf::GlslSection>& s, const char* name,
                     const char* fallbackPath, const char* fallbackText) {
    SourceFile f;
    if (s) {
      f.path = file.path;
      f.text = s->code;
      f.first_line = s->first_line;
    } else {
      f.path = fallbackPath;
      f.text = fallbackText;
    }
    pp.addVirtualFile(name, std::move(f));
  };
  section(file.initializer, "bssrdf:initializer", "<default initializer>", "void init() {}\n");
  section(file.diffuse_reflectance, "bssrdf:diffuseReflectance", "<no diffuseReflectance>", "");
  section(file.shader, "bssrdf:shader", "", "");
  return pp;
}

namespace {

const char* typeName(const ParameterValue& v) {
  return std::holds_alternative<double>(v) ? "float" : std::holds_alternative<bool>(v) ? "bool"
                                                                                       : "color";
}

ParameterValue defaultValue(const bssrdf::BssrdfParameter& p) {
  if (const auto* f = std::get_if<bssrdf::FloatParameter>(&p.spec)) return f->value;
  if (const auto* b = std::get_if<bssrdf::BoolParameter>(&p.spec)) return b->value;
  return std::get<bssrdf::ColorParameter>(p.spec).value;
}

glm::vec3 toVec3(const Rgb& c) {
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

}  // namespace

std::filesystem::path bssrdfDirectory() {
  if (const char* env = std::getenv("TRANSLUCENT_BSSRDF_DIR"); env != nullptr && *env != '\0')
    return std::filesystem::path(env);
  return io::shareDirectory() / "data" / "bssrdf";
}

ShaderSource assembleBssrdfKernel(const bssrdf::BssrdfFile& file, BssrdfKernel kernel) {
  if (kernel == BssrdfKernel::DiffuseReflectance && !file.diffuse_reflectance)
    throw GlError(fmt::format("{}: error: no 'diffuseReflectance' section: the Rdr(alpha') kernel "
                              "(and the Rdr, ld parametrisation) is unavailable for this model",
                              file.path));
  return bssrdfPreprocessor(file).load(kernelFile(kernel));
}

ShaderProgram buildBssrdfKernel(const bssrdf::BssrdfFile& file, BssrdfKernel kernel) {
  auto snapshot = std::make_shared<const bssrdf::BssrdfFile>(file);
  return ShaderProgram(fmt::format("{} ({})", file.path, kernelFile(kernel)),
                       {{GL_COMPUTE_SHADER, [snapshot, kernel] {
                           return assembleBssrdfKernel(*snapshot, kernel);
                         }}});
}

BssrdfEvaluator::BssrdfEvaluator(std::filesystem::path file) : path_(std::move(file)) {
  auto parsed = std::make_shared<const bssrdf::BssrdfFile>(bssrdf::loadBssrdf(path_));
  profile_.emplace(buildBssrdfKernel(*parsed, BssrdfKernel::Profile));
  if (parsed->diffuse_reflectance)
    rd_.emplace(buildBssrdfKernel(*parsed, BssrdfKernel::DiffuseReflectance));
  file_ = std::move(parsed);
}

BssrdfEvaluator BssrdfEvaluator::builtin(std::string_view name) {
  return BssrdfEvaluator(bssrdfDirectory() / (std::string(name) + ".bssrdf"));
}

void BssrdfEvaluator::setMedium(const Medium& medium) {
  medium.validate();
  medium_ = medium;
}

void BssrdfEvaluator::setParameter(std::string_view name, const ParameterValue& value) {
  const bssrdf::BssrdfParameter* p = file_->findParameter(name);
  if (p == nullptr) {
    std::string names;
    for (const auto& q : file_->parameters) names += (names.empty() ? "" : ", ") + q.name;
    throw ParameterError(fmt::format("{}: no parameter '{}' (declared: {})", file_->path, name,
                                     names.empty() ? "none" : names));
  }
  const ParameterValue def = defaultValue(*p);
  if (value.index() != def.index())
    throw ParameterError(fmt::format("{}: parameter '{}' is a {} (line {}), got a {} value",
                                     file_->path, name, typeName(def), p->line, typeName(value)));
  if (const auto* f = std::get_if<bssrdf::FloatParameter>(&p->spec)) {
    const double v = std::get<double>(value);
    if (!(v >= f->min && v <= f->max))
      throw ParameterError(fmt::format("{}: parameter '{}' is {}: expected a value in [{}, {}]",
                                       file_->path, name, v, f->min, f->max));
  }
  overrides_.insert_or_assign(std::string(name), value);
}

ParameterValue BssrdfEvaluator::parameter(std::string_view name) const {
  const bssrdf::BssrdfParameter* p = file_->findParameter(name);
  if (p == nullptr) throw ParameterError(fmt::format("{}: no parameter '{}'", file_->path, name));
  const auto it = overrides_.find(name);
  return it != overrides_.end() ? it->second : defaultValue(*p);
}

void BssrdfEvaluator::applyUniforms(const ShaderProgram& program) const {
  // Per-channel coefficients in scene units, exactly as Medium::channel(c) hands them to the
  // C++ models (σ · scale).
  glm::vec3 sa, ss;
  for (int c = 0; c < 3; ++c) {
    const ScalarMedium ch = medium_.channel(c);
    sa[c] = static_cast<float>(ch.sigma_a);
    ss[c] = static_cast<float>(ch.sigma_s);
  }
  program.set("SigmaA", sa);
  program.set("SigmaS", ss);
  program.set("G", static_cast<float>(medium_.g));
  program.set("IOR", static_cast<float>(medium_.eta));
  for (const auto& p : file_->parameters) {
    const ParameterValue value = parameter(p.name);
    const std::string& name = p.name;
    if (const auto* d = std::get_if<double>(&value)) program.set(name, static_cast<float>(*d));
    else if (const auto* b = std::get_if<bool>(&value)) program.set(name, *b);
    else program.set(name, toVec3(std::get<Rgb>(value)));
  }
}

std::vector<std::array<float, 3>> BssrdfEvaluator::run(ShaderProgram& program,
                                                      std::span<const float> input, size_t count) {
  if (count == 0) return {};
  const Buffer in = makeStorageBuffer(input);
  const Buffer out = makeStorageBuffer(count * 4 * sizeof(float));
  bindStorage(0, in);
  bindStorage(1, out);
  applyUniforms(program);
  program.set("BssrdfCount", static_cast<unsigned>(count));
  dispatch1D(program, count);
  const auto raw = download<float>(out, count * 4);
  std::vector<std::array<float, 3>> result(count);
  for (size_t i = 0; i < count; ++i) result[i] = {raw[4 * i], raw[4 * i + 1], raw[4 * i + 2]};
  return result;
}

std::vector<std::array<float, 3>> BssrdfEvaluator::profile(std::span<const float> radii) {
  return run(*profile_, radii, radii.size());
}

std::vector<std::array<float, 3>> BssrdfEvaluator::evaluate(std::span<const BssrdfQuery> queries) {
  if (!directional_) directional_.emplace(buildBssrdfKernel(*file_, BssrdfKernel::Directional));
  std::vector<float> packed;
  packed.reserve(queries.size() * 24);
  for (const BssrdfQuery& q : queries)
    for (const glm::vec3& v : {q.x_i, q.n_i, q.w_i, q.x_o, q.n_o, q.w_o})
      packed.insert(packed.end(), {v.x, v.y, v.z, 0.0f});
  return run(*directional_, packed, queries.size());
}

std::vector<std::array<float, 3>> BssrdfEvaluator::diffuseReflectance(
    std::span<const float> alpha_prime) {
  if (!rd_)
    throw GlError(fmt::format("{}: no 'diffuseReflectance' section: Rdr(alpha') is unavailable",
                              file_->path));
  return run(*rd_, alpha_prime, alpha_prime.size());
}

bool BssrdfEvaluator::reload() {
  try {
    // Build everything from one snapshot of the file before replacing anything.
    auto parsed = std::make_shared<const bssrdf::BssrdfFile>(bssrdf::loadBssrdf(path_));
    ShaderProgram profile = buildBssrdfKernel(*parsed, BssrdfKernel::Profile);
    std::optional<ShaderProgram> rd;
    if (parsed->diffuse_reflectance)
      rd.emplace(buildBssrdfKernel(*parsed, BssrdfKernel::DiffuseReflectance));

    std::map<std::string, ParameterValue, std::less<>> overrides;
    for (const auto& p : parsed->parameters) {
      const auto old = overrides_.find(p.name);
      if (old == overrides_.end() || old->second.index() != defaultValue(p).index()) continue;
      const auto* f = std::get_if<bssrdf::FloatParameter>(&p.spec);
      if (f != nullptr && !(std::get<double>(old->second) >= f->min &&
                            std::get<double>(old->second) <= f->max))
        continue;
      overrides.emplace(p.name, old->second);
    }

    profile_.emplace(std::move(profile));
    rd_ = std::move(rd);
    directional_.reset();  // rebuilt from the new file by the next evaluate()
    overrides_ = std::move(overrides);
    file_ = std::move(parsed);
    last_error_.clear();
    return true;
  } catch (const std::exception& e) {
    last_error_ = e.what();
    return false;
  }
}

std::unique_ptr<BssrdfEvaluator> openBssrdf(const std::filesystem::path& path) {
  try {
    return std::make_unique<BssrdfEvaluator>(path);
  } catch (const bssrdf::BssrdfFileError& err) {
    throw ParameterError(err.what());
  } catch (const GlError& err) {
    throw ParameterError(bssrdf::firstBssrdfLine(err.what()));
  }
}

}  // namespace translucent::gpu
