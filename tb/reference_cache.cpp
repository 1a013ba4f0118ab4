#include "reference_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "byte_size.h"
#include "fnv1a.h"
#include "config/config.h"
#include "render/atomic_file.h"
#include "render/partial_files.h"

namespace rtm {
namespace fs = std::filesystem;
namespace {

/// The entry's checksum: FNV-1a over 64-bit words (eight times faster than over bytes on a
/// gigabyte entry), each step also folding high bits down, then the tail bytes.
uint64_t checksum(const char* p, size_t n) {
  uint64_t h = kFnvBasis;
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t w;
    std::memcpy(&w, p + i, 8);
    h = (h ^ w) * kFnvPrime;
    h ^= h >> 29;
  }
  for (; i < n; ++i) h = (h ^ uint8_t(p[i])) * kFnvPrime;
  return h;
}

/// The key's digest stored inside the entry: another basis than the file name's hash, so an entry
/// copied or renamed to another key's name, or a collision of names, is told apart.
uint64_t key_digest(const std::string& key) { return fnv1a(key, 0x9e3779b97f4a7c15ull); }

fs::path cache_dir() {
  if (const char* d = std::getenv("RTM_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "rtm";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache" / "rtm";
  return {};
}

/// Format 02: magic, the key's digest, width and height, the pixels, the ids, the counts, the
/// wall time, then the checksum of everything before it.
constexpr char kMagic[8] = {'r', 't', 'm', 'r', 'e', 'f', '0', '2'};
constexpr size_t kHeaderBytes = sizeof kMagic + sizeof(uint64_t) + 2 * sizeof(int32_t);

size_t entry_bytes(int w, int h) {
  return kHeaderBytes + size_t(w) * size_t(h) * (sizeof(Vec3) + sizeof(int32_t)) +
         sizeof(TraceCounts) + sizeof(double) + sizeof(uint64_t);
}

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <class T>
T take(const char*& p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  p += sizeof(T);
  return v;
}

bool is_entry(const fs::path& p) {
  return p.extension() == ".ref" && p.filename().string()[0] != '.';
}

/// Reads an entry; on any problem returns false with `why` saying what (empty: there is none).
bool load(const fs::path& p, const Scene& s, uint64_t digest, ReferenceResult& r, std::string& why,
          struct stat& st) {
  why.clear();
  const auto fail = [&](std::string w) {
    why = std::move(w);
    return false;
  };
  const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;  // no entry
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  char magic[sizeof kMagic] = {};
  if (fstat(fd, &st) != 0 || ::pread(fd, magic, sizeof magic, 0) < 0) return fail("cannot be read");
  if (std::memcmp(magic, kMagic, sizeof kMagic - 2) == 0 &&
      std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    return fail("is of another format (" + std::string(magic, sizeof magic) + ")");
  const size_t want = entry_bytes(s.camera.width, s.camera.height);
  // The size is checked before anything is allocated, so a damaged header cannot ask for memory.
  if (size_t(st.st_size) != want)
    return fail("has " + std::to_string(st.st_size) + " bytes, not the " + std::to_string(want) +
                " of its frame");
  std::string data(want, '\0');
  for (size_t got = 0; got < want;) {
    const ssize_t n = ::pread(fd, data.data() + got, want - got, off_t(got));
    if (n <= 0) return fail("cannot be read");
    got += size_t(n);
  }
  const char* q = data.data() + want - sizeof(uint64_t);
  if (take<uint64_t>(q) != checksum(data.data(), want - sizeof(uint64_t)))
    return fail("is damaged (its checksum does not match its contents)");
  const char* c = data.data();
  if (std::memcmp(c, kMagic, sizeof kMagic) != 0) return fail("is not a reference cache entry");
  c += sizeof kMagic;
  if (take<uint64_t>(c) != digest) return fail("was made for another scene or setting");
  const int w = take<int32_t>(c), h = take<int32_t>(c);
  if (w != s.camera.width || h != s.camera.height) return fail("was made for another frame size");
  r.image = Image(w, h);
  std::memcpy(r.image.rgb.data(), c, r.image.rgb.size() * sizeof(Vec3));
  c += r.image.rgb.size() * sizeof(Vec3);
  std::memcpy(r.image.ids.data(), c, r.image.ids.size() * sizeof(int32_t));
  c += r.image.ids.size() * sizeof(int32_t);
  r.counts = take<TraceCounts>(c);
  r.wall_seconds = take<double>(c);
  return true;
}

/// Where an entry grows past the cap, the least recently used entries go first (a hit renews an
/// entry's time).
uint64_t size_cap() {
  if (const char* v = std::getenv("RTM_CACHE_SIZE"); v && *v) {
    try {
      return parse_byte_size(v);
    } catch (const std::invalid_argument& e) {
      std::cerr << "rtm: RTM_CACHE_SIZE: " << e.what() << "; using the default "
                << format_bytes(double(kDefaultCacheCap)) << "\n";
    }
  }
  return kDefaultCacheCap;
}

struct Listing {
  struct Entry {
    fs::path path;
    uint64_t bytes;
    fs::file_time_type used;
  };
  std::vector<Entry> entries;
  uint64_t bytes = 0;
  size_t partials = 0, abandoned = 0;
};

Listing list(const fs::path& dir, bool remove_abandoned) {
  Listing l;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e2;
    const std::string name = it->path().filename().string();
    const auto time = fs::last_write_time(it->path(), e2);
    if (e2) continue;
    if (name.find(".partial-") != std::string::npos) {
      ++l.partials;
      if (abandoned_partial(name, time)) {
        ++l.abandoned;
        if (remove_abandoned) fs::remove(it->path(), e2);
      }
      continue;
    }
    if (!is_entry(it->path())) continue;
    const uint64_t bytes = fs::file_size(it->path(), e2);
    if (e2) continue;
    l.entries.push_back({it->path(), bytes, time});
    l.bytes += bytes;
  }
  return l;
}

/// Removes the least recently used entries until the cache holds at most `cap` bytes, and the
/// temporaries writers left behind.
void trim(const fs::path& dir, uint64_t cap) {
  Listing l = list(dir, true);
  std::sort(l.entries.begin(), l.entries.end(),
            [](const auto& a, const auto& b) { return a.used < b.used; });
  std::error_code ec;
  for (const auto& e : l.entries) {
    if (l.bytes <= cap) break;
    if (fs::remove(e.path, ec)) l.bytes -= e.bytes;
  }
}

void store(const fs::path& p, uint64_t digest, const ReferenceResult& r) {
  const uint64_t cap = size_cap();
  const size_t bytes = entry_bytes(r.image.width, r.image.height);
  if (bytes > cap) return;  // it would evict everything and still not fit
  std::string data;
  data.reserve(bytes);
  data.append(kMagic, sizeof kMagic);
  put(data, digest);
  put(data, int32_t(r.image.width));
  put(data, int32_t(r.image.height));
  data.append(reinterpret_cast<const char*>(r.image.rgb.data()), r.image.rgb.size() * sizeof(Vec3));
  data.append(reinterpret_cast<const char*>(r.image.ids.data()),
              r.image.ids.size() * sizeof(int32_t));
  put(data, r.counts);
  put(data, r.wall_seconds);
  put(data, checksum(data.data(), data.size()));
  // Concurrent writers (two sweeps) each write a temporary of their own and rename it: the entry is
  // always one writer's whole file.
  try {
    const PartialFile partial(temporary_beside(p.string()));  // a signal removes it
    commit_atomically(p.string(), [&](const std::string& tmp) {
      std::ofstream f(tmp, std::ios::binary);
      f.write(data.data(), std::streamsize(data.size()));
      f.close();
      if (!f) throw std::runtime_error("cannot write");
    });
  } catch (const std::exception&) {
    return;  // a cache that cannot be written is only slower
  }
  trim(p.parent_path(), cap);
}

}  // namespace

ReferenceResult cached_reference(const Scene& s, const Grid& g, const std::string& scene_text,
                                 bool* hit, const ReferenceWatch& watch, PeFrame frame) {
  std::ostringstream key;
  key.precision(17);
  const Camera& c = s.camera;  // --camera may change it without changing scene_text
  key << scene_text << "|" << c.width << "x" << c.height << "|eye " << c.eye.x << "," << c.eye.y
      << "," << c.eye.z << "|at " << c.look_at.x << "," << c.look_at.y << "," << c.look_at.z
      << "|up " << c.up.x << "," << c.up.y << "," << c.up.z << "|fov " << c.fov_deg << "|grid "
      << g.n[0] << "," << g.n[1] << "," << g.n[2] << "|t " << s.threshold << "|d " << s.max_depth
      << "|o " << s.spawn_offset << " " << to_string(s.spawn_policy) << "|normals "
      << to_string(s.normal_interpolation) << "|frame " << to_string(frame) << "|" << __DATE__
      << " " << __TIME__ << "|" << reference_build_id();
  key << "|refs "
      << fnv1a(std::string(reinterpret_cast<const char*>(g.items.data()),
                           g.items.size() * sizeof(uint32_t)))
      << " "
      << fnv1a(std::string(reinterpret_cast<const char*>(g.start.data()),
                           g.start.size() * sizeof(uint32_t)));
  const fs::path dir = cache_dir();
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.ref", (unsigned long long)fnv1a(key.str()));
  const uint64_t digest = key_digest(key.str());
  ReferenceResult r;
  if (!dir.empty()) {
    const fs::path p = dir / name;
    std::string why;
    struct stat st {};
    if (load(p, s, digest, r, why, st)) {
      std::error_code ec;
      fs::last_write_time(p, fs::file_time_type::clock::now(), ec);  // recently used: evicted last
      if (hit) *hit = true;
      return r;
    }
    if (!why.empty()) {
      // Reported once: the entry is deleted (unless another writer has replaced it meanwhile).
      struct stat now {};
      if (::stat(p.c_str(), &now) == 0 && now.st_ino == st.st_ino && now.st_dev == st.st_dev)
        ::unlink(p.c_str());
      std::cerr << "rtm: reference cache: " << p.string() << " " << why
                << "; deleted, rendering the reference again\n";
    }
  }
  if (hit) *hit = false;
  r = render_reference(s, g, 0, watch, frame);
  if (!dir.empty()) store(dir / name, digest, r);
  return r;
}

int run_cache(const std::string& action) {
  const fs::path dir = cache_dir();
  if (dir.empty()) {
    std::cerr << "rtm: no reference cache: set RTM_CACHE_DIR, XDG_CACHE_HOME or HOME\n";
    return 2;
  }
  if (action == "info") {
    const Listing l = list(dir, false);
    std::cout << "reference cache: " << dir.string() << "\n"
              << "entries: " << l.entries.size() << ", " << format_bytes(double(l.bytes)) << " ("
              << l.bytes << " bytes)\n"
              << "size cap: " << format_bytes(double(size_cap()))
              << " (RTM_CACHE_SIZE; least recently used go first)\n"
              << "partial files: " << l.partials << " (" << l.abandoned
              << " left by writers that are gone)\n";
    return 0;
  }
  if (action == "clean") {
    const Listing l = list(dir, false);
    std::error_code ec;
    size_t removed = 0, partials = 0;
    for (const auto& e : l.entries) removed += fs::remove(e.path, ec);
    // Only abandoned temporaries: a running writer's is its own to rename or remove.
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      std::error_code e2;
      const std::string n = it->path().filename().string();
      if (n.find(".partial-") != std::string::npos &&
          abandoned_partial(n, fs::last_write_time(it->path(), e2)) && !e2)
        partials += fs::remove(it->path(), e2);
    }
    std::cout << "removed " << removed << (removed == 1 ? " entry (" : " entries (")
              << format_bytes(double(l.bytes)) << ") and " << partials
              << (partials == 1 ? " partial file" : " partial files") << " from " << dir.string()
              << "\n";
    return 0;
  }
  std::cerr << "rtm: cache: expected info or clean, got '" << action << "'\n";
  return 2;
}

}  // namespace rtm
