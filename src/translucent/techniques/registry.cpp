// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/registry.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "translucent/techniques/empirical/empirical_technique.h"
#include "translucent/techniques/lss/lss_technique.h"
#include "translucent/techniques/pointcloud/pointcloud_technique.h"
#include "translucent/techniques/splatting/splatting_technique.h"
#include "translucent/techniques/tsis/tsis_technique.h"
#include "translucent/techniques/transfer/transfer_technique.h"
#include "translucent/techniques/tsm/tsm_technique.h"

namespace translucent::techniques {
namespace {

struct Entry {
  const char* name;
  const char* description;
  std::unique_ptr<Technique> (*create)();
};

// One line per technique.
constexpr Entry kTechniques[] = {
    {"pointcloud", "hierarchical point-cloud BSSRDF evaluation (Jensen & Buhler 2002; Bitterli 2013, §2.6.4, §3.3)",
     &pointcloud::makePointCloudTechnique},
    {"empirical", "empirical translucency shader: depth-peeled thickness, per-vertex AO (Gascons 2011, chapter 3)",
     &empirical::makeEmpiricalTechnique},
    {"tsis", "texture-space importance sampling of the irradiance over a surface atlas (Chang 2007, chapter 3)",
     &tsis::makeTsisTechnique},
    {"tsm", "translucent shadow maps: a 21-sample filter of light-view irradiance maps (Dachsbacher & Stamminger 2003)",
     &tsm::makeTsmTechnique},
    {"lss", "local subsurface scattering: per-pixel importance sampling of Rd on the image plane (Mertens et al. 2003)",
     &lss::makeLssTechnique},
    {"splatting", "multiresolution splatting of adaptively selected light-view irradiance samples (Chen, Peers, Zhang & Tong 2012)",
     &splatting::makeSplattingTechnique},
    {"shah", "image-space splatting of every irradiance texel with full-size splats (Shah, Kontinen & Pattanaik 2009)",
     &splatting::makeShahTechnique},
    {"transfer", "precomputed subsurface transfer of a static mesh, path-traced once (in the spirit of Wang et al. 2005 and Hašan et al. 2006)",
     &transfer::makeTransferTechnique},
};

const Entry& find(std::string_view name) {
  for (const Entry& e : kTechniques)
    if (name == e.name) return e;
  throw UnknownTechniqueError(fmt::format("unknown technique '{}': valid techniques are {}", name,
                                          fmt::join(names(), ", ")));
}

}  // namespace

std::unique_ptr<Technique> make(std::string_view name) { return find(name).create(); }

std::vector<std::string> names() {
  std::vector<std::string> out;
  for (const Entry& e : kTechniques) out.emplace_back(e.name);
  return out;
}

std::string description(std::string_view name) { return find(name).description; }

}  // namespace translucent::techniques
