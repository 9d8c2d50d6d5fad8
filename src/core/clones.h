/*
 * SINTER_CLONES: a hot function compiled for the baseline x86-64 and for AVX2, the copy
 * picked once at load time from the CPU (GCC's target_clones, Linux x86-64 only), so the
 * default build runs on any x86-64 machine and uses wider vectors where there are some.
 * Neither copy contracts a * b + c into a fused multiply-add (-std=c11: fp-contract off,
 * and "avx2" does not enable FMA), so both give the same bits. Empty elsewhere or with
 * SINTER_NO_CLONES.
 */
#ifndef SINTER_CLONES_H
#define SINTER_CLONES_H

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) &&       \
    !defined(SINTER_NO_CLONES)
#define SINTER_CLONES __attribute__((target_clones("default", "avx2")))
#else
#define SINTER_CLONES
#endif

#endif
