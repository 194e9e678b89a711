// HOS_CPU_CLONES before a hot function compiles it twice, for the x86-64
// baseline and for x86-64-v3 (AVX2, FMA), and picks one when the program
// loads, so one binary runs on any x86-64 and uses the wider vectors where
// the CPU has them. Only what the marked function inlines is compiled with
// it: HOS_INLINED_INTO_CLONES marks the hot callees that must be. Results
// may differ in the last bits between the two (FMA rounds once). Elsewhere
// (other compilers or CPUs) the marks are empty.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define HOS_CPU_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#define HOS_INLINED_INTO_CLONES __attribute__((always_inline))
#else
#define HOS_CPU_CLONES
#define HOS_INLINED_INTO_CLONES
#endif
