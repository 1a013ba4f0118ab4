// The boundary between rtm and its image library (model/oiio/, built as librtm_image.so).
//
// OpenImageIO on Debian pulls in some 250 shared libraries (FFmpeg, GDAL, OpenCV, ...) whose
// symbol binding costs ~0.2 s of every process start. Kept behind dlopen, only processes that
// read or write images pay it, and a render pays it on a second thread while it traces.
#pragma once

#include <cstdint>
#include <string>

#include "render/image_io.h"

namespace rtm {

/// Raised whenever ImageLibrary changes: a library left from another build of rtm (beside a copied
/// program, say) is refused by name instead of called through pointers it does not have.
inline constexpr uint64_t kImageLibraryInterface = 2;

struct ImageLibrary {
  uint64_t interface;  ///< kImageLibraryInterface of the build that made the library
  void (*write_image)(const std::string& path, const Image& img);
  void (*write_id_map)(const std::string& path, const Image& img);
  Image (*read_image)(const std::string& path);
  Image (*read_id_map)(const std::string& path);
  ImageError (*compare_images)(const Image& img, const Image& ref);
  void (*write_channels)(const std::string& path, const Channels& c);
  Channels (*read_channels)(const std::string& path);
};

/// The one symbol the library exports (C linkage, so dlsym finds it by this name).
inline constexpr const char* kImageLibrarySymbol = "rtm_image_library";
inline constexpr const char* kImageLibraryFile = "librtm_image.so";

}  // namespace rtm
