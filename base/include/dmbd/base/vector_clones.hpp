#pragma once
// DMBD_VECTOR_CLONES before a function whose loops the compiler vectorises: GCC on
// x86-64 then builds it twice, for AVX2 and for the baseline (SSE2), and the loader
// picks the one the processor runs (an ifunc). Only for loops whose results do not
// depend on the lanes: each element's arithmetic is the same in both (no FMA: the
// project compiles with -ffp-contract=off), so both clones give the same bits.
// Used where a loop dominates: blocks/ (Bode), base/dense_cholesky.cpp (the plant
// step's and the whole-body QP's Cholesky factors).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define DMBD_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define DMBD_VECTOR_CLONES
#endif
