#include "lzf.hpp"

#include <algorithm>
#include <cstring>

namespace fg::host::lzf {

namespace {
constexpr size_t kMaxLiteral = 32;   // ctrl 0..31 -> 1..32 literal bytes
constexpr size_t kMaxOffset = 8192;  // 13-bit offset + 1
constexpr size_t kMaxMatch = 264;    // 7 + 255 + 2
constexpr size_t kHashBits = 14;
}  // namespace

bool decompress(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_size, std::string& error) {
  size_t ip = 0;
  size_t op = 0;
  while (ip < in_size) {
    const unsigned ctrl = in[ip++];
    if (ctrl < 32) {
      const size_t len = ctrl + 1;
      if (len > in_size - ip) {
        error = "LZF stream is corrupt: a literal run of " + std::to_string(len) + " bytes at input offset " +
                std::to_string(ip - 1) + " runs past the end of the input";
        return false;
      }
      if (len > out_size - op) {
        error =
            "LZF stream is corrupt: output overflow (more than the declared " + std::to_string(out_size) + " bytes)";
        return false;
      }
      // Fast path: a fixed 32-byte copy (inlined as vector moves) when both buffers
      // have the slack; the bytes past len are overwritten by what follows.
      if (ip + kMaxLiteral <= in_size && op + kMaxLiteral <= out_size) {
        std::memcpy(out + op, in + ip, kMaxLiteral);
      } else {
        std::memcpy(out + op, in + ip, len);
      }
      ip += len;
      op += len;
    } else {
      size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_size) {
          error = "LZF stream is corrupt: a back-reference is cut off at the end of the input";
          return false;
        }
        len += in[ip++];
      }
      if (ip >= in_size) {
        error = "LZF stream is corrupt: a back-reference is cut off at the end of the input";
        return false;
      }
      const size_t dist = ((static_cast<size_t>(ctrl & 0x1f) << 8) | in[ip++]) + 1;
      len += 2;
      if (dist > op) {
        error = "LZF stream is corrupt: a back-reference points " + std::to_string(dist) + " bytes back but only " +
                std::to_string(op) + " bytes were decoded (before the start of the output)";
        return false;
      }
      if (len > out_size - op) {
        error =
            "LZF stream is corrupt: output overflow (more than the declared " + std::to_string(out_size) + " bytes)";
        return false;
      }
      const uint8_t* ref = out + op - dist;
      uint8_t* dst = out + op;
      if (op + len + 16 <= out_size) {
        // Chunked copies (the bytes past len are overwritten by what follows). An
        // 8-byte chunk whose source lies wholly before it (distance 8 or more) copies
        // the run, its overlap included; most matches are 5-7 bytes, so two chunks
        // without a loop test are the rule. A shorter distance repeats a pattern
        // (4: a repeated float, runs of NaN pixels): its first 8 bytes go byte by
        // byte, after which the run repeats at a distance of 8 or more.
        uint64_t v;
        if (dist < 8) {
          for (size_t k = 0; k < 8; ++k) dst[k] = ref[k];
          ref = dst - dist * ((8 + dist - 1) / dist);  // the same phase, 8 to 14 back
        } else {
          std::memcpy(&v, ref, 8);
          std::memcpy(dst, &v, 8);
        }
        std::memcpy(&v, ref + 8, 8);
        std::memcpy(dst + 8, &v, 8);
        for (size_t k = 16; k < len; k += 8) {
          std::memcpy(&v, ref + k, 8);
          std::memcpy(dst + k, &v, 8);
        }
      } else if (dist >= len) {
        std::memcpy(dst, ref, len);
      } else {
        for (size_t k = 0; k < len; ++k) dst[k] = ref[k];  // overlapping run
      }
      op += len;
    }
  }
  if (op != out_size) {
    error = "LZF stream is truncated: it decodes to " + std::to_string(op) + " bytes but " + std::to_string(out_size) +
            " were declared";
    return false;
  }
  return true;
}

std::vector<uint8_t> compress(const uint8_t* in, size_t n) {
  std::vector<uint8_t> out;
  out.reserve(n + n / kMaxLiteral + 16);
  auto emit_literals = [&](size_t from, size_t to) {
    while (from < to) {
      const size_t len = std::min(kMaxLiteral, to - from);
      out.push_back(static_cast<uint8_t>(len - 1));
      out.insert(out.end(), in + from, in + from + len);
      from += len;
    }
  };
  std::vector<int64_t> table(size_t{1} << kHashBits, -1);
  auto hash = [&](size_t i) {
    const uint32_t v = (uint32_t{in[i]} << 16) | (uint32_t{in[i + 1]} << 8) | in[i + 2];
    return static_cast<size_t>((v * 2654435761u) >> (32 - kHashBits));
  };
  size_t lit_start = 0;
  size_t i = 0;
  while (n >= 3 && i + 2 < n) {
    const size_t h = hash(i);
    const int64_t ref_signed = table[h];
    table[h] = static_cast<int64_t>(i);
    if (ref_signed >= 0) {
      const size_t ref = static_cast<size_t>(ref_signed);
      const size_t dist = i - ref;
      if (dist >= 1 && dist <= kMaxOffset && in[ref] == in[i] && in[ref + 1] == in[i + 1] && in[ref + 2] == in[i + 2]) {
        const size_t max_len = std::min(kMaxMatch, n - i);
        size_t len = 3;
        while (len < max_len && in[ref + len] == in[i + len]) ++len;
        emit_literals(lit_start, i);
        const size_t off = dist - 1;
        const size_t l = len - 2;
        if (l < 7) {
          out.push_back(static_cast<uint8_t>((l << 5) | (off >> 8)));
        } else {
          out.push_back(static_cast<uint8_t>((7 << 5) | (off >> 8)));
          out.push_back(static_cast<uint8_t>(l - 7));
        }
        out.push_back(static_cast<uint8_t>(off & 0xff));
        // Index a couple of positions inside the match so later data can refer to it.
        const size_t end = i + len;
        for (size_t k = i + 1; k < end && k + 2 < n && k < i + 3; ++k) {
          table[hash(k)] = static_cast<int64_t>(k);
        }
        i = end;
        lit_start = i;
        continue;
      }
    }
    ++i;
  }
  emit_literals(lit_start, n);
  return out;
}

}  // namespace fg::host::lzf
