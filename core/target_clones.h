// KOMA_TARGET_CLONES("avx2", "default"): GCC's and clang's function multiversioning
// (__attribute__((target_clones(...)))), one copy per instruction set, chosen by an ifunc
// resolver when the program is loaded. Every copy computes the same bits (the tests pin them).
//
// Under ThreadSanitizer the attribute is dropped and only the default copy is built: the
// resolver runs during relocation, before TSan's runtime is set up, and TSan's instrumentation
// of it crashed every test binary at start (clang 14). ASan and UBSan are unaffected.
#ifndef KOMA_CORE_TARGET_CLONES_H_
#define KOMA_CORE_TARGET_CLONES_H_

#if defined(__SANITIZE_THREAD__)
#define KOMA_THREAD_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define KOMA_THREAD_SANITIZER 1
#endif
#endif

#if defined(KOMA_THREAD_SANITIZER)
#define KOMA_TARGET_CLONES(...)
#else
#define KOMA_TARGET_CLONES(...) __attribute__((target_clones(__VA_ARGS__)))
#endif

#endif  // KOMA_CORE_TARGET_CLONES_H_
