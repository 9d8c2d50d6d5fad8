/*
 * SINTER_CLONES: a hot function compiled for the baseline x86-64, for AVX2 and for AVX-512
 * (F), the copy picked once at load time from the CPU (GCC's target_clones, Linux x86-64
 * only), so the default build runs on any x86-64 machine and uses wider vectors where there
 * are some. No copy contracts a * b + c into a fused multiply-add (-std=c11: fp-contract off;
 * none is in the objects), and every lane does its own IEEE operations, so all give the same
 * bits (RESULTS.md, session 18; .ci/run compares three scenes' outputs with a build without
 * the copies). The AVX-512 copy: the 8k and 64k packed beds' force phase on one thread 1.5 %
 * faster at the best of 10-12 interleaved runs, 8-10 % at the median, on session 18's Intel
 * VM. Empty elsewhere or with SINTER_NO_CLONES.
 */
#ifndef SINTER_CLONES_H
#define SINTER_CLONES_H

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) &&       \
    !defined(SINTER_NO_CLONES)
#define SINTER_CLONES __attribute__((target_clones("default", "avx2", "avx512f")))
#else
#define SINTER_CLONES
#endif

#endif
