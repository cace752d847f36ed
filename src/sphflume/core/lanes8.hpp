// Eight float lanes as a GCC vector type, and the loads of small per-particle records by index into them.
//
// A pass over kept pair rows (schemes/dual_pairs.cpp) reads each partner's state through its index. Written lane by
// lane, GCC 12 loads such values one float at a time and inserts each into its vector (3 instructions a value), or,
// with a signed index, uses the hardware gather, 1.4x slower again on AMD EPYC. Here a partner's values lie together
// in one record (2 or 4 floats) and eight records are loaded whole and transposed into lanes with shuffles: about a
// third of the instructions. The types are GCC's vector extensions: the same code on x86-64-v3 (AVX2) and AVX-512
// builds (32-byte vectors on both), and the arithmetic is lane-wise IEEE float, as the scalar lanes' was.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>

// (A build without AVX, SPHFLUME_NATIVE=OFF, warns that these 32-byte vectors are passed differently from an AVX
// build's: -Wpsabi. The functions are inline and never cross a library's boundary: the warning is silenced here.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace sph::lanes8 {

using v8f = float __attribute__((vector_size(32)));
using v4f = float __attribute__((vector_size(16)));
using v2f = float __attribute__((vector_size(8)));
using v8i = std::int32_t __attribute__((vector_size(32)));

[[gnu::always_inline]] inline v8f load(const float* p) {
  v8f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
[[gnu::always_inline]] inline void store(float* p, v8f v) { std::memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline v8f splat(float x) { return v8f{x, x, x, x, x, x, x, x}; }
/// |x| by its sign bit (exact, -0 to +0, as std::abs).
[[gnu::always_inline]] inline v8f abs(v8f x) {
  return reinterpret_cast<v8f>(reinterpret_cast<v8i>(x) & std::int32_t(0x7fffffff));
}

/// The first two floats {a, b} of the records rec + stride j[k], k = 0..7, as two vectors of lanes.
[[gnu::always_inline]] inline void gather2(const float* __restrict rec, std::size_t stride, const std::uint32_t* __restrict j,
                                           v8f& a, v8f& b) {
  v2f r[8];
  for (int k = 0; k < 8; ++k) std::memcpy(&r[k], rec + stride * j[k], sizeof(v2f));
  const v4f q01 = __builtin_shufflevector(r[0], r[1], 0, 1, 2, 3), q23 = __builtin_shufflevector(r[2], r[3], 0, 1, 2, 3);
  const v4f q45 = __builtin_shufflevector(r[4], r[5], 0, 1, 2, 3), q67 = __builtin_shufflevector(r[6], r[7], 0, 1, 2, 3);
  const v8f x = __builtin_shufflevector(q01, q45, 0, 1, 2, 3, 4, 5, 6, 7);  // a0 b0 a1 b1 | a4 b4 a5 b5
  const v8f y = __builtin_shufflevector(q23, q67, 0, 1, 2, 3, 4, 5, 6, 7);  // a2 b2 a3 b3 | a6 b6 a7 b7
  a = __builtin_shufflevector(x, y, 0, 2, 8, 10, 4, 6, 12, 14);
  b = __builtin_shufflevector(x, y, 1, 3, 9, 11, 5, 7, 13, 15);
}

/// The four floats {a, b, c, d} of the records rec + 4 j[k], k = 0..7, as four vectors of lanes.
[[gnu::always_inline]] inline void gather4(const float* __restrict rec, const std::uint32_t* __restrict j, v8f& a, v8f& b,
                                           v8f& c, v8f& d) {
  v4f r[8];
  for (int k = 0; k < 8; ++k) std::memcpy(&r[k], rec + 4 * std::size_t(j[k]), sizeof(v4f));
  const v8f r04 = __builtin_shufflevector(r[0], r[4], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8f r15 = __builtin_shufflevector(r[1], r[5], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8f r26 = __builtin_shufflevector(r[2], r[6], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8f r37 = __builtin_shufflevector(r[3], r[7], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8f t0 = __builtin_shufflevector(r04, r15, 0, 8, 1, 9, 4, 12, 5, 13);    // a0 a1 b0 b1 | a4 a5 b4 b5
  const v8f t1 = __builtin_shufflevector(r04, r15, 2, 10, 3, 11, 6, 14, 7, 15);  // c0 c1 d0 d1 | c4 c5 d4 d5
  const v8f t2 = __builtin_shufflevector(r26, r37, 0, 8, 1, 9, 4, 12, 5, 13);    // a2 a3 b2 b3 | a6 a7 b6 b7
  const v8f t3 = __builtin_shufflevector(r26, r37, 2, 10, 3, 11, 6, 14, 7, 15);  // c2 c3 d2 d3 | c6 c7 d6 d7
  a = __builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13);
  b = __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15);
  c = __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13);
  d = __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15);
}

}  // namespace sph::lanes8

#pragma GCC diagnostic pop
