#pragma once
// How the vectorized kernels (kangcho/stencil.cpp, multigrid.cpp) ask the compiler for SIMD.

// Kernels are cloned for x86-64-v4 (AVX-512: 32 vector registers, so a kernel's accumulators need
// not spill), x86-64-v3 (AVX2, FMA) and the baseline; the dynamic loader picks one per CPU. Clang
// and other targets get the baseline only. The library is built with -ffp-contract=off, so every
// clone rounds alike and gives the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define CLOTH_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define CLOTH_SIMD_CLONES
#endif
// Loops whose arrays do not overlap (GCC does not reliably honour restrict on local pointers).
// Clang builds (the fuzzer) get no hint: its forcing pragma turns a loop it cannot vectorize,
// as under the sanitizers, into a warning, and the result is the same either way.
#if defined(__GNUC__) && !defined(__clang__)
#define CLOTH_IVDEP _Pragma("GCC ivdep")
#else
#define CLOTH_IVDEP
#endif
// Helpers must inline into every clone (GCC does not inline across target options otherwise).
#define CLOTH_INLINE __attribute__((always_inline))

namespace cloth {
// Rows per tile of the vectorized kernels: their per-tile accumulators stay in L1.
constexpr int kTile = 128;
}  // namespace cloth
