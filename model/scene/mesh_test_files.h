// What the mesh tests share: a folder of their own for the files they write, and a small OBJ.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace rtm::test {

/// A test whose files go into a folder of its own (named after the test and the process), removed
/// after it.
class MeshFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rtm-mesh-" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
            std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::filesystem::path dir_;
};

/// A unit square in z = 0 as two triangles, and one more triangle behind it.
inline const std::string kObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 -1\nv 1 0 -1\nv 0 1 -1\n"
    "f 1 2 3 4\n"
    "f 5 6 7\n";

}  // namespace rtm::test
