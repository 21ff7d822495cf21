// Reading a libFuzzer input as a stream of small decisions, for the harnesses of
// tests/fuzz/. Past the end every read gives zeros, so any input decodes to something.
#ifndef SEICHE_FUZZ_INPUT_H
#define SEICHE_FUZZ_INPUT_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct fuzz_input {
    const uint8_t *data;
    size_t size;
} fuzz_input;

/// Copies n bytes (zeros past the end) into out.
static inline void fuzz_bytes(fuzz_input *in, void *out, size_t n)
{
    size_t k = n < in->size ? n : in->size;
    if (k) memcpy(out, in->data, k);
    if (n > k) memset((uint8_t *)out + k, 0, n - k);
    in->data += k;
    in->size -= k;
}

static inline uint8_t fuzz_u8(fuzz_input *in)
{
    uint8_t v;
    fuzz_bytes(in, &v, 1);
    return v;
}

static inline uint32_t fuzz_u32(fuzz_input *in)
{
    uint32_t v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

static inline bool fuzz_bool(fuzz_input *in) { return fuzz_u8(in) & 1; }

/// Numbers that break code: zeros, signs, NaN, infinities, extremes, denormals, the edges of
/// the documented ranges; else raw bits.
static inline double fuzz_double(fuzz_input *in)
{
    static const double table[] = {
        0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 10.0, 100.0, 1000.0, 1e5, 1e9, 2e9, 3e9, 4294967296.0, 1e18, 1e30, 1e38,
        3.5e38, 1e300, -1e300, 1e-300, 5e-324, 1e-45, 1.2e-38, 1e-30, 1e-9, 1e-6, 1e-4, 0.0005, 0.00050001, 0.001,
        0.0125, 0.025, 0.05, 0.1, 0.125, 0.2, 0.9999999, 1.0000001, 1.999999, 63.0, 64.0, 65.0, 99.5, 100.0001,
        -2147483648.0, 2147483647.0, 2147483648.0, NAN, -NAN, INFINITY, -INFINITY, 0.1 + 0.2, 1.0 / 3.0,
    };
    uint8_t how = fuzz_u8(in);
    if (how < 160) return table[how % (sizeof table / sizeof table[0])];
    if (how < 200) return (double)(int8_t)fuzz_u8(in);
    double v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

static inline float fuzz_float(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    if (how < 224) {
        double d = fuzz_double(in);
        // Out of float range gives an infinity (IEEE), not a C conversion of an overflow.
        return isnan(d) ? (float)d : fabs(d) > 3.4e38 ? (d > 0 ? INFINITY : -INFINITY) : (float)d;
    }
    float v;
    fuzz_bytes(in, &v, sizeof v);
    return v;
}

/// A buffer of exactly `size` bytes, so that ASan catches a write past it: for size 0, a
/// pointer just past a 1-byte block (ASan lets malloc(0) take one byte). Free with
/// fuzz_free_exact(buffer, size).
static inline char *fuzz_alloc_exact(size_t size)
{
    char *p = (char *)malloc(size ? size : 1);
    return p && size == 0 ? p + 1 : p;
}

static inline void fuzz_free_exact(char *p, size_t size)
{
    if (p) free(size == 0 ? p - 1 : p);
}

#endif
