// SPDX-License-Identifier: GPL-3.0-or-later
// The .bssrdf parser (seed appendix A.2): the seed's own listing, and one malformed variant per
// kind of mistake, each reported at the right line with what was expected. No GL needed.
#include <gtest/gtest.h>

#include <gmock/gmock.h>

#include <sstream>
#include <string>
#include <vector>

#include "translucent/bssrdf/bssrdf_file.h"
#include "seed_listing.h"

namespace translucent::bssrdf {
namespace {

using ::testing::HasSubstr;
using translucent::testing::kSeedListingA2;
using translucent::testing::kSeedListingA2Glsl;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string join(const std::vector<std::string>& ls) {
  std::string s;
  for (const auto& l : ls) s += l + "\n";
  return s;
}

// The valid listing with line `n` (1-based) replaced; an empty optional deletes it.
std::string replaceLine(int n, const std::optional<std::string>& with) {
  auto ls = lines(kSeedListingA2Glsl);
  if (with) ls[static_cast<size_t>(n - 1)] = *with;
  else ls.erase(ls.begin() + (n - 1));
  return join(ls);
}

std::string insertBefore(int n, const std::string& text) {
  auto ls = lines(kSeedListingA2Glsl);
  ls.insert(ls.begin() + (n - 1), text);
  return join(ls);
}

struct Failure {
  int line = -1;
  std::string what;
};

Failure parseError(const std::string& text) {
  try {
    parseBssrdf(text, "models/test.bssrdf");
  } catch (const BssrdfFileError& e) {
    EXPECT_EQ(e.path(), "models/test.bssrdf");
    return {e.line(), e.what()};
  }
  return {-1, "(parsed without error)"};
}

TEST(BssrdfFile, SeedListingA2ParsesVerbatim) {
  const BssrdfFile f = parseBssrdf(kSeedListingA2, "dipole.bssrdf");
  EXPECT_TRUE(f.attributes.analytic);
  EXPECT_TRUE(f.attributes.radial);
  EXPECT_TRUE(f.attributes.no_wi);
  EXPECT_TRUE(f.attributes.no_wo);

  ASSERT_EQ(f.parameters.size(), 1u);
  const BssrdfParameter& m = f.parameters[0];
  EXPECT_EQ(m.name, "Multiplier");
  EXPECT_EQ(m.line, 3);
  const auto* spec = std::get_if<FloatParameter>(&m.spec);
  ASSERT_NE(spec, nullptr);
  EXPECT_EQ(spec->min, 0.0);
  EXPECT_EQ(spec->max, 10.0);
  EXPECT_EQ(spec->value, 1.0);
  EXPECT_EQ(f.findParameter("Multiplier"), &f.parameters[0]);
  EXPECT_EQ(f.findParameter("multiplier"), nullptr);
  EXPECT_EQ(f.parameters_line, 2);

  // Each GLSL section starts on the line after its ::begin, and holds exactly its lines.
  ASSERT_TRUE(f.initializer.has_value());
  EXPECT_EQ(f.initializer->first_line, 6);
  EXPECT_EQ(lines(f.initializer->code).size(), 13u);  // lines 6-18
  EXPECT_EQ(lines(f.initializer->code).front(), "vec3 Lu;");
  ASSERT_TRUE(f.diffuse_reflectance.has_value());
  EXPECT_EQ(f.diffuse_reflectance->first_line, 21);
  EXPECT_EQ(lines(f.diffuse_reflectance->code).size(), 4u);  // lines 21-24
  EXPECT_EQ(f.shader.first_line, 27);
  const auto shaderLines = lines(f.shader.code);
  ASSERT_EQ(shaderLines.size(), 12u);  // lines 27-38
  EXPECT_EQ(shaderLines.front(), "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {");
  EXPECT_EQ(shaderLines.back(), "}");
  EXPECT_TRUE(f.ignored_sections.empty());
  EXPECT_EQ(f.stem(), "dipole");
}

TEST(BssrdfFile, SectionsInAnyOrderUnknownSectionsIgnoredCommentsAndCrLf) {
  const std::string text =
      "analytic radial\r\n"
      "// a comment outside sections\r\n"
      "::begin shader\r\n"
      "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return Tint * float(Enabled); }\r\n"
      "::end\r\n"
      "\r\n"
      "::begin notes\r\n"
      "anything at all, even float x y z\r\n"
      "::end notes\r\n"
      "::begin parameters\r\n"
      "// parameters may be commented\r\n"
      "bool Enabled true\r\n"
      "color Tint 1 0.5 0.25\r\n"
      "float Width -1e-3 +2.5e1 0\r\n"
      "::end parameters\r\n";
  const BssrdfFile f = parseBssrdf(text, "x.bssrdf");
  EXPECT_TRUE(f.attributes.analytic);
  EXPECT_TRUE(f.attributes.radial);
  EXPECT_FALSE(f.attributes.no_wi);
  EXPECT_FALSE(f.attributes.no_wo);
  EXPECT_EQ(f.shader.first_line, 4);
  EXPECT_EQ(f.shader.code.find('\r'), std::string::npos);
  EXPECT_FALSE(f.initializer.has_value());
  EXPECT_FALSE(f.diffuse_reflectance.has_value());
  EXPECT_EQ(f.ignored_sections, std::vector<std::string>{"notes"});
  ASSERT_EQ(f.parameters.size(), 3u);
  EXPECT_EQ(std::get<BoolParameter>(f.parameters[0].spec).value, true);
  EXPECT_EQ(f.parameters[0].line, 12);
  EXPECT_EQ(std::get<ColorParameter>(f.parameters[1].spec).value, (Rgb{1.0, 0.5, 0.25}));
  const auto& w = std::get<FloatParameter>(f.parameters[2].spec);
  EXPECT_EQ(w.min, -1e-3);
  EXPECT_EQ(w.max, 25.0);
  EXPECT_EQ(w.value, 0.0);
}

struct Variant {
  const char* name;
  std::string text;
  int line;              // expected error line (0: the whole file)
  const char* expected;  // part of the message saying what was expected
};

TEST(BssrdfFile, EachMalformedVariantIsReportedAtItsLine) {
  const std::vector<Variant> variants = {
      {"unknown attribute", replaceLine(1, "analytic radial shiny"), 1,
       "unknown attribute 'shiny': expected analytic, radial, no_wi or no_wo"},
      {"missing analytic", replaceLine(1, "radial no_wi no_wo"), 1,
       "missing attribute 'analytic'"},
      {"empty attribute line", replaceLine(1, ""), 1, "expected the attribute list"},
      {"no attribute line", replaceLine(1, std::nullopt), 1, "expected the attribute list"},
      {"too few parameter fields", replaceLine(3, "float Multiplier 0.0 10.0"), 3,
       "expected 'float NAME MIN MAX DEFAULT' (5 fields, found 4)"},
      {"non-numeric value", replaceLine(3, "float Multiplier 0.0 ten 1.0"), 3,
       "maximum 'ten' is not a finite number"},
      {"unknown parameter type", replaceLine(3, "int Multiplier 0 10 1"), 3,
       "unknown type 'int', expected float, bool or color"},
      {"bad bool", replaceLine(3, "bool Multiplier maybe"), 3,
       "default 'maybe' is not a boolean (expected true, false, 1 or 0)"},
      {"short color", replaceLine(3, "color Multiplier 1 0.5"), 3,
       "expected 'color NAME R G B'"},
      {"default out of range", replaceLine(3, "float Multiplier 0.0 10.0 11.0"), 3,
       "default 11 is outside [0, 10]"},
      {"min above max", replaceLine(3, "float Multiplier 10.0 0.0 1.0"), 3,
       "minimum 10 is larger than maximum 0"},
      {"invalid name", replaceLine(3, "float 2x 0 1 0"), 3, "is not a valid GLSL identifier"},
      {"reserved name", replaceLine(3, "float IOR 1 2 1.3"), 3, "'IOR' is reserved"},
      {"duplicate parameter", insertBefore(4, "bool Multiplier true"), 4,
       "duplicate parameter 'Multiplier' (first declared at line 3)"},
      {"unterminated at end of file", replaceLine(39, std::nullopt), 26,
       "unterminated section 'shader': expected '::end shader' before the end of the file"},
      {"unterminated before next section", replaceLine(19, std::nullopt), 5,
       "unterminated section 'initializer': expected '::end initializer' before '::begin "
       "diffuseReflectance' at line 19"},
      {"duplicate section", insertBefore(20, "::begin initializer\n::end initializer"), 20,
       "duplicate section 'initializer' (first begun at line 5)"},
      {"mismatched end", replaceLine(25, "::end shader"), 25,
       "'::end shader' does not close the open section: expected '::end diffuseReflectance'"},
      {"end without begin", insertBefore(5, "::end parameters"), 5,
       "without a matching '::begin'"},
      {"text outside sections", insertBefore(5, "vec3 stray;"), 5,
       "text outside a section: expected '::begin NAME'"},
      {"marker without name", replaceLine(26, "::begin"), 26, "expected '::begin NAME'"},
      {"malformed marker", replaceLine(26, "::start shader"), 26,
       "expected '::begin NAME' or '::end NAME'"},
      {"missing shader section", [] {
         auto ls = lines(kSeedListingA2Glsl);
         ls.erase(ls.begin() + 25, ls.end());  // drop lines 26-39
         return join(ls);
       }(),
       0, "missing section 'shader'"},
      {"empty file", "", 0, "empty file"},
  };
  for (const Variant& v : variants) {
    const Failure f = parseError(v.text);
    EXPECT_EQ(f.line, v.line) << v.name << ": " << f.what;
    EXPECT_THAT(f.what, HasSubstr(v.expected)) << v.name;
    // The message starts with the file and the line, compiler style.
    const std::string prefix =
        v.line > 0 ? "models/test.bssrdf:" + std::to_string(v.line) + ": error: "
                   : std::string("models/test.bssrdf: error: ");
    EXPECT_EQ(f.what.rfind(prefix, 0), 0u) << v.name << ": " << f.what;
  }
}

TEST(BssrdfFile, MissingFileIsAClearError) {
  try {
    loadBssrdf("/nonexistent/dir/model.bssrdf");
    FAIL() << "no error";
  } catch (const BssrdfFileError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("/nonexistent/dir/model.bssrdf"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("cannot open"));
    EXPECT_EQ(e.line(), 0);
  }
}

// How model entries are told apart, and which line of a multi-line driver log is shown.
TEST(BssrdfFile, ExtensionAndFirstBssrdfLine) {
  EXPECT_TRUE(hasBssrdfExtension("my.bssrdf"));
  EXPECT_TRUE(hasBssrdfExtension("/a/b/Skin.BSSRDF"));
  EXPECT_FALSE(hasBssrdfExtension(".bssrdf"));  // a name is needed
  EXPECT_FALSE(hasBssrdfExtension("dipole"));
  EXPECT_FALSE(hasBssrdfExtension("my.bssrdf.txt"));
  EXPECT_EQ(firstBssrdfLine("linking failed\r\nwax.bssrdf:12: 'x' undeclared\nother.bssrdf:3: y"),
            "wax.bssrdf:12: 'x' undeclared");
  EXPECT_EQ(firstBssrdfLine("no file named here"), "no file named here");
}

}  // namespace
}  // namespace translucent::bssrdf
