#include "big_buffer.hpp"

#include <cstdint>
#include <cstdlib>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace fg::host {

namespace {
constexpr size_t kHugePage = size_t{2} << 20;
}

void* big_allocate(size_t bytes) {
  if (bytes < kHugePage) {
    void* p = std::malloc(bytes > 0 ? bytes : 1);
    if (p == nullptr) throw std::bad_alloc();
    return p;
  }
  // Rounded up to whole huge pages, so the advice covers the block's tail too (the
  // padding is address space only until touched).
  if (bytes > SIZE_MAX - kHugePage) throw std::bad_alloc();
  const size_t rounded = (bytes + kHugePage - 1) & ~(kHugePage - 1);
  void* p = nullptr;
  if (posix_memalign(&p, kHugePage, rounded) != 0 || p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // A hint; refused or unsupported changes nothing.
  (void)madvise(p, rounded, MADV_HUGEPAGE);
#endif
  return p;
}

void big_deallocate(void* p) noexcept { std::free(p); }

}  // namespace fg::host
