#pragma once
/// VISCERA_TARGET_CLONES(isa): GCC's target_clones(isa, "default") on a hot function: an ifunc
/// picks the clone for the CPU at load time. Only with GCC on x86-64 with ELF and glibc (ifunc
/// dispatch), and left out under every sanitizer: their runtimes are not up when the loader
/// calls an ifunc's resolver (a TSan build crashed there before main), and their builds need no
/// speed. VISCERA_SANITIZED is CMake's mark of an ASan/UBSan or TSan build.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__ELF__) &&   \
    defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__) && \
    !defined(VISCERA_SANITIZED)
#define VISCERA_TARGET_CLONES(isa) __attribute__((target_clones(isa, "default")))
#else
#define VISCERA_TARGET_CLONES(isa)
#endif
