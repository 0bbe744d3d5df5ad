// A small stand-in for libFuzzer's main(), so the fuzz targets (LLVMFuzzerTestOneInput in
// fuzz_*.cpp) also run in the ordinary gcc build and in `make test` (ctest label `fuzz`):
//
//   1. replays every file given on the command line (files, or every regular file of a folder,
//      in sorted order): the seed corpus and the known/ reproducers of earlier findings;
//   2. runs seeded, deterministic random mutations of those files (bit flips, byte insert /
//      delete / overwrite, chunk duplication, splicing between corpus files, interesting integers
//      such as 0, -1, INT_MAX and huge sizes at random and at header offsets, number tokens in
//      text replaced by extreme values) until -runs=N executions or -max_total_time=S seconds.
//
// There is no coverage feedback (that is what the clang/libFuzzer build of `make fuzz` is for);
// the value is a cheap, always-on smoke test against crashes, uncaught exceptions and hangs on
// hostile input. The mutation sequence depends only on -seed and the inputs, so a run that
// stops earlier (slower machine) tested a prefix of what a longer run tests.
//
// Findings: a crash signal (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT -- which is also how an
// uncaught exception ends) or an input that runs longer than -timeout=S seconds (SIGALRM) writes
// the current input to -artifact=PATH with async-signal-safe calls only, prints where it went and
// ends the process with the signal (ctest fails). The input is not written to disk before each
// execution, which keeps an execution as cheap as the target itself.
//
//   fuzz_scene_driver [-runs=N] [-max_total_time=S] [-seed=N] [-max_len=N] [-timeout=S]
//                     [-rss_limit_mb=N] [-artifact=PATH] FILE_OR_DIR...
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) __attribute__((weak));

namespace {

namespace fs = std::filesystem;

// The input under test, for the signal handler (written before each execution: two stores).
const std::uint8_t* volatile g_data = nullptr;
volatile std::size_t g_size = 0;
char g_artifact[4096] = "fuzz-crash";
char g_what[64] = "";
volatile std::uint64_t g_exec = 0;  ///< mutated executions started (0 during the replay)

void write_all(int fd, const void* p, std::size_t n) {
  const auto* c = static_cast<const char*>(p);
  while (n > 0) {
    const ssize_t w = ::write(fd, c, n);
    if (w <= 0) return;
    c += w;
    n -= static_cast<std::size_t>(w);
  }
}

void say(const char* s) {
  write_all(2, s, std::strlen(s));
}

/// Saves the current input to g_artifact, reports, and dies of the same signal.
extern "C" void on_finding(int sig) {
  const int fd = ::open(g_artifact, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    if (g_data != nullptr) write_all(fd, const_cast<const std::uint8_t*>(g_data), g_size);
    ::close(fd);
  }
  say("\n==fuzz driver== ");
  say(sig == SIGALRM ? "TIMEOUT (an input ran longer than -timeout)" : "CRASH (signal ");
  if (sig != SIGALRM) {
    char num[8] = {static_cast<char>('0' + (sig / 10) % 10), static_cast<char>('0' + sig % 10), ')', 0};
    say(num);
  }
  say(" in ");
  say(g_what);
  if (g_exec > 0) {
    char num[24];
    int k = 23;
    num[k] = 0;
    for (std::uint64_t e = g_exec; e > 0 && k > 0; e /= 10) num[--k] = static_cast<char>('0' + e % 10);
    say(", execution ");
    say(num + k);
  }
  say("; the input is saved in ");
  say(g_artifact);
  say("\n");
  std::signal(sig, SIG_DFL);
  if (sig == SIGALRM) sig = SIGABRT;  // a core-dump-like exit status ctest reports as failed
  std::signal(sig, SIG_DFL);
  ::raise(sig);
  ::_exit(128 + sig);
}

/// splitmix64: small, fast, and the same sequence on every platform and standard library.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, n) (n > 0; the modulo bias is irrelevant here).
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
  bool one_in(std::size_t n) { return below(n) == 0; }

 private:
  std::uint64_t s_;
};

using Bytes = std::vector<std::uint8_t>;

const std::int64_t kInteresting[] = {0,
                                     1,
                                     -1,
                                     2,
                                     3,
                                     7,
                                     8,
                                     16,
                                     255,
                                     256,
                                     -128,
                                     127,
                                     32767,
                                     -32768,
                                     65535,
                                     65536,
                                     std::numeric_limits<std::int32_t>::max(),
                                     std::numeric_limits<std::int32_t>::min(),
                                     std::numeric_limits<std::uint32_t>::max(),
                                     1LL << 31,
                                     1LL << 40,
                                     std::numeric_limits<std::int64_t>::max(),
                                     std::numeric_limits<std::int64_t>::min()};

const char* const kTextValues[] = {"0",    "-1",   "-0",     "1e308", "-1e308",     "1e-320",     "nan",
                                   ".nan", ".inf", "-.inf",  "inf",   "2147483647", "2147483648", "-2147483649",
                                   "1e9",  "1e12", "999999", "0.0",   "1e-30",      "",           "~"};

/// Offsets of fixed-layout header fields: the NIfTI-1 header (sizeof_hdr, dim[0..7], datatype,
/// bitpix, vox_offset, scl, qform/sform codes, the affine rows) and the HDF5 superblock (version
/// bytes, sizes of offsets/lengths, base/EOF/root addresses).
const std::size_t kHeaderOffsets[] = {0,   40,  42,  44,  46,  48,  50,  52,  54, 56, 70, 72, 76, 80,
                                      108, 112, 116, 252, 254, 280, 296, 312, 8,  9,  13, 14, 24, 32};

void put_int(Bytes& b, std::size_t at, std::int64_t v, std::size_t width, bool big_endian) {
  for (std::size_t k = 0; k < width && at + k < b.size(); ++k) {
    const std::size_t shift = 8 * (big_endian ? width - 1 - k : k);
    b[at + k] = static_cast<std::uint8_t>((static_cast<std::uint64_t>(v) >> shift) & 0xFF);
  }
}

/// One random edit of `b`, sometimes using `other` (another corpus file) for splicing.
void mutate_once(Bytes& b, const Bytes& other, Rng& r, std::size_t max_len) {
  const std::size_t op = r.below(11);
  const std::size_t n = b.size();
  switch (op) {
    case 0:  // flip a bit
      if (n > 0) b[r.below(n)] ^= static_cast<std::uint8_t>(1u << r.below(8));
      break;
    case 1:  // overwrite a byte
      if (n > 0) b[r.below(n)] = static_cast<std::uint8_t>(r.next());
      break;
    case 2: {  // insert 1..8 random bytes
      const std::size_t k = 1 + r.below(8), at = r.below(n + 1);
      Bytes ins(k);
      for (auto& c : ins) c = static_cast<std::uint8_t>(r.next());
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), ins.begin(), ins.end());
      break;
    }
    case 3: {  // delete a range (up to 1/8 of the input)
      if (n == 0) break;
      const std::size_t at = r.below(n), k = 1 + r.below(std::max<std::size_t>(1, std::min(n - at, n / 8 + 1)));
      b.erase(b.begin() + static_cast<std::ptrdiff_t>(at), b.begin() + static_cast<std::ptrdiff_t>(at + k));
      break;
    }
    case 4:    // an interesting integer at a random offset
    case 5: {  // ... or at a header field
      if (n == 0) break;
      const std::size_t widths[] = {1, 2, 4, 8};
      const std::size_t at = op == 4 ? r.below(n) : kHeaderOffsets[r.below(std::size(kHeaderOffsets))];
      put_int(b, at, kInteresting[r.below(std::size(kInteresting))], widths[r.below(4)], r.one_in(4));
      break;
    }
    case 6: {  // duplicate a chunk in place
      if (n == 0) break;
      const std::size_t at = r.below(n), k = 1 + r.below(std::min<std::size_t>(n - at, 64));
      const Bytes chunk(b.begin() + static_cast<std::ptrdiff_t>(at), b.begin() + static_cast<std::ptrdiff_t>(at + k));
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(r.below(n + 1)), chunk.begin(), chunk.end());
      break;
    }
    case 7: {  // splice: a chunk of another corpus file over or into this one
      if (other.empty()) break;
      const std::size_t from = r.below(other.size()), k = 1 + r.below(std::min<std::size_t>(other.size() - from, 256));
      const std::size_t at = r.below(n + 1);
      if (r.one_in(2) || at + k > n) {
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), other.begin() + static_cast<std::ptrdiff_t>(from),
                 other.begin() + static_cast<std::ptrdiff_t>(from + k));
      } else {
        std::copy(other.begin() + static_cast<std::ptrdiff_t>(from),
                  other.begin() + static_cast<std::ptrdiff_t>(from + k), b.begin() + static_cast<std::ptrdiff_t>(at));
      }
      break;
    }
    case 8: {  // crossover: the head of this file, the tail of the other
      if (other.empty() || n == 0) break;
      const std::size_t cut = r.below(n), from = r.below(other.size());
      b.resize(cut);
      b.insert(b.end(), other.begin() + static_cast<std::ptrdiff_t>(from), other.end());
      break;
    }
    case 9: {  // text: replace a number token by an extreme value
      std::vector<std::size_t> starts;
      for (std::size_t i = 0; i < n; ++i)
        if ((b[i] >= '0' && b[i] <= '9') && (i == 0 || !(b[i - 1] >= '0' && b[i - 1] <= '9'))) starts.push_back(i);
      if (starts.empty()) break;
      std::size_t at = starts[r.below(starts.size())], end = at;
      while (end < n && ((b[end] >= '0' && b[end] <= '9') || b[end] == '.' || b[end] == 'e' || b[end] == '-')) ++end;
      const std::string v = kTextValues[r.below(std::size(kTextValues))];
      b.erase(b.begin() + static_cast<std::ptrdiff_t>(at), b.begin() + static_cast<std::ptrdiff_t>(end));
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), v.begin(), v.end());
      break;
    }
    case 10: {  // text: a whole line of the other file inserted at a line start (YAML structure)
      if (other.empty()) break;
      std::size_t from = r.below(other.size());
      while (from > 0 && other[from - 1] != '\n') --from;
      std::size_t to = from;
      while (to < other.size() && other[to] != '\n') ++to;
      if (to < other.size()) ++to;
      std::size_t at = r.below(n + 1);
      while (at > 0 && b[at - 1] != '\n') --at;
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), other.begin() + static_cast<std::ptrdiff_t>(from),
               other.begin() + static_cast<std::ptrdiff_t>(to));
      break;
    }
    default:
      break;
  }
  if (b.size() > max_len) b.resize(max_len);
}

Bytes read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Runs the target on one input with the watchdog armed.
void execute(const Bytes& b, unsigned timeout_s) {
  g_data = b.data();
  g_size = b.size();
  if (timeout_s > 0) ::alarm(timeout_s);
  (void)LLVMFuzzerTestOneInput(b.data(), b.size());
  if (timeout_s > 0) ::alarm(0);
  g_data = nullptr;
  g_size = 0;
}

bool option(const std::string& arg, const char* name, std::string& value) {
  const std::string prefix = std::string("-") + name + "=";
  if (arg.rfind(prefix, 0) != 0) return false;
  value = arg.substr(prefix.size());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (LLVMFuzzerInitialize != nullptr) LLVMFuzzerInitialize(&argc, &argv);
  std::uint64_t runs = 0, seed = 1;
  double max_seconds = 0.0;
  std::size_t max_len = 65536;
  unsigned timeout_s = 20;
  std::size_t rss_limit_mb = 0;
  std::vector<fs::path> files;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      std::string v;
      if (option(a, "runs", v)) {
        runs = std::stoull(v);
      } else if (option(a, "max_total_time", v)) {
        max_seconds = std::stod(v);
      } else if (option(a, "seed", v)) {
        seed = std::stoull(v);
      } else if (option(a, "max_len", v)) {
        max_len = std::stoull(v);
      } else if (option(a, "timeout", v)) {
        timeout_s = static_cast<unsigned>(std::stoul(v));
      } else if (option(a, "rss_limit_mb", v)) {
        rss_limit_mb = std::stoull(v);
      } else if (option(a, "artifact", v)) {
        if (v.size() >= sizeof g_artifact) throw std::runtime_error("-artifact path too long");
        std::strcpy(g_artifact, v.c_str());
      } else if (!a.empty() && a[0] == '-') {
        throw std::runtime_error("unknown option " + a);
      } else if (fs::is_directory(a)) {
        std::vector<fs::path> in_dir;
        for (const auto& e : fs::directory_iterator(a))
          if (e.is_regular_file()) in_dir.push_back(e.path());
        std::sort(in_dir.begin(), in_dir.end());
        files.insert(files.end(), in_dir.begin(), in_dir.end());
      } else if (fs::is_regular_file(a)) {
        files.emplace_back(a);
      } else {
        throw std::runtime_error(a + " is neither a file nor a folder");
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr,
                 "%s: %s\nusage: %s [-runs=N] [-max_total_time=S] [-seed=N] [-max_len=N] [-timeout=S] "
                 "[-rss_limit_mb=N] [-artifact=PATH] FILE_OR_DIR...\n",
                 argv[0], e.what(), argv[0]);
    return 2;
  }
  if (files.empty()) {
    std::fprintf(stderr, "%s: no inputs (give the seed corpus folder)\n", argv[0]);
    return 2;
  }
  if (rss_limit_mb > 0) {
    // Caps the address space, so an input that makes a reader allocate without bound fails
    // (std::bad_alloc: a finding) instead of exhausting a machine shared with other jobs. Not
    // for sanitizer builds, whose shadow memory needs terabytes of address space.
    const rlimit lim{rss_limit_mb << 20, rss_limit_mb << 20};
    if (setrlimit(RLIMIT_AS, &lim) != 0) std::perror("setrlimit(RLIMIT_AS)");
  }
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) std::signal(sig, on_finding);

  // 1. Replay.
  std::vector<Bytes> corpus;
  for (const auto& f : files) {
    Bytes b = read_bytes(f);
    std::snprintf(g_what, sizeof g_what, "replay of %s", f.filename().string().substr(0, 40).c_str());
    const auto t0 = std::chrono::steady_clock::now();
    execute(b, timeout_s);
    std::printf("replayed %s (%zu bytes, %.3f s)\n", f.string().c_str(), b.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    corpus.push_back(std::move(b));
  }
  std::fflush(stdout);

  // 2. Mutations.
  Rng rng(seed);
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  std::uint64_t done = 0;
  std::snprintf(g_what, sizeof g_what, "a mutation (-seed=%llu)", static_cast<unsigned long long>(seed));
  Bytes input;
  while ((runs == 0 || done < runs) && (max_seconds <= 0.0 || elapsed() < max_seconds)) {
    if (runs == 0 && max_seconds <= 0.0) break;  // neither bound given: replay only
    const std::size_t base = rng.below(corpus.size());
    input = corpus[base];
    const Bytes& other = corpus[rng.below(corpus.size())];
    const std::size_t edits = 1 + rng.below(rng.one_in(4) ? 16 : 4);
    for (std::size_t k = 0; k < edits; ++k) mutate_once(input, other, rng, max_len);
    g_exec = done + 1;
    execute(input, timeout_s);
    ++done;
  }
  const double s = elapsed();
  std::printf("%s: %zu inputs replayed, %llu mutated executions in %.1f s (%.0f/s, seed %llu): no crash, no hang\n",
              argv[0], files.size(), static_cast<unsigned long long>(done), s,
              s > 0 ? static_cast<double>(done) / s : 0.0, static_cast<unsigned long long>(seed));
  return 0;
}
