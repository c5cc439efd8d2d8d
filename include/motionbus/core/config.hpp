// motionbus — compile-time configuration.
//
// Every macro here may be defined by the user before including any motionbus header
// (or on the compiler command line). Defaults suit a hosted build and a Cortex-M4 alike.
#ifndef MOTIONBUS_CORE_CONFIG_HPP
#define MOTIONBUS_CORE_CONFIG_HPP

#if __cplusplus < 201703L && !(defined(_MSVC_LANG) && _MSVC_LANG >= 201703L)
#error "motionbus needs C++17 or later"
#endif

#if defined(__has_include)
#if __has_include(<version>)
#include <version>
#endif
#endif

/// Size of the lookup tables used by the named CRCs when the caller does not choose one:
/// 256 (256 entries per CRC), 16 (a nibble table) or 0 (bitwise, no table); on hosts 1024 or
/// 2048 (slice-by-4 / slice-by-8 for reflected CRCs such as CRC-16/MODBUS; others use 256).
/// Tables always live in constant (read-only) storage.
#ifndef MOTIONBUS_CRC_DEFAULT_TABLE
#define MOTIONBUS_CRC_DEFAULT_TABLE 256
#endif

#if MOTIONBUS_CRC_DEFAULT_TABLE != 256 && MOTIONBUS_CRC_DEFAULT_TABLE != 16 && \
    MOTIONBUS_CRC_DEFAULT_TABLE != 0 && MOTIONBUS_CRC_DEFAULT_TABLE != 1024 && \
    MOTIONBUS_CRC_DEFAULT_TABLE != 2048
#error "MOTIONBUS_CRC_DEFAULT_TABLE must be 0, 16, 256, 1024 or 2048"
#endif

/// Byte views are std::span under C++20 (when the library provides it), and a minimal
/// equivalent under C++17. Define MOTIONBUS_NO_STD_SPAN to force the minimal view.
#if !defined(MOTIONBUS_NO_STD_SPAN) && defined(__cpp_lib_span) && __cpp_lib_span >= 202002L
#define MOTIONBUS_HAS_STD_SPAN 1
#else
#define MOTIONBUS_HAS_STD_SPAN 0
#endif

/// Marks the rare paths of a hot decoder (error reporting, uncommon layouts) so that the
/// common path stays small enough for the compiler to inline at the call site.
#ifndef MOTIONBUS_COLD
#if defined(__GNUC__) || defined(__clang__)
#define MOTIONBUS_COLD __attribute__((noinline, cold))
#elif defined(_MSC_VER)
#define MOTIONBUS_COLD __declspec(noinline)
#else
#define MOTIONBUS_COLD
#endif
#endif

/// Keeps a decision out of line, so that the per-byte path inlined at a stream object's call
/// site stays a leaf that ends in a tail call (the receiver's and the framer's decide_byte).
#ifndef MOTIONBUS_NOINLINE
#if defined(__GNUC__) || defined(__clang__)
#define MOTIONBUS_NOINLINE __attribute__((noinline))
#elif defined(_MSC_VER)
#define MOTIONBUS_NOINLINE __declspec(noinline)
#else
#define MOTIONBUS_NOINLINE
#endif
#endif

/// Forces a short hot function (a few dozen instructions at most) into its callers. Policy
/// (docs/design.md, "Performance policy"): only where the meter shows it pays, so only with
/// GCC and Clang (the compilers the meter measures), never in unoptimised builds (debuggers
/// step through calls, and -O0 inlines nothing else). Each use says why in one line.
/// This and MOTIONBUS_COLD may be defined empty to leave every choice to the compiler.
#ifndef MOTIONBUS_INLINE
#if (defined(__GNUC__) || defined(__clang__)) && defined(__OPTIMIZE__)
#define MOTIONBUS_INLINE inline __attribute__((always_inline))
#else
#define MOTIONBUS_INLINE inline
#endif
#endif

/// True where the compiler sees `x` as a compile-time constant (after inlining), for code
/// that specialises a step only when it then folds to a few instructions (a BiSS-C CRC6 of a
/// fixed layout); 0 elsewhere. Define it as 0 to keep every such step in the shared kernels.
#ifndef MOTIONBUS_CONSTANT_P
#if defined(__GNUC__) || defined(__clang__)
#define MOTIONBUS_CONSTANT_P(x) __builtin_constant_p(x)
#else
#define MOTIONBUS_CONSTANT_P(x) 0
#endif
#endif

/// True while a constant expression is evaluated, where the compiler can tell (GCC 9, Clang 9,
/// MSVC 19.25 and later); else true, so that code taking the constexpr-friendly branch on it
/// stays correct everywhere.
#ifndef MOTIONBUS_CONSTANT_EVALUATED
#if defined(__GNUC__) || defined(__clang__) || (defined(_MSC_VER) && _MSC_VER >= 1925)
#define MOTIONBUS_CONSTANT_EVALUATED() __builtin_is_constant_evaluated()
#else
#define MOTIONBUS_CONSTANT_EVALUATED() true
#endif
#endif

/// Selects the smallest form of the decoders that have two (the T-format response decoder,
/// the BiSS-C frame decoder): 1 for size (one table-driven path for every layout), 0 for
/// speed (hot layouts inlined and unrolled). Both forms return identical results, which the
/// tests check over random input. Follows -Os (__OPTIMIZE_SIZE__) unless defined; a program
/// built with mixed -O levels should define it once for all its translation units.
#ifndef MOTIONBUS_SMALL_CODE
#if defined(__OPTIMIZE_SIZE__)
#define MOTIONBUS_SMALL_CODE 1
#else
#define MOTIONBUS_SMALL_CODE 0
#endif
#endif

/// Asks the compiler to unroll the next loop up to `n` times (even at -Os).
#if defined(__clang__)
#define MOTIONBUS_PRAGMA(x) _Pragma(#x)
#define MOTIONBUS_UNROLL(n) MOTIONBUS_PRAGMA(unroll n)
#elif defined(__GNUC__)
#define MOTIONBUS_PRAGMA(x) _Pragma(#x)
#define MOTIONBUS_UNROLL(n) MOTIONBUS_PRAGMA(GCC unroll n)
#else
#define MOTIONBUS_UNROLL(n)
#endif

/// 1 where the core counts leading zeros in one instruction (Cortex-M3 and up, x86, AArch64,
/// RISC-V with Zbb): code may then prefer 32-bit counts to 64-bit ones. Cores without it
/// (Cortex-M0+, rv32imc) call a library routine either way.
#ifndef MOTIONBUS_FAST_CLZ
#if defined(__ARM_FEATURE_CLZ) || defined(__x86_64__) || defined(__i386__) || \
    defined(__aarch64__) || defined(__riscv_zbb)
#define MOTIONBUS_FAST_CLZ 1
#else
#define MOTIONBUS_FAST_CLZ 0
#endif
#endif

#endif  // MOTIONBUS_CORE_CONFIG_HPP
