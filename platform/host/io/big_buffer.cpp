#include "big_buffer.hpp"

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
  void* p = nullptr;
  if (posix_memalign(&p, kHugePage, bytes) != 0 || p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // A hint on the whole huge pages of the block; refused or unsupported changes nothing.
  (void)madvise(p, bytes & ~(kHugePage - 1), MADV_HUGEPAGE);
#endif
  return p;
}

void big_deallocate(void* p) noexcept { std::free(p); }

}  // namespace fg::host
