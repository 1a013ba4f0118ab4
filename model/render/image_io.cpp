// image_io.h's image functions forward to the image library (render/image_library.h), loaded
// once: on first use, or ahead of it on a thread of its own by preload_image_library.
#include "render/image_io.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <stdexcept>

#include "render/atomic_file.h"
#include "render/image_library.h"

namespace rtm {
namespace {

/// $RTM_IMAGE_LIBRARY if set; else beside the running program (rtm and the test programs are
/// built into one directory); else where the build put it.
std::string library_path() {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (const char* set = std::getenv("RTM_IMAGE_LIBRARY")) {
    if (!fs::exists(set, ec)) throw std::runtime_error(std::string("RTM_IMAGE_LIBRARY: no such file: ") + set);
    return set;
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path beside = ec ? fs::path() : exe.parent_path() / kImageLibraryFile;
  if (!beside.empty() && fs::exists(beside, ec)) return beside.string();
  if (fs::exists(RTM_IMAGE_LIBRARY, ec)) return RTM_IMAGE_LIBRARY;
  throw std::runtime_error(std::string("cannot find rtm's image library ") + kImageLibraryFile + ": it belongs beside " +
                           (exe.empty() ? std::string("the rtm program") : exe.string()) + " (the build puts it at " +
                           RTM_IMAGE_LIBRARY + "; RTM_IMAGE_LIBRARY=FILE names another place)");
}

const ImageLibrary* load(const std::string& path) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw std::runtime_error(std::string("cannot load the image library: ") + dlerror());
  using Entry = const ImageLibrary* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, kImageLibrarySymbol));
  if (!entry) throw std::runtime_error(path + ": not rtm's image library (it has no " + kImageLibrarySymbol + ")");
  return entry();
}

std::once_flag load_started;
std::shared_future<const ImageLibrary*> loaded;  // waited for at exit if still loading

/// Finding the library is immediate, so a missing one is reported before any work is done.
void start_loading() {
  std::call_once(load_started, [] { loaded = std::async(std::launch::async, load, library_path()).share(); });
}

const ImageLibrary& library() {
  start_loading();
  return *loaded.get();
}

}  // namespace

void preload_image_library() { start_loading(); }

void write_image(const std::string& path, const Image& img) { library().write_image(path, img); }
void write_id_map(const std::string& path, const Image& img) { library().write_id_map(path, img); }
Image read_image(const std::string& path) { return library().read_image(path); }
Image read_id_map(const std::string& path) { return library().read_id_map(path); }
ImageError compare_images(const Image& img, const Image& ref) { return library().compare_images(img, ref); }

void write_text_atomically(const std::string& path, const std::string& text) {
  commit_atomically(path, [&](const std::string& tmp) {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    f.close();
    if (!f) throw std::runtime_error(path + ": cannot write");
  });
}

}  // namespace rtm
