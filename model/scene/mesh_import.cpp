// Mesh files through Assimp, in a child process. Assimp crashes on some inputs and exhausts
// memory on others (assimp-testmodels' invalid/OutOfMemory.off asks for terabytes): the child
// imports under an address-space and a time limit and sends the triangles back through a pipe, so
// that whatever the library does becomes a SceneError naming the file.
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "scene/mesh.h"

// The sanitizers reserve terabytes of shadow memory up front, which any address-space limit
// refuses: their builds import without one (the time limit still holds).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RTM_IMPORT_MEMORY_LIMIT 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define RTM_IMPORT_MEMORY_LIMIT 0
#endif
#endif
#ifndef RTM_IMPORT_MEMORY_LIMIT
#define RTM_IMPORT_MEMORY_LIMIT 1
#endif

namespace rtm {

bool import_memory_is_limited() { return RTM_IMPORT_MEMORY_LIMIT != 0; }

namespace {

Vec3 vec(const aiVector3D& v) { return {v.x, v.y, v.z}; }
Vec3 vec(const aiColor3D& c) { return {c.r, c.g, c.b}; }

aiMatrix4x4 global_transform(const aiNode* n) {
  aiMatrix4x4 t;
  for (; n; n = n->mParent) t = n->mTransformation * t;
  return t;
}

template <class T>
std::optional<T> property(const aiMaterial* m, const char* key, unsigned type, unsigned index) {
  T x{};
  if (m->Get(key, type, index, x) != AI_SUCCESS) return std::nullopt;
  return x;
}

std::optional<Vec3> colour(const aiMaterial* m, const char* key, unsigned type, unsigned index) {
  if (auto c = property<aiColor3D>(m, key, type, index)) return vec(*c);
  return std::nullopt;
}

std::optional<double> real(const aiMaterial* m, const char* key, unsigned type, unsigned index) {
  if (auto x = property<float>(m, key, type, index)) return double(*x);
  return std::nullopt;
}

MeshMaterial material(const aiMaterial* m) {
  MeshMaterial x;
  aiString name;
  if (m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) x.name = name.C_Str();
  x.kd = colour(m, AI_MATKEY_COLOR_DIFFUSE);
  x.ks = colour(m, AI_MATKEY_COLOR_SPECULAR);
  x.ns = real(m, AI_MATKEY_SHININESS);
  x.ni = real(m, AI_MATKEY_REFRACTI);
  x.opacity = real(m, AI_MATKEY_OPACITY);
  x.illum = property<int>(m, "$mat.illum", 0, 0);  // OBJ only (Assimp's ObjFileImporter)
  if (auto c = property<aiColor4D>(m, AI_MATKEY_BASE_COLOR)) x.base_color = Vec3(c->r, c->g, c->b);
  x.metallic = real(m, AI_MATKEY_METALLIC_FACTOR);
  x.roughness = real(m, AI_MATKEY_ROUGHNESS_FACTOR);
  x.transmission = real(m, AI_MATKEY_TRANSMISSION_FACTOR);
  return x;
}

void add_node(const aiScene* sc, const aiNode* n, const aiMatrix4x4& parent, MeshData& out) {
  const aiMatrix4x4 t = parent * n->mTransformation;
  // Normals turn with the inverse transpose (a non-uniform scale would tilt them otherwise).
  aiMatrix3x3 turn_normals(t);
  turn_normals.Inverse().Transpose();
  for (unsigned i = 0; i < n->mNumMeshes; ++i) {
    const aiMesh* mesh = sc->mMeshes[n->mMeshes[i]];
    const uint32_t base = uint32_t(out.positions.size());
    for (unsigned k = 0; k < mesh->mNumVertices; ++k) {
      out.positions.push_back(vec(t * mesh->mVertices[k]));
      out.normals.push_back(mesh->HasNormals() ? vec(turn_normals * mesh->mNormals[k]) : Vec3(0));
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices < 3) {
        ++out.points_and_lines;
        continue;
      }
      // aiProcess_Triangulate has split every larger face.
      out.triangles.push_back(
          {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
      out.triangle_material.push_back(mesh->mMaterialIndex);
    }
  }
  for (unsigned i = 0; i < n->mNumChildren; ++i) add_node(sc, n->mChildren[i], t, out);
}

MeshData read_with_assimp(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* sc =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_ValidateDataStructure);
  if (!sc) {
    const std::string why = importer.GetErrorString();
    // Assimp catches its own allocation failures and reports them by the exception's name.
    if (why == "std::bad_alloc") throw std::bad_alloc();
    throw std::runtime_error("Assimp cannot read it: " + why);
  }
  if (!sc->mRootNode) throw std::runtime_error("the file has no scene graph");
  MeshData out;
  for (unsigned i = 0; i < sc->mNumMaterials; ++i)
    out.materials.push_back(material(sc->mMaterials[i]));
  add_node(sc, sc->mRootNode, aiMatrix4x4(), out);
  bool any_normal = false;
  for (unsigned i = 0; i < sc->mNumMeshes; ++i)
    any_normal = any_normal || sc->mMeshes[i]->HasNormals();
  if (!any_normal) out.normals.clear();
  if (sc->mNumCameras > 0) {
    const aiCamera* c = sc->mCameras[0];
    const aiNode* n = sc->mRootNode->FindNode(c->mName);
    const aiMatrix4x4 t = n ? global_transform(n) : aiMatrix4x4();
    const aiMatrix3x3 turn(t);
    // Assimp 5.2's glTF importer departs from its own aiCamera convention: it copies the node's
    // translation into mPosition (which is relative to the node) and gives the whole horizontal
    // angle where the others give half of it.
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    const bool gltf = ext == ".gltf" || ext == ".glb";
    MeshCamera cam;
    cam.eye = vec(t * (gltf ? aiVector3D(0, 0, 0) : c->mPosition));
    cam.look_at = cam.eye + vec(turn * c->mLookAt);
    cam.up = vec(turn * c->mUp);
    cam.fov_deg = (gltf ? 1 : 2) * double(c->mHorizontalFOV) * 180 / M_PI;
    out.camera = cam;
  }
  for (unsigned i = 0; i < sc->mNumLights; ++i) {
    const aiLight* l = sc->mLights[i];
    if (l->mType != aiLightSource_POINT) {
      ++out.other_lights;
      continue;
    }
    const aiNode* n = sc->mRootNode->FindNode(l->mName);
    const aiMatrix4x4 t = n ? global_transform(n) : aiMatrix4x4();
    out.lights.push_back({vec(t * l->mPosition), vec(l->mColorDiffuse)});
  }
  if (out.triangles.empty())
    throw std::runtime_error(out.points_and_lines
                                 ? "the file has only points and lines, no triangles"
                                 : "the file has no triangles");
  return out;
}

/// This process's address space now, from /proc/self/statm; 0 if unknown.
uint64_t address_space_bytes() {
  std::ifstream f("/proc/self/statm");
  uint64_t pages = 0;
  f >> pages;
  return pages * uint64_t(sysconf(_SC_PAGESIZE));
}

void write_all(int fd, const std::string& s) {
  size_t at = 0;
  while (at < s.size()) {
    const ssize_t n = ::write(fd, s.data() + at, s.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent has gone: nothing to tell
    at += size_t(n);
  }
}

[[noreturn]] void child(int fd, const std::string& path, const SceneReadOptions& options) {
  std::string reply;
  if (RTM_IMPORT_MEMORY_LIMIT && options.import_memory > 0) {
    const rlim_t limit = rlim_t(address_space_bytes() + options.import_memory);
    const rlimit r{limit, limit};
    setrlimit(RLIMIT_AS, &r);
  }
  try {
    reply = "M" + encode_mesh(read_with_assimp(path));
  } catch (const std::bad_alloc&) {
    reply = "Eout of memory: Assimp needed more than the import's limit of " +
            std::to_string(options.import_memory >> 20) + " MiB of address space";
  } catch (const std::exception& e) {
    reply = std::string("E") + e.what();
  } catch (...) {
    reply = "Ethe mesh import (Assimp) failed with an unknown exception";
  }
  write_all(fd, reply);
  ::close(fd);
  _exit(0);  // not exit: the parent's atexit handlers and buffers are not the child's to run
}

double now_seconds() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// Assimp's messages may end in a newline or carry control characters from the file.
std::string printable(const std::string& s) {
  std::string out;
  for (const char c : s.substr(0, 300)) out += (c >= 32 && c < 127) ? c : ' ';
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

}  // namespace

bool is_mesh_extension(const std::string& ext) {
  if (ext.size() < 2 || ext[0] != '.') return false;
  return Assimp::Importer().IsExtensionSupported(ext);
}

MeshData import_mesh(const std::string& path, const SceneReadOptions& options) {
  namespace fs = std::filesystem;
  auto fail = [&](const std::string& what) { throw SceneError(path, 0, what); };
  std::error_code ec;
  if (!fs::exists(path, ec)) fail("cannot read mesh file: " + std::string(std::strerror(ENOENT)));
  if (!fs::is_regular_file(path, ec)) fail("cannot read mesh file: it is not a regular file");
  if (access(path.c_str(), R_OK) != 0)
    fail("cannot read mesh file: " + std::string(std::strerror(errno)));

  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    fail("cannot start the mesh import: " + std::string(std::strerror(errno)));
  const pid_t pid = fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    fail("cannot start the mesh import: " + std::string(std::strerror(errno)));
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], path, options);
  }
  ::close(fds[1]);

  // Read everything the child sends, until it closes the pipe or the time is up.
  std::string reply;
  const double deadline = now_seconds() + options.import_seconds;
  bool timed_out = false;
  char buffer[1 << 16];
  for (;;) {
    const double left = deadline - now_seconds();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    if (options.progress) options.progress("mesh import (Assimp)", "", 0, 0);
    // Awake at least twice a second, for the progress line.
    pollfd p{fds[0], POLLIN, 0};
    const int ready = poll(&p, 1, int(std::min(left * 1000 + 1, 500.0)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    reply.append(buffer, size_t(n));
  }
  ::close(fds[0]);
  if (timed_out) kill(pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    fail("the mesh import (Assimp) took longer than its limit of " +
         std::to_string(int(options.import_seconds)) + " s; stopped");
  if (WIFSIGNALED(status))
    fail("the mesh import (Assimp) crashed on this file (signal " +
         std::to_string(WTERMSIG(status)) + ", " + strsignal(WTERMSIG(status)) + ")");
  if (reply.empty())
    fail("the mesh import (Assimp) ended without an answer (exit status " +
         std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  if (reply[0] == 'E') fail(printable(reply.substr(1)));
  try {
    return decode_mesh(reply.substr(1));
  } catch (const std::invalid_argument& e) {
    fail(std::string("the mesh import sent a bad answer: ") +
         e.what());  // unreachable but for a bug
  }
  return {};
}

}  // namespace rtm
