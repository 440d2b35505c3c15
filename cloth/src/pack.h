#pragma once
// Fixed-width SIMD packs on the compiler's vector extensions (GCC and Clang): 32 bytes, that is 8
// floats or 4 doubles, with the arithmetic operators lane by lane, comparisons giving a lane mask,
// and `mask ? a : b` selecting per lane. Each lane rounds exactly as the same scalar operation
// (the library is built without contraction, simd.h), so a kernel written once as a template on
// V = Pack<T> or V = T gives the same bits for its full packs and for its scalar tail. Unlike an
// auto-vectorized loop over arrays, a pack keeps a kernel's accumulators in registers while it
// walks a runtime list of operands (the stencil's spring families).

#include <cstring>

#include "simd.h"

namespace cloth {

template <class T>
struct PackOf {
    typedef T type __attribute__((vector_size(32)));
};
template <class T>
using Pack = typename PackOf<T>::type;
template <class T>
constexpr int kLanes = int(32 / sizeof(T));

// Unaligned load and store of one V (a pack or a scalar) at p.
template <class V, class T>
CLOTH_INLINE inline V load(const T* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <class V, class T>
CLOTH_INLINE inline void store(T* p, const V& v) {
    std::memcpy(p, &v, sizeof v);
}

}  // namespace cloth
