// Fixed-capacity point buffers (the ETL shape): a size-erased base that algorithms
// take by reference, a version with its storage inside (capacity as a template
// parameter), and a version over caller memory. push() always checks capacity.
#pragma once
#include <cstdint>

#include "fg/core/status.hpp"
#include "fg/core/types.hpp"

namespace fg {

class PointSpan {
 public:
  uint32_t size() const { return size_; }
  uint32_t capacity() const { return capacity_; }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == capacity_; }
  void clear() { size_ = 0; }

  //! Appends p; capacity_exceeded (and no change) when full.
  [[nodiscard]] Status push(const Vec3& p) {
    if (size_ >= capacity_) return Status::capacity_exceeded;
    data_[size_++] = p;
    return Status::ok;
  }
  const Vec3& operator[](uint32_t i) const { return data_[i]; }
  Vec3& operator[](uint32_t i) { return data_[i]; }
  const Vec3* data() const { return data_; }
  Vec3* data() { return data_; }
  const Vec3* begin() const { return data_; }
  const Vec3* end() const { return data_ + size_; }

  PointSpan(const PointSpan&) = delete;
  PointSpan& operator=(const PointSpan&) = delete;

 protected:
  PointSpan(Vec3* data, uint32_t capacity) : data_(data), capacity_(capacity) {}
  ~PointSpan() = default;
  void rebind(Vec3* data, uint32_t capacity) {
    data_ = data;
    capacity_ = capacity;
    size_ = 0;
  }

 private:
  Vec3* data_;
  uint32_t capacity_;
  uint32_t size_ = 0;
};

//! Storage inside the object: PointBuffer<4096> pts; pts.push(p);
template <uint32_t N>
class PointBuffer final : public PointSpan {
  static_assert(N > 0, "a point buffer needs room for at least one point");

 public:
  PointBuffer() : PointSpan(storage_, N) {}
  PointBuffer(const PointBuffer&) = delete;
  PointBuffer& operator=(const PointBuffer&) = delete;

 private:
  Vec3 storage_[N];
};

//! Storage in caller memory (e.g. a firmware workspace).
class PointBufferExt final : public PointSpan {
 public:
  PointBufferExt(Vec3* memory, uint32_t capacity) : PointSpan(memory, memory != nullptr ? capacity : 0u) {}
};

}  // namespace fg
