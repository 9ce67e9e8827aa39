// Host-only: the allocator of the readers' big buffers (a file's bytes, a decompressed
// block, a cloud's coordinates). Two costs of a plain std::vector go away:
// - resize() default-initialises, so bytes about to be overwritten are not zeroed first;
// - blocks of 2 MiB and more are 2 MiB aligned and advised as transparent huge pages
//   where Linux offers them: one page fault per 2 MiB instead of one per 4 KiB (a
//   640x480 cloud is 3.7 MB; on this VM the faults of the 4 KiB pages cost more than
//   decompressing it). Without the kernel's consent the advice is a no-op.
#pragma once
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace fg::host {

void* big_allocate(size_t bytes);  // throws std::bad_alloc
void big_deallocate(void* p) noexcept;

template <class T>
struct BigAllocator {
  using value_type = T;
  BigAllocator() = default;
  template <class U>
  BigAllocator(const BigAllocator<U>&) noexcept {}
  T* allocate(size_t n) {
    if (n > SIZE_MAX / sizeof(T)) throw std::bad_alloc();
    return static_cast<T*>(big_allocate(n * sizeof(T)));
  }
  void deallocate(T* p, size_t) noexcept { big_deallocate(p); }
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;  // default-initialise: no zeroing
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
  template <class U>
  bool operator==(const BigAllocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const BigAllocator<U>&) const noexcept {
    return false;
  }
};

template <class T>
using BigBuffer = std::vector<T, BigAllocator<T>>;

}  // namespace fg::host
