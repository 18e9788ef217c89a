#pragma once

// SKRED_INLINE marks the small functions of the time-step loops (shape functions, gathers and
// scatters, stress updates) that GCC must inline: `[[gnu::always_inline]] inline`. Under the
// sanitizers (CMake option SKRED_SANITIZE, which defines SKRED_NO_FORCE_INLINE) it is plain
// `inline`: forced inlining of the instrumented code makes one solver file take many minutes
// and gigabytes to compile, and the compiler still inlines what it finds worth it.
#ifdef SKRED_NO_FORCE_INLINE
#define SKRED_INLINE inline
#else
#define SKRED_INLINE [[gnu::always_inline]] inline
#endif
