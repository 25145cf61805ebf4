#pragma once

// AGV_VECTOR_CLONES before a function with long arithmetic loops: GCC builds it twice, for AVX2
// and for the baseline x86-64 (SSE2), and picks one when the program loads (target_clones). The
// arithmetic is the same in both (no fused multiply-add), so results are bit-identical on any
// machine; AVX2 only takes twice the values per instruction. Left out where it cannot apply
// (other compilers and processors) and under the address and thread sanitizers, whose run-time
// set-up the load-time choice would run before.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define AGV_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define AGV_VECTOR_CLONES
#endif
