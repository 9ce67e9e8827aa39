// Host-only: LZF (the liblzf format that PCL uses for DATA binary_compressed).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fg::host::lzf {

//! Decompresses `in` into exactly `out_size` bytes at `out`. Strict: a literal run or a
//! back-reference that goes past the end of the input, a back-reference before the start
//! of the output, output that would overflow `out_size`, or output shorter than
//! `out_size` are errors. Returns false and sets `error` (no file name) on failure.
[[nodiscard]] bool decompress(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_size, std::string& error);

//! Compresses `in` into a valid LZF stream (hash-based greedy matcher, like liblzf).
//! Never fails; the worst case is literal runs only (n + ceil(n / 32) bytes).
std::vector<uint8_t> compress(const uint8_t* in, size_t in_size);

//! Largest output a stream of `in_size` bytes can decode to (a 3-byte back-reference
//! yields at most 264 bytes), for rejecting absurd declared sizes before allocating.
inline uint64_t max_decompressed_size(uint64_t in_size) { return in_size / 3 * 264 + 264; }

}  // namespace fg::host::lzf
