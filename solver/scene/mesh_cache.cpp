#include "solver/scene/mesh_cache.hpp"

#include <unistd.h>

#include <fstream>
#include <iomanip>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/pipeline/mesh_pipeline.hpp"

namespace adamss::solver {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kFnvOffset = 1469598103934665603ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

/// Continues the FNV-1a hash h over n bytes.
std::uint64_t fnv1a(std::uint64_t h, const char* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= kFnvPrime;
  }
  return h;
}

std::string hex16(std::uint64_t h) {
  std::ostringstream os;
  os << std::hex << std::setw(16) << std::setfill('0') << h;
  return os.str();
}

}  // namespace

std::string hash_hex(const std::string& s) {
  return hex16(fnv1a(kFnvOffset, s.data(), s.size()));
}

std::string file_hash_hex(const fs::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(what + ": cannot read '" + file.string() + "'");
  std::uint64_t h = kFnvOffset;
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) h = fnv1a(h, buf, static_cast<std::size_t>(in.gcount()));
  return hex16(h);
}

fs::path cache_dir_of(const SceneOptions& opt) {
  return opt.cache_dir.empty() ? default_cache_dir() : opt.cache_dir;
}

preprocess::Mesh cached_mesh(const preprocess::MeshRequest& request, const SceneOptions& opt,
                             const std::string& file_name, std::string& source) {
  const fs::path dir = cache_dir_of(opt);
  const fs::path file = dir / file_name;
  source = file.string();
  if (fs::exists(file)) return preprocess::read_mesh_h5(file);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError("mesh cache folder " + dir.string() + ": " + ec.message() + " (set ADAMSS_CACHE_DIR)");
  preprocess::Mesh mesh = preprocess::build_mesh(request).mesh;
  const fs::path part = file.string() + ".part" + std::to_string(::getpid());
  preprocess::write_mesh_h5(part, mesh);
  fs::rename(part, file, ec);
  if (ec) throw InputError("mesh cache: cannot rename " + part.string() + " to " + file.string() + ": " + ec.message());
  return mesh;
}

}  // namespace adamss::solver
