#pragma once
/// VISCERA_AVX_CLONE: GCC's target_clones("avx", "default") on a hot function of the mechanics.
/// Products and sums only, never fused (-ffp-contract=off, src/mechanics/CMakeLists.txt) and
/// never reassociated (no -ffast-math): the AVX clone gives the baseline one's numbers bit for
/// bit, only with wider registers. Needs GCC on x86-64 with ELF and glibc (ifunc dispatch), and
/// is left out under every sanitizer (their builds need no speed; VISCERA_SANITIZED is CMake's
/// mark of an ASan/UBSan or TSan build).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__ELF__) &&   \
    defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__) && \
    !defined(VISCERA_SANITIZED)
#define VISCERA_AVX_CLONE __attribute__((target_clones("avx", "default")))
#else
#define VISCERA_AVX_CLONE
#endif
