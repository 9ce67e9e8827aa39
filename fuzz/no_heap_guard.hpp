// The no-heap guard of the plan fuzz target: while armed, any heap allocation or free
// on this thread prints what happened and abort()s, so libFuzzer (or the replay test)
// reports it as a crash. An allocation in the core is a finding.
//
// Two mechanisms, chosen at compile time:
//  * without AddressSanitizer (the normal gcc build's replay test): the replaced
//    operator new / delete family and malloc family of tests/unit/test_no_heap.cpp,
//    forwarding to glibc's __libc_* entry points;
//  * under AddressSanitizer (the libFuzzer build and the asan preset's replay test) the
//    allocator belongs to ASan, so the replacements are compiled out as in
//    test_no_heap.cpp, and the sanitizer's allocation hooks
//    (__sanitizer_install_malloc_and_free_hooks, called by ASan for malloc, new and
//    free alike) do the same job and print the allocating stack.
// guard_self_test() proves the guard live (a deliberate malloc and new are seen).
//
// Defines global functions: include from exactly one translation unit.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
#define FG_FUZZ_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FG_FUZZ_UNDER_ASAN 1
#endif
#endif
#ifndef FG_FUZZ_UNDER_ASAN
#define FG_FUZZ_UNDER_ASAN 0
#endif

namespace fg_fuzz {
namespace {

// Per thread: libFuzzer's own threads (the RSS watcher) may allocate at any time.
thread_local bool t_armed = false;
thread_local bool t_probe = false;  // self test: count instead of aborting
thread_local uint32_t t_probe_hits = 0;

void say(const char* s) {
  const ssize_t r = ::write(2, s, std::strlen(s));
  (void)r;
}

#if FG_FUZZ_UNDER_ASAN
extern "C" void __sanitizer_print_stack_trace();
#endif

// Called from inside the allocator: nothing here may allocate.
void heap_use(const char* what) {
  if (t_probe) {
    ++t_probe_hits;
    return;
  }
  t_armed = false;
  say("\n==fg-no-heap== FINDING: ");
  say(what);
  say(" while the no-heap guard was armed (inside fg::Planner configure/reset/add_*/plan/"
      "analyze_view): the core must not use the heap\n");
#if FG_FUZZ_UNDER_ASAN
  __sanitizer_print_stack_trace();
#endif
  std::abort();
}

}  // namespace
}  // namespace fg_fuzz

#if FG_FUZZ_UNDER_ASAN

extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*, size_t),
                                                         void (*free_hook)(const volatile void*));

namespace fg_fuzz {
namespace {
void malloc_hook(const volatile void*, size_t) {
  if (t_armed) heap_use("heap allocation (malloc / new)");
}
void free_hook(const volatile void* p) {
  if (t_armed && p != nullptr) heap_use("heap free (free / delete)");
}
const int g_hooks_installed = __sanitizer_install_malloc_and_free_hooks(malloc_hook, free_hook);
}  // namespace
}  // namespace fg_fuzz

#else  // !FG_FUZZ_UNDER_ASAN: replace the allocation functions (tests/unit/test_no_heap.cpp)

extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void __libc_free(void*);
void* __libc_memalign(size_t, size_t);

void* malloc(size_t n) {
  if (fg_fuzz::t_armed) fg_fuzz::heap_use("malloc");
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t s) {
  if (fg_fuzz::t_armed) fg_fuzz::heap_use("calloc");
  return __libc_calloc(n, s);
}
void* realloc(void* p, size_t n) {
  if (fg_fuzz::t_armed) fg_fuzz::heap_use("realloc");
  return __libc_realloc(p, n);
}
void free(void* p) {
  if (fg_fuzz::t_armed && p != nullptr) fg_fuzz::heap_use("free");
  __libc_free(p);
}
void* memalign(size_t a, size_t n) {
  if (fg_fuzz::t_armed) fg_fuzz::heap_use("memalign");
  return __libc_memalign(a, n);
}
void* aligned_alloc(size_t a, size_t n) {
  if (fg_fuzz::t_armed) fg_fuzz::heap_use("aligned_alloc");
  return __libc_memalign(a, n);
}
int posix_memalign(void** out, size_t a, size_t n) {
  if (fg_fuzz::t_armed) fg_fuzz::heap_use("posix_memalign");
  if (a < sizeof(void*) || (a & (a - 1)) != 0) return 22;  // EINVAL
  void* p = __libc_memalign(a, n);
  if (p == nullptr && n != 0) return 12;  // ENOMEM
  *out = p;
  return 0;
}
}  // extern "C"

namespace fg_fuzz {
namespace {
void* guarded_new(size_t n) {
  if (t_armed) heap_use("operator new");
  return __libc_malloc(n == 0 ? 1 : n);
}
void* guarded_new_aligned(size_t n, std::align_val_t a) {
  if (t_armed) heap_use("aligned operator new");
  size_t al = static_cast<size_t>(a);
  if (al < sizeof(void*)) al = sizeof(void*);
  return __libc_memalign(al, n == 0 ? 1 : n);
}
void guarded_delete(void* p) {
  if (p == nullptr) return;
  if (t_armed) heap_use("operator delete");
  __libc_free(p);
}
}  // namespace
}  // namespace fg_fuzz

void* operator new(size_t n) {
  void* p = fg_fuzz::guarded_new(n);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](size_t n) {
  void* p = fg_fuzz::guarded_new(n);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new(size_t n, const std::nothrow_t&) noexcept { return fg_fuzz::guarded_new(n); }
void* operator new[](size_t n, const std::nothrow_t&) noexcept { return fg_fuzz::guarded_new(n); }
void* operator new(size_t n, std::align_val_t a) {
  void* p = fg_fuzz::guarded_new_aligned(n, a);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](size_t n, std::align_val_t a) {
  void* p = fg_fuzz::guarded_new_aligned(n, a);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new(size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return fg_fuzz::guarded_new_aligned(n, a);
}
void* operator new[](size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return fg_fuzz::guarded_new_aligned(n, a);
}
void operator delete(void* p) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete[](void* p) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete(void* p, size_t) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete[](void* p, size_t) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete(void* p, std::align_val_t) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete[](void* p, std::align_val_t) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { fg_fuzz::guarded_delete(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { fg_fuzz::guarded_delete(p); }

#endif  // FG_FUZZ_UNDER_ASAN

namespace fg_fuzz {
namespace {

void* volatile g_sink = nullptr;  // keeps the self test's allocations observable

inline void arm() {
  __atomic_signal_fence(__ATOMIC_SEQ_CST);
  t_armed = true;
  __atomic_signal_fence(__ATOMIC_SEQ_CST);
}

inline void disarm() {
  __atomic_signal_fence(__ATOMIC_SEQ_CST);
  t_armed = false;
  __atomic_signal_fence(__ATOMIC_SEQ_CST);
}

//! The positive control: a malloc, a free, a new and a delete made while armed in probe
//! mode must all be seen; otherwise the guard is dead and the target aborts.
inline void guard_self_test() {
#if FG_FUZZ_UNDER_ASAN
  if (g_hooks_installed == 0) {
    say("==fg-no-heap== __sanitizer_install_malloc_and_free_hooks refused the hooks\n");
    std::abort();
  }
#endif
  t_probe = true;
  t_probe_hits = 0;
  arm();
  g_sink = std::malloc(16);
  std::free(g_sink);
  g_sink = new int(7);
  delete static_cast<int*>(g_sink);
  disarm();
  t_probe = false;
  g_sink = nullptr;
  if (t_probe_hits < 4) {
    say("==fg-no-heap== the heap guard is not live (a deliberate allocation went unseen)\n");
    std::abort();
  }
}

}  // namespace
}  // namespace fg_fuzz
