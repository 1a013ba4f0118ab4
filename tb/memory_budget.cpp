#include "memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "byte_size.h"
#include "engine/pe_engine.h"
#include "render/pixel_sum.h"
#include "render/reference.h"
#include "render/scene_memory.h"
#include "render_options.h"
#include "units/fifo_table.h"
#include "units/machine_ray.h"

namespace rtm {
namespace {

// Measured with this build (/usr/bin/time, peak resident size) and rounded up: a process that
// renders a 1x1 frame holds about 135 MiB (the libraries, OpenImageIO included); a PE on the PE
// engine about 16 KiB, one as modules about 110 KiB, besides its FIFOs.
constexpr double kProcessBytes = 160.0 * (1 << 20);
constexpr double kEnginePeBytes = 24.0 * 1024;
constexpr double kModularPeBytes = 128.0 * 1024;
/// A FIFO place: the engine queues 4-byte slot numbers; a module's sc_fifo holds whole payloads
/// (a MachineRay; a MAC result, a ray with its schedule and sums, about 400 bytes).
constexpr double kEnginePlaceBytes = 4, kMacResultBytes = 512;
/// Per pixel: an RGB pixel (3 doubles) and its primitive id.
constexpr double kPixelBytes = sizeof(Vec3) + sizeof(int32_t);

struct Ks {
  double ks = 0, kt = 0;
};
Ks branch_coefficients(const Scene& s) {
  Ks k;
  for (const Primitive& p : s.primitives) {
    const Material& m = s.materials[size_t(p.material)];
    k.ks = std::max(k.ks, m.specular);
    k.kt = std::max(k.kt, m.transmission);
  }
  return k;
}

/// Branch rays of generation d (primary: d = 1) whose contribution can exceed the threshold: the
/// paths with j transmissions and d - 1 - j reflections, C(d - 1, j) of each.
double generation_bound(const Scene& s, const Ks& k, int d) {
  if (d == 1) return 1;
  double n = 0, binomial = 1;  // C(d - 1, j)
  for (int j = 0; j <= d - 1; ++j) {
    if (j > 0) binomial = binomial * double(d - j) / double(j);
    const double c = std::pow(k.ks, d - 1 - j) * std::pow(k.kt, j);
    if (c > s.threshold) n += binomial;  // necessary for every ray of the path to have been spawned
  }
  return n;
}

std::string str(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

uint64_t read_number(const char* path) {
  std::ifstream f(path);
  uint64_t v = 0;
  return (f >> v) ? v : 0;
}

/// What a heap block costs beyond its bytes: glibc's malloc keeps 8 bytes a block and rounds to 16.
double heap_block(double bytes) { return bytes > 0 ? std::ceil((bytes + 8) / 16) * 16 : 0; }

template <class T>
double heap_of(const std::vector<T>& v) {
  return heap_block(double(v.capacity() * sizeof(T)));
}

/// A primitive's SceneMemory entry (render/scene_memory.h): its coefficient RAM image, its
/// centre and its clips in its frame, at fp64 (the reference's; the machine's fp32 image is
/// smaller).
double memory_image_bytes(const Scene& s) {
  double bytes = 0;
  for (const Primitive& p : s.primitives)
    bytes += sizeof(CoefRam<double>) + sizeof(Vec3) + sizeof(std::vector<HalfSpace>) +
             heap_block(double(p.clips.size() * sizeof(HalfSpace)));
  return bytes;
}

}  // namespace

double scene_bytes(const Scene& s) {
  double bytes = 0;
  for (const Primitive& p : s.primitives)
    bytes += sizeof(Primitive) + heap_of(p.clips) + heap_of(p.vertices) + heap_of(p.outline);
  for (const SourceLocation& o : s.origins)
    bytes += sizeof(SourceLocation) +
             (o.file.capacity() > 15 ? heap_block(double(o.file.capacity() + 1)) : 0);
  return bytes;
}

double rays_per_primary_bound(const Scene& s) {
  const Ks k = branch_coefficients(s);
  double total = 0;
  for (int d = 1; d <= s.max_depth; ++d) total += generation_bound(s, k, d);
  return total * (1 + double(s.lights.size()));
}

std::vector<MemoryPart> estimate_memory(const Scene& s, const Grid& g, const MachineConfig* c,
                                        bool tracing, int threads) {
  const double pixels = double(s.camera.width) * double(s.camera.height);
  const std::string frame =
      std::to_string(s.camera.width) + "x" + std::to_string(s.camera.height) + " pixels";
  std::vector<MemoryPart> parts;
  parts.push_back({"the program", kProcessBytes, "its libraries and data (measured)"});
  // Either renderer traces a copy of the scene and its grid (in the PEs' frame), and the
  // primitives' memory image made from it, while the world's copy stays; a machine render has
  // the PEs' image and then the reference's.
  const double scene = scene_bytes(s), images = (c ? 2 : 1) * memory_image_bytes(s);
  parts.push_back(
      {"the scene", 2 * scene + images,
       std::to_string(s.primitives.size()) + " primitives at " +
           str((2 * scene + images) / std::max<double>(1, double(s.primitives.size()))) +
           " bytes each: the world's and the frame's copies, and " +
           (c ? "the PEs' and the reference's memory images" : "the memory image")});
  // Each reference thread's mailbox: a stamp and a hit per primitive (render/reference.cpp).
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const double mailbox = double(sizeof(uint32_t) + sizeof(PrimitiveHit));
  parts.push_back(
      {"the mailboxes", double(threads) * double(s.primitives.size()) * mailbox,
       std::to_string(threads) + " reference threads at " + str(mailbox) + " bytes a primitive"});
  parts.push_back({"the grid", 2 * double(g.start.size() + g.items.size()) * sizeof(uint32_t),
                   std::to_string(g.voxel_count()) + " voxels, " + std::to_string(g.items.size()) +
                       " references, twice (the world's and the frame's copies)"});
  if (!c) {
    // The frame (RGB and ids), and the file's pixels while it is written.
    parts.push_back({"the image", pixels * (kPixelBytes + 16),
                     frame + " at " + str(kPixelBytes + 16) + " bytes each"});
    return parts;
  }
  // The PEs' frame buffers (fixed-point sums and ids), the host's gathered frame and the result's
  // copy, the reference's, and comparing them (OpenImageIO's buffers, a cache entry as it is read).
  const double per_pixel =
      (sizeof(PixelSum) + 4) + 2 * kPixelBytes + kPixelBytes + 2 * sizeof(Vec3) + kPixelBytes;
  parts.push_back({"the images", pixels * per_pixel,
                   frame + " at " + str(per_pixel) +
                       " bytes each: the PEs' frame buffers, the gathered frame, the reference and "
                       "their comparison"});
  parts.push_back({"the primary rays", pixels * sizeof(Ray) * 2,
                   frame +
                       ": each PE's rays in its local memory, and the host's as it sends them (" +
                       std::to_string(sizeof(Ray)) + " bytes a ray)"});
  // Each PE: its state, and every FIFO allocated whole.
  const bool engine = engine_unsupported(*c, tracing).empty();
  double places = 0, fifo_bytes = 0;
  for (const FifoSpec& f : fifo_table()) {
    const double n = double(c->*f.depth) * (f.per_lane ? c->intersection_units : 1);
    places += n;
    fifo_bytes += n * (engine                            ? kEnginePlaceBytes
                       : f.payload == Payload::MacResult ? kMacResultBytes
                       : f.payload == Payload::Ray       ? double(sizeof(MachineRay))
                                                         : 8.0);
  }
  const double pe_bytes = (engine ? kEnginePeBytes : kModularPeBytes) + fifo_bytes;
  parts.push_back({"the PEs", double(c->pes) * pe_bytes,
                   std::to_string(c->pes) + " PEs at " + format_bytes(pe_bytes) + " each (" +
                       str(places) + " FIFO places" +
                       (engine ? " on the PE engine" : " as modules") + ")"});
  return parts;
}

uint64_t default_memory_budget() {
  const double physical = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
  double limit = physical > 0 ? physical : double(uint64_t(4) << 30);
  if (const uint64_t cg = read_number("/sys/fs/cgroup/memory.max"); cg > 0)
    limit = std::min(limit, double(cg));
  struct rlimit as {};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    limit = std::min(limit, double(as.rlim_cur));
  return uint64_t(limit * 0.75);
}

std::string default_memory_budget_source() {
  return "the default, 3/4 of the " + format_bytes(double(default_memory_budget()) / 0.75) +
         " this machine (or its control group) has";
}

void check_memory_budget(const std::vector<MemoryPart>& parts, uint64_t budget, bool given) {
  double total = 0;
  const MemoryPart* largest = &parts.front();
  for (const MemoryPart& p : parts) {
    total += p.bytes;
    if (p.bytes > largest->bytes) largest = &p;
  }
  if (total <= double(budget)) return;
  throw UsageError("--max-memory: this render needs about " + format_bytes(total) +
                   ", more than the " + format_bytes(double(budget)) + " allowed (" +
                   (given ? std::string("--max-memory") : default_memory_budget_source()) +
                   "); the largest part is " + largest->name + ": " + format_bytes(largest->bytes) +
                   " for " + largest->detail);
}

}  // namespace rtm
