// image_io.h's image functions forward to the image library (render/image_library.h), loaded
// once: on first use, or ahead of it on a thread of its own by preload_image_library.
#include "render/image_io.h"

#include <dlfcn.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "render/atomic_file.h"
#include "render/image_library.h"
#include "render/partial_files.h"

namespace rtm {
namespace {

/// $RTM_IMAGE_LIBRARY if set; else beside the running program (rtm and the test programs are
/// built into one directory); else where the build put it.
std::string library_path() {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (const char* set = std::getenv("RTM_IMAGE_LIBRARY")) {
    if (!fs::exists(set, ec))
      throw std::runtime_error(std::string("RTM_IMAGE_LIBRARY: no such file: ") + set);
    return set;
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path beside = ec ? fs::path() : exe.parent_path() / kImageLibraryFile;
  if (!beside.empty() && fs::exists(beside, ec)) return beside.string();
  if (fs::exists(RTM_IMAGE_LIBRARY, ec)) return RTM_IMAGE_LIBRARY;
  throw std::runtime_error(
      std::string("cannot find rtm's image library ") + kImageLibraryFile + ": it belongs beside " +
      (exe.empty() ? std::string("the rtm program") : exe.string()) + " (the build puts it at " +
      RTM_IMAGE_LIBRARY + "; RTM_IMAGE_LIBRARY=FILE names another place)");
}

const ImageLibrary* load(const std::string& path) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw std::runtime_error(std::string("cannot load the image library: ") + dlerror());
  using Entry = const ImageLibrary* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, kImageLibrarySymbol));
  if (!entry)
    throw std::runtime_error(path + ": not rtm's image library (it has no " + kImageLibrarySymbol +
                             ")");
  const ImageLibrary* library = entry();
  // An older library's first member is a function pointer, never a small number.
  if (library->interface != kImageLibraryInterface)
    throw std::runtime_error(path + ": an image library from another build of rtm: use the " +
                             kImageLibraryFile +
                             " built with this rtm (or name it with RTM_IMAGE_LIBRARY=FILE)");
  return library;
}

std::once_flag load_started;
std::shared_future<const ImageLibrary*> loaded;

/// Finding the library is immediate, so a missing one is reported before any work is done.
void start_loading() {
  std::call_once(load_started,
                 [] { loaded = std::async(std::launch::async, load, library_path()).share(); });
}

const ImageLibrary& library() {
  start_loading();
  return *loaded.get();
}

}  // namespace

void preload_image_library() { start_loading(); }
void finish_loading_image_library() {
  if (loaded.valid()) loaded.wait();
}

// The library writes through commit_atomically's temporary: registered here, where a signal
// handler can see it (the library is a module of its own).
void write_image(const std::string& path, const Image& img) {
  const PartialFile tmp(temporary_beside(path));
  library().write_image(path, img);
}
void write_id_map(const std::string& path, const Image& img) {
  const PartialFile tmp(temporary_beside(path));
  library().write_id_map(path, img);
}
void write_channels(const std::string& path, const Channels& c) {
  const PartialFile tmp(temporary_beside(path));
  library().write_channels(path, c);
}
Channels read_channels(const std::string& path) { return library().read_channels(path); }
Image read_image(const std::string& path) { return library().read_image(path); }
Image read_id_map(const std::string& path) { return library().read_id_map(path); }
namespace {

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

/// Throws NonFiniteImage naming `which` if some channel of `im` is NaN or infinite.
void require_finite(const Image& im, const char* which) {
  uint64_t bad = 0;
  size_t first = 0;
  for (size_t i = 0; i < im.rgb.size(); ++i) {
    const Vec3& v = im.rgb[i];
    if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) continue;
    if (bad++ == 0) first = i;
  }
  if (bad == 0) return;
  const Vec3& v = im.rgb[first];
  throw NonFiniteImage(
      std::string(which) + " has " + std::to_string(bad) + " pixel" + (bad == 1 ? "" : "s") +
      " with a NaN or infinite value (the first at x " + std::to_string(first % size_t(im.width)) +
      ", y " + std::to_string(first / size_t(im.width)) + ": " + number(v.x) + ", " + number(v.y) +
      ", " + number(v.z) + "), so no error figure would mean anything");
}

}  // namespace

ImageError compare_images(const Image& img, const Image& ref) {
  if (img.width != ref.width || img.height != ref.height)
    throw std::invalid_argument("images differ in size");
  require_finite(img, "the image");
  require_finite(ref, "the reference image");
  ImageError e = library().compare_images(img, ref);
  for (size_t i = 0; i < img.ids.size() && i < ref.ids.size(); ++i)
    e.primary_ids_differing += img.ids[i] != ref.ids[i];
  // Finite values can still square past the largest double.
  if (!std::isfinite(e.rmse) || !std::isfinite(e.max_abs) || std::isnan(e.psnr_db))
    throw NonFiniteImage("the error figures overflow (rmse " + number(e.rmse) + ", max_abs " +
                         number(e.max_abs) + "): the images hold values too large to compare");
  return e;
}

void write_text_atomically(const std::string& path, const std::string& text) {
  const PartialFile partial(temporary_beside(path));
  commit_atomically(path, [&](const std::string& tmp) {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    f.close();
    if (!f) throw std::runtime_error(path + ": cannot write");
  });
}

}  // namespace rtm
