#include "reference_cache.h"

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace rtm {
namespace fs = std::filesystem;
namespace {

uint64_t fnv1a(const std::string& s, uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

fs::path cache_dir() {
  if (const char* d = std::getenv("RTM_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "rtm";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache" / "rtm";
  return {};
}

constexpr char kMagic[8] = {'r', 't', 'm', 'r', 'e', 'f', '0', '1'};

template <class T>
void put(std::ostream& o, const T& v) {
  o.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <class T>
bool get(std::istream& i, T& v) {
  return bool(i.read(reinterpret_cast<char*>(&v), sizeof(T)));
}

bool load(const fs::path& p, const Scene& s, ReferenceResult& r) {
  std::ifstream f(p, std::ios::binary);
  char magic[8];
  if (!f || !f.read(magic, 8) || std::memcmp(magic, kMagic, 8) != 0) return false;
  int w = 0, h = 0;
  if (!get(f, w) || !get(f, h) || w != s.camera.width || h != s.camera.height) return false;
  r.image = Image(w, h);
  if (!f.read(reinterpret_cast<char*>(r.image.rgb.data()), std::streamsize(r.image.rgb.size() * sizeof(Vec3))) ||
      !f.read(reinterpret_cast<char*>(r.image.ids.data()), std::streamsize(r.image.ids.size() * sizeof(int32_t))))
    return false;
  return get(f, r.counts) && get(f, r.wall_seconds);
}

void store(const fs::path& p, const ReferenceResult& r) {
  std::error_code ec;
  fs::create_directories(p.parent_path(), ec);
  const fs::path tmp = p.string() + ".partial-" + std::to_string(getpid());
  {
    std::ofstream f(tmp, std::ios::binary);
    f.write(kMagic, 8);
    put(f, r.image.width);
    put(f, r.image.height);
    f.write(reinterpret_cast<const char*>(r.image.rgb.data()), std::streamsize(r.image.rgb.size() * sizeof(Vec3)));
    f.write(reinterpret_cast<const char*>(r.image.ids.data()), std::streamsize(r.image.ids.size() * sizeof(int32_t)));
    put(f, r.counts);
    put(f, r.wall_seconds);
    if (!f) {
      fs::remove(tmp, ec);
      return;  // a cache that cannot be written is only slower
    }
  }
  fs::rename(tmp, p, ec);
  if (ec) fs::remove(tmp, ec);
}

}  // namespace

ReferenceResult cached_reference(const Scene& s, const Grid& g, const std::string& scene_text, bool* hit) {
  std::ostringstream key;
  key.precision(17);
  key << scene_text << "|" << s.camera.width << "x" << s.camera.height << "|grid " << g.n[0] << "," << g.n[1] << ","
      << g.n[2] << "|t " << s.threshold << "|d " << s.max_depth << "|o " << s.spawn_offset << " " << to_string(s.spawn_policy) << "|" << __DATE__ << " "
      << __TIME__ << "|" << reference_build_id();
  key << "|refs " << fnv1a(std::string(reinterpret_cast<const char*>(g.items.data()), g.items.size() * sizeof(uint32_t)))
      << " " << fnv1a(std::string(reinterpret_cast<const char*>(g.start.data()), g.start.size() * sizeof(uint32_t)));
  const fs::path dir = cache_dir();
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.ref", (unsigned long long)fnv1a(key.str()));
  ReferenceResult r;
  if (!dir.empty() && load(dir / name, s, r)) {
    if (hit) *hit = true;
    return r;
  }
  if (hit) *hit = false;
  r = render_reference(s, g, 0);
  if (!dir.empty()) store(dir / name, r);
  return r;
}

}  // namespace rtm
