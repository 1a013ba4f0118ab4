// Everything rtm does with image files, through OpenImageIO; built as librtm_image.so and loaded
// on demand (render/image_library.h says why).
#include "render/image_library.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "render/atomic_file.h"
#include "render/image_formats.h"

namespace rtm::oiio {

/// names: the channels' names; empty, the format's own (R, G, B; Y).
void write_pixels(const std::string& final_path, const std::string& tmp, int w, int h, int channels,
                  OIIO::TypeDesc type, const void* data,
                  const std::vector<std::string>& names = {}) {
  auto out = OIIO::ImageOutput::create(final_path);
  if (!out)
    throw std::runtime_error(final_path + ": cannot write this image format: " + OIIO::geterror());
  OIIO::ImageSpec spec(w, h, channels, type);
  if (!names.empty()) spec.channelnames = names;
  if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, data) || !out->close())
    throw std::runtime_error(final_path + ": cannot write: " + out->geterror());
}

void write_image(const std::string& path, const Image& img) {
  if (!is_image_path(path)) throw std::runtime_error(path + ": output must be .png or .exr");
  const bool png = image_extension(path) == ".png";
  std::vector<float> px(img.rgb.size() * 3);
  for (size_t i = 0; i < img.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double v = img.rgb[i][c];
      px[i * 3 + size_t(c)] = float(png ? std::clamp(v, 0.0, 1.0) : v);
    }
  commit_atomically(path, [&](const std::string& tmp) {
    write_pixels(path, tmp, img.width, img.height, 3,
                 png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT, px.data());
  });
}

void write_id_map(const std::string& path, const Image& img) {
  if (!is_exr_path(path)) throw std::runtime_error(path + ": the ID map must be an .exr file");
  std::vector<float> px(img.ids.begin(), img.ids.end());
  commit_atomically(path, [&](const std::string& tmp) {
    write_pixels(path, tmp, img.width, img.height, 1, OIIO::TypeDesc::FLOAT, px.data());
  });
}

void write_channels(const std::string& path, const Channels& c) {
  if (!is_exr_path(path)) throw std::runtime_error(path + ": must be an .exr file");
  if (c.values.size() != size_t(c.width) * size_t(c.height) * c.names.size())
    throw std::invalid_argument(path + ": the channels' values do not fill the image");
  commit_atomically(path, [&](const std::string& tmp) {
    write_pixels(path, tmp, c.width, c.height, int(c.names.size()), OIIO::TypeDesc::FLOAT,
                 c.values.data(), c.names);
  });
}

OIIO::ImageBuf read_buf(const std::string& path) {
  OIIO::ImageBuf buf(path);
  if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT))
    throw std::runtime_error(path + ": cannot read image: " + buf.geterror());
  return buf;
}

Image read_image(const std::string& path) {
  OIIO::ImageBuf buf = read_buf(path);
  const OIIO::ImageSpec& spec = buf.spec();
  Image img(spec.width, spec.height);
  std::vector<float> px(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
  for (size_t i = 0; i < img.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c)
      img.rgb[i][c] = px[i * size_t(spec.nchannels) + size_t(std::min(c, spec.nchannels - 1))];
  return img;
}

Image read_id_map(const std::string& path) {
  OIIO::ImageBuf buf = read_buf(path);
  const OIIO::ImageSpec& spec = buf.spec();
  if (spec.nchannels != 1) throw std::runtime_error(path + ": an ID map has one channel");
  Image img(spec.width, spec.height);
  std::vector<float> px(size_t(spec.width) * size_t(spec.height));
  buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
  for (size_t i = 0; i < px.size(); ++i) img.ids[i] = int32_t(std::lround(px[i]));
  return img;
}

Channels read_channels(const std::string& path) {
  OIIO::ImageBuf buf = read_buf(path);
  const OIIO::ImageSpec& spec = buf.spec();
  Channels c;
  c.width = spec.width;
  c.height = spec.height;
  c.names = spec.channelnames;
  c.values.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, c.values.data());
  return c;
}

ImageError compare_images(const Image& img, const Image& ref) {
  if (img.width != ref.width || img.height != ref.height)
    throw std::invalid_argument("images differ in size");
  auto to_buf = [](const Image& im) {
    OIIO::ImageBuf b(OIIO::ImageSpec(im.width, im.height, 3, OIIO::TypeDesc::DOUBLE));
    b.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::DOUBLE, im.rgb.data());
    return b;
  };
  const OIIO::ImageBuf a = to_buf(img), b = to_buf(ref);
  // CompareResults::error only says some pixel exceeded the threshold; nfail counts those pixels.
  const auto r = OIIO::ImageBufAlgo::compare(a, b, float(1.0 / 255.0), float(1.0 / 255.0));
  if (a.has_error() || b.has_error())
    throw std::runtime_error("image comparison failed: " + a.geterror() + b.geterror());
  ImageError e;
  e.rmse = r.rms_error;
  e.psnr_db = r.rms_error > 0 ? 20 * std::log10(1.0 / r.rms_error)
                              : std::numeric_limits<double>::infinity();
  e.max_abs = r.maxerror;
  e.pixels_over_1_255 = r.nfail;
  return e;
}

}  // namespace rtm::oiio

extern "C" __attribute__((visibility("default"))) const rtm::ImageLibrary* rtm_image_library() {
  using namespace rtm::oiio;
  static const rtm::ImageLibrary library{rtm::kImageLibraryInterface,
                                         write_image,
                                         write_id_map,
                                         read_image,
                                         read_id_map,
                                         compare_images,
                                         write_channels,
                                         read_channels};
  return &library;
}
