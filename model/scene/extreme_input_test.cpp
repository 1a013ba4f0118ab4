// Case 11 of docs/numerics.md: non-finite and overflowing input is rejected with a message that
// names the file, the line and what is wrong, in both scene formats and in scenes built in code.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene/scene.h"

namespace rtm {
namespace {

struct Bad {
  std::string text;
  int line;
  std::string says;  ///< a part of the message
};

void expect_rejected(const Bad& b, bool nff) {
  SCOPED_TRACE(b.text);
  try {
    if (nff)
      parse_nff(b.text, "x.nff");
    else
      parse_native(b.text, "x.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), b.line) << e.what();
    EXPECT_NE(std::string(e.what()).find(b.says), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(
                  std::string(nff ? "x.nff:" : "x.yaml:") + std::to_string(b.line) + ":", 0),
              0u)
        << e.what();
  }
}

const std::string kCam = "camera: {eye: [0, 0, 10], look_at: [0, 0, 0]}\n";
const std::string kMat = "materials: {m: {}}\n";

TEST(ExtremeInput, NativeNonFiniteAndOverflowingNumbers) {
  const std::vector<Bad> cases = {
      {"camera: {eye: [.nan, 0, 10], look_at: [0, 0, 0]}\nprimitives: []\n", 1, "not finite"},
      {"camera: {eye: [0, 0, 10], look_at: [0, -.inf, 0]}\nprimitives: []\n", 1, "not finite"},
      {"camera: {eye: [0, 0, 1e400], look_at: [0, 0, 0]}\nprimitives: []\n", 1, "out of range"},
      {"camera: {eye: [0, 0, 10], look_at: [0, 0, 0], up: [0, nan, 0]}\nprimitives: []\n", 1,
       "not finite"},
      // Finite, but squared distances would overflow a double.
      {"camera: {eye: [0, 0, 1e200], look_at: [0, 0, 0]}\nprimitives: []\n", 1, "within +-1e150"},
      {kCam + "lights:\n  - {position: [1, .inf, 1]}\nprimitives: []\n", 3, "not finite"},
      {kCam + "lights:\n  - {position: [1e200, 0, 0]}\nprimitives: []\n", 3, "within +-1e150"},
      {kCam + "lights:\n  - {position: [1, 1, 1], color: [1, .nan, 1]}\nprimitives: []\n", 3,
       "not finite"},
      {kCam + kMat + "primitives:\n  - {sphere: {center: [0, .nan, 0], radius: 1}, material: m}\n",
       4, "not finite"},
      {kCam + kMat + "primitives:\n  - {sphere: {center: [0, 0, 0], radius: .inf}, material: m}\n",
       4, "not finite"},
      {kCam + kMat + "primitives:\n  - {sphere: {center: [1e200, 0, 0], radius: 1}, material: m}\n",
       4, "too far"},
      {kCam + kMat +
           "primitives:\n  - {sphere: {center: [0, 0, 0], radius: 1e-200}, material: m}\n",
       4, "too small"},
      {kCam + kMat +
           "primitives:\n  - {quadric: {coefficients: [1, 1, 1, 0, 0, 0, 0, 0, .nan, -1], box: "
           "{min: [-1, -1, -1], max: [1, 1, 1]}}, material: m}\n",
       4, "not finite"},
      {kCam + kMat +
           "primitives:\n  - {quadric: {coefficients: [1e400, 1, 1, 0, 0, 0, 0, 0, 0, -1], box: "
           "{min: [-1, -1, -1], max: [1, 1, 1]}}, material: m}\n",
       4, "out of range"},
      {kCam + kMat +
           "primitives:\n  - {plane: {normal: [0, 1, 0], box: {min: [-1e200, -1, -1], max: [1, 1, "
           "1]}}, material: m}\n",
       4, "too far"},
      {kCam + kMat +
           "primitives:\n  - {ellipsoid: {center: [0, 0, 0], radii: [1e300, 1, 1]}, material: m}\n",
       4, "finite"},
      {kCam + kMat +
           "primitives:\n  - {cone: {base: [0, 0, 0], base_radius: .nan, apex: [0, 0, 1], "
           "apex_radius: 0}, material: m}\n",
       4, "not finite"},
      {kCam + "render: {spawn_offset: .nan}\nprimitives: []\n", 2, "not finite"},
      {kCam + "render: {spawn_policy: exact}\nprimitives: []\n", 2, "relative or bound"},
  };
  for (const Bad& b : cases) expect_rejected(b, false);
}

TEST(ExtremeInput, NffNonFiniteAndOverflowingNumbers) {
  const std::string view =
      "v\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n";
  const std::string f = "f 1 1 1 0.5 0.5 0 0 1\n";
  const std::vector<Bad> cases = {
      {"v\nfrom nan 0 10\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n", 2, "not"},
      {view + "l 1 inf 1\n", 8, "not"},
      {view + "l 1e200 0 0\n", 8, "within +-1e150"},
      {view + f + "s 0 0 0 1e400\n", 9, "out of range"},
      {view + f + "s 1e200 0 0 1\n", 9, "too far"},
      {view + f + "p 3\n0 0 0\n1 nan 0\n0 1 0\n", 11, "not"},
  };
  for (const Bad& b : cases) expect_rejected(b, true);
}

TEST(ExtremeInput, ScenesBuiltInCodeAreCheckedToo) {
  Scene s =
      parse_native(kCam + kMat + "lights: [{position: [1, 2, 3]}]\nprimitives: []\n", "x.yaml");
  ASSERT_NO_THROW(validate(s));
  s.lights[0].position = {0, 1e160, 0};
  EXPECT_THROW(validate(s), std::invalid_argument);
  s.lights[0].position = {0, 1, 0};
  s.camera.eye = {-1e160, 0, 0};
  EXPECT_THROW(validate(s), std::invalid_argument);
  EXPECT_THROW(make_sphere({0, 0, 0}, 1e-170), std::invalid_argument);
  EXPECT_NO_THROW(make_sphere({0, 0, 0}, 1e-150));
  EXPECT_THROW(make_sphere({0, 1e151, 0}, 1), std::invalid_argument);
  EXPECT_NO_THROW(make_sphere({0, 1e149, 0}, 1));
}

}  // namespace
}  // namespace rtm
