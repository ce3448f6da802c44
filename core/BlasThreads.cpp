#include "core/BlasThreads.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <mutex>

namespace keller {

namespace {

// OpenBLAS's thread controls, where the program has loaded it (a program linked with keller's
// libraries finds them in its global scope; a library loaded locally, as a Python module is,
// does not, and keeps the BLAS as it is).
struct OpenBlasControls {
  void (*set)(int) = nullptr;
  int (*get)() = nullptr;
  int initial = 0;  // the count at the first call: OpenBLAS's own, before keller changed it

  OpenBlasControls() {
    set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    if (!set || !get) {
      set = nullptr;
      get = nullptr;
    }
    if (get) initial = get();
  }
};

std::atomic<int> g_policy{-1};  // -1: not set (off), 0: off, 1: on

OpenBlasControls& controls() {
  static OpenBlasControls c;
  return c;
}

}  // namespace

int blas_threads_for_unknowns(long unknowns, int available) {
  return unknowns < kThreadedBlasUnknowns ? 1 : std::max(1, available);
}

void set_blas_thread_policy(bool on) { g_policy = on ? 1 : 0; }

bool blas_thread_policy() { return g_policy == 1; }

void default_blas_thread_policy(bool on) {
  int unset = -1;
  g_policy.compare_exchange_strong(unset, on ? 1 : 0);
}

int use_blas_threads_for(long unknowns) {
  static std::mutex m;
  const std::lock_guard<std::mutex> lock(m);
  OpenBlasControls& c = controls();
  if (!c.set) return 0;
  const int threads = blas_threads_for_unknowns(unknowns, c.initial);
  if (c.get() != threads) c.set(threads);
  return threads;
}

int blas_threads() {
  OpenBlasControls& c = controls();
  return c.get ? c.get() : 0;
}

std::string blas_core() {
  auto corename = reinterpret_cast<char* (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  const char* name = corename ? corename() : nullptr;
  return name ? std::string(name) : std::string();
}

std::string better_blas_core(const std::string& core, bool avx2_and_fma, bool avx512) {
  std::string lower = core;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower != "prescott") return "";
  if (avx512) return "SkylakeX";
  return avx2_and_fma ? "Haswell" : "";
}

std::string better_blas_core() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  const bool avx2_and_fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
  return better_blas_core(blas_core(), avx2_and_fma, avx512);
#else
  return "";
#endif
}

}  // namespace keller
