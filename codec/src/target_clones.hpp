#pragma once
// Hot loops get an AVX2 clone beside the default one on x86-64 (chosen at load time);
// other targets (WebAssembly: web/wasm, ARM) have no function multiversioning and build
// the default alone.  Same integer arithmetic either way.
#if defined(__x86_64__) && !defined(__EMSCRIPTEN__)
#define FOLDCAST_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FOLDCAST_AVX2_CLONES
#endif
