// The image functions and the loading of the library behind them.
#include "render/image_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
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

// A NaN compares false with everything: "rms_error > 0" once read it as a perfect match (psnr inf,
// 0 pixels off). NaN or infinity in either image is an error naming the image and the pixel.
TEST(ImageIo, ANonFinitePixelInEitherImageIsAnErrorNotAPerfectMatch) {
  Image a(4, 3), b(4, 3);
  for (size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] = b.rgb[i] = Vec3(0.5, 0.25, 0.125);
  const ImageError same = compare_images(a, b);
  EXPECT_EQ(same.rmse, 0);
  EXPECT_EQ(same.pixels_over_1_255, 0u);
  auto message = [](const Image& x, const Image& y) {
    try {
      compare_images(x, y);
    } catch (const NonFiniteImage& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Image nan = a;
  nan.rgb[6].y = std::nan("");
  nan.rgb[9].x = std::nan("");
  EXPECT_EQ(message(nan, b),
            "the image has 2 pixels with a NaN or infinite value (the first at x 2, y 1: 0.5, nan, "
            "0.125), so no "
            "error figure would mean anything");
  Image inf = b;
  inf.rgb[11].z = -HUGE_VAL;
  EXPECT_EQ(
      message(a, inf).rfind(
          "the reference image has 1 pixel with a NaN or infinite value (the first at x 3, y 2", 0),
      0u)
      << message(a, inf);
  Image huge = a;
  huge.rgb[0] = Vec3(1e300, 1e300, 1e300);
  EXPECT_EQ(message(huge, b).rfind("the error figures overflow", 0), 0u) << message(huge, b);
}

}  // namespace
}  // namespace rtm
