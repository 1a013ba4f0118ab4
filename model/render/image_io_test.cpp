// The image functions and the loading of the library behind them.
#include "render/image_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace rtm {
namespace {

bool open_image_io_mapped() {
  std::ifstream maps("/proc/self/maps");
  std::stringstream text;
  text << maps.rdbuf();
  return text.str().find("libOpenImageIO") != std::string::npos;
}

// Each test is a process of its own (gtest_discover_tests), so nothing has loaded it before.
TEST(ImageIo, OpenImageIOIsLoadedOnlyWhenImagesAreUsed) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rtm_image_io_test_" + std::to_string(getpid()));
  EXPECT_FALSE(open_image_io_mapped());
  write_text_atomically((dir / "stats.json").string(), "{}");
  EXPECT_FALSE(open_image_io_mapped());

  Image img(3, 2);
  img.rgb[4] = Vec3(0.25, -1.5, 7.0);
  img.ids[4] = 41;
  write_image((dir / "rgb.exr").string(), img);
  write_id_map((dir / "ids.exr").string(), img);
  EXPECT_TRUE(open_image_io_mapped());

  const Image rgb = read_image((dir / "rgb.exr").string());
  const Image ids = read_id_map((dir / "ids.exr").string());
  std::filesystem::remove_all(dir);
  ASSERT_EQ(rgb.width, 3);
  ASSERT_EQ(rgb.height, 2);
  EXPECT_EQ(rgb.rgb[4], Vec3(0.25, -1.5, 7.0));  // EXR keeps float values, unclamped
  EXPECT_EQ(ids.ids[4], 41);
  EXPECT_EQ(ids.ids[0], -1);
}

TEST(ImageIo, PreloadingIsIdempotentAndErrorsStillReachTheCaller) {
  preload_image_library();
  preload_image_library();
  EXPECT_THROW(read_image("/nonexistent/rtm/image.png"), std::runtime_error);
  EXPECT_THROW(write_image("/tmp/rtm_image_io_test.bmp", Image(1, 1)), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists("/tmp/rtm_image_io_test.bmp"));
}

}  // namespace
}  // namespace rtm
