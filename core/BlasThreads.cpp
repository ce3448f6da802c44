#include "core/BlasThreads.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <mutex>

namespace keller {

namespace {

// OpenBLAS's thread controls, looked up where it is loaded: in the global namespace (a program), or
// by the names Debian's alternatives give it (a Python module loads its libraries locally).
struct OpenBlasControls {
  void (*set)(int) = nullptr;
  int (*get)() = nullptr;
  int initial = 0;  // the count before keller changed it: OPENBLAS_NUM_THREADS, or the cores

  OpenBlasControls() {
    void* scopes[] = {RTLD_DEFAULT, dlopen("libblas.so.3", RTLD_LAZY | RTLD_NOLOAD),
                      dlopen("libopenblas.so.0", RTLD_LAZY | RTLD_NOLOAD)};
    for (void* scope : scopes) {
      if (!scope) continue;
      set = reinterpret_cast<void (*)(int)>(dlsym(scope, "openblas_set_num_threads"));
      get = reinterpret_cast<int (*)()>(dlsym(scope, "openblas_get_num_threads"));
      if (set && get) break;
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

}  // namespace keller
