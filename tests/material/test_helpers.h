// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the material tests: a temporary folder, media, and a scene text around a material.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "translucent/material/material.h"
#include "translucent/material/medium_desc.h"

namespace translucent::material::testing {

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            (std::string("translucent-material-") + info->test_suite_name() + "-" + info->name() +
             "-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name, std::ios::binary) << text;
    return path_ / name;
  }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline MediumDesc mediumA() { return mediumDesc({0.01, 0.02, 0.03}, {1.0, 1.5, 2.0}, 0.0); }
inline MediumDesc mediumB() { return mediumDesc({0.5, 0.4, 0.3}, {5.0, 4.0, 3.0}, 0.5); }
inline MediumDesc mediumC() { return mediumDesc({0.1, 0.1, 0.1}, {0.2, 8.0, 0.5}, -0.2); }

}  // namespace translucent::material::testing
