// Fingerprint: 64-bit FNV-1a over 64-bit words, for detecting changed inputs and damaged files
// (not a cryptographic hash: it guards against accidents, not against an adversary).
// Word-wise, so that hashing costs about a millisecond per 10^6 values.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace fretbem {

class Fingerprint {
 public:
  void add(double x) {
    std::uint64_t w;
    std::memcpy(&w, &x, sizeof w);
    add_word(w);
  }
  void add_word(std::uint64_t w) { h_ = (h_ ^ w) * 1099511628211ull; }
  /// Bytes in 8-byte little-endian words, the tail zero-padded, then the length (so that
  /// trailing zero bytes change the value).
  void add_bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, p + i, 8);
      add_word(w);
    }
    std::uint64_t tail = 0;
    std::memcpy(&tail, p + i, n - i);
    add_word(tail);
    add_word(n);
  }
  std::uint64_t value() const { return h_; }
  /// 16 lowercase hex digits.
  std::string hex() const {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
    return buf;
  }

 private:
  std::uint64_t h_ = 14695981039346656037ull;
};

}  // namespace fretbem
