// Image files through OpenImageIO, written atomically; image comparison. OpenImageIO is loaded
// on first use (render/image_library.h); errors loading it are thrown as std::runtime_error.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "render/reference.h"

namespace rtm {

/// .png: 8-bit, each channel clamped to [0, 1] then rounded to the nearest of 256 levels.
/// .exr: 32-bit float, linear, unclamped. Written to a temporary file and renamed, so a failed
/// write never leaves a partial image. Throws std::runtime_error naming the file.
void write_image(const std::string& path, const Image& img);
/// One-channel float EXR: per pixel the primitive number the primary ray hit, -1 for background.
void write_id_map(const std::string& path, const Image& img);
/// A float image of named channels, pixel by pixel (values[pixel * names.size() + channel]).
struct Channels {
  int width = 0, height = 0;
  std::vector<std::string> names;
  std::vector<float> values;
};
/// A float EXR with the channels' names, written as write_image writes.
void write_channels(const std::string& path, const Channels& c);
/// Reads any image as named float channels.
Channels read_channels(const std::string& path);
/// Reads an RGB image (any format OpenImageIO reads; alpha dropped, grey replicated).
Image read_image(const std::string& path);
/// Reads a one-channel ID map written by write_id_map.
Image read_id_map(const std::string& path);

/// Error of `img` against `ref` over all pixels and RGB channels (computed by OpenImageIO).
struct ImageError {
  double rmse = 0;
  double psnr_db = 0;  ///< 20 log10(1 / rmse); infinite for identical images
  double max_abs = 0;
  uint64_t pixels_over_1_255 = 0;  ///< pixels with some channel off by more than 1/255
  uint64_t primary_ids_differing =
      0;  ///< pixels whose primary ray hit another primitive (or the background)
};
/// An image with a NaN or infinite channel, or one whose error figures overflow: no figure would
/// mean anything (a NaN compares false with everything, so it once read as a perfect match).
struct NonFiniteImage : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// Throws NonFiniteImage if either image holds a value that is not finite, naming which image,
/// how many pixels and the first of them; std::invalid_argument if their sizes differ.
ImageError compare_images(const Image& img, const Image& ref);

/// Starts loading the image library on a thread of its own, so a program about to render does
/// not wait for it at the end; throws at once if the library is missing. Idempotent; the
/// functions above wait for the load to finish.
void preload_image_library();
/// Waits for a load preload_image_library started to finish, if one did. A program must not exit
/// while the library loads: exit() destroys the static objects of the libraries loaded so far
/// while the loading thread still constructs and uses them.
void finish_loading_image_library();

/// Writes text to path through a temporary file and a rename.
void write_text_atomically(const std::string& path, const std::string& text);

}  // namespace rtm
