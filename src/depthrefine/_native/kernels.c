/* gbp's compiled kernels in plain C, built when the package is installed and called through ctypes.
 *
 * Each function is the numba kernel of the same name (depthrefine/methods/_wls_jit.py, _resample_jit.py,
 * gbp/_offsets_jit.py) operation for operation, in the same types and the same order, so that the two
 * give the same bits (tests/test_native.py compares them). A fresh process then runs gbp without
 * importing numba (its set-up costs about half a second: docs/speed.md).
 *
 * Rules that keep the bits: no -ffast-math and no contraction of a * b + c into one rounding
 * (-ffp-contract=off; the only fused operations are the explicit fma() calls of expf32, as numba's
 * llvm.fma); min and max as Python's (max(a, b) is b only when b > a); float32 arithmetic stays float32
 * and mixed int / float32 arithmetic is done in double, as numba types it.
 *
 * The functions hold no state and write only their own part of their outputs (rows i0:i1, columns
 * j0:j1), so threads may run parts side by side; ctypes releases the GIL around each call.
 */

#include <Python.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#ifndef DEPTHREFINE_KERNELS_SOURCE
#define DEPTHREFINE_KERNELS_SOURCE ""
#endif

/* The functions' signatures, checked by the loader (depthrefine._native.ABI): raise it with any change of them. */
#define DEPTHREFINE_KERNELS_ABI 4

#if defined(_MSC_VER) && !defined(__clang__)
#define restrict __restrict     /* MSVC knows C99's restrict only with /std:c11 */
#endif

#if defined(_WIN32)
#define EXPORT __declspec(dllexport)
#else
#define EXPORT __attribute__((visibility("default")))
#endif

typedef ptrdiff_t index_t;

/* Python's max and min (numba's): max(a, b) is b only when b > a, min(a, b) only when b < a. */
static inline float max_f(float a, float b) { return b > a ? b : a; }
static inline float min_f(float a, float b) { return b < a ? b : a; }
static inline double max_d(double a, double b) { return b > a ? b : a; }
static inline double min_d(double a, double b) { return b < a ? b : a; }
static inline index_t max_i(index_t a, index_t b) { return b > a ? b : a; }
static inline index_t min_i(index_t a, index_t b) { return b < a ? b : a; }

/* The hash of this file the package was built from (setup.py), so that a stale build is not used. */
EXPORT const char *dr_source_hash(void) { return DEPTHREFINE_KERNELS_SOURCE; }
EXPORT int dr_abi_version(void) { return DEPTHREFINE_KERNELS_ABI; }

/* ---- exp of a float32 as glibc computes it (depthrefine._numba.expf32) ---- */

static const uint64_t EXP2_TABLE[32] = {
    0x3ff0000000000000ULL, 0x3fefd9b0d3158574ULL, 0x3fefb5586cf9890fULL, 0x3fef9301d0125b51ULL,
    0x3fef72b83c7d517bULL, 0x3fef54873168b9aaULL, 0x3fef387a6e756238ULL, 0x3fef1e9df51fdee1ULL,
    0x3fef06fe0a31b715ULL, 0x3feef1a7373aa9cbULL, 0x3feedea64c123422ULL, 0x3feece086061892dULL,
    0x3feebfdad5362a27ULL, 0x3feeb42b569d4f82ULL, 0x3feeab07dd485429ULL, 0x3feea47eb03a5585ULL,
    0x3feea09e667f3bcdULL, 0x3fee9f75e8ec5f74ULL, 0x3feea11473eb0187ULL, 0x3feea589994cce13ULL,
    0x3feeace5422aa0dbULL, 0x3feeb737b0cdc5e5ULL, 0x3feec49182a3f090ULL, 0x3feed503b23e255dULL,
    0x3feee89f995ad3adULL, 0x3feeff76f2fb5e47ULL, 0x3fef199bdd85529cULL, 0x3fef3720dcef9069ULL,
    0x3fef5818dcfba487ULL, 0x3fef7c97337b9b5fULL, 0x3fefa4afa2a490daULL, 0x3fefd0765b6e4540ULL,
};

static inline uint64_t double_bits(double x) { uint64_t k; memcpy(&k, &x, 8); return k; }
static inline double bits_double(uint64_t k) { double x; memcpy(&x, &k, 8); return x; }

static inline float exp_f32(float x)
{
    const double inv_ln2_32 = 0x1.71547652b82fep+5, shift = 0x1.8p+52;
    const double c0 = 0x1.c6af84b912394p-20, c1 = 0x1.ebfce50fac4f3p-13, c2 = 0x1.62e42ff0c52d6p-6;
    double xd = (double)x;
    double shifted = fma(inv_ln2_32, xd, shift);
    uint64_t k = double_bits(shifted);
    double kd = shifted - shift;
    double r = fma(inv_ln2_32, xd, -kd);
    double scale = bits_double(EXP2_TABLE[k & 31u] + (k << 47));
    double cubic = fma(fma(r, c0, c1), r * r, fma(r, c2, 1.0));
    float out = (float)(cubic * scale);
    out = x < -0x1.9d1d9ep6f ? 0x1.4p-75f * 0x1.4p-75f : out;   /* glibc's special cases, as selections */
    out = x < -0x1.9fe368p6f ? 0.0f : out;
    out = x > 0x1.62e42ep6f ? INFINITY : out;
    return x != x ? x + x : out;
}

EXPORT float dr_exp_f32(float x) { return exp_f32(x); }

/* ---- the weighted least-squares solver (methods/_wls_jit.py) ---- */

/* Solve (I + lam L_w) v = u along axis 0 for the columns j0:j1 of u (rows x ?, row strides in elements),
 * in place; ratio holds rows x (j1 - j0) floats, e and last (j1 - j0) each. */
static void sweep_columns(float *u, index_t u_stride, const float *w, index_t w_stride, index_t rows, float lam,
                          index_t j0, index_t j1, float *restrict ratio, float *restrict e, float *restrict last)
{
    const index_t n = j1 - j0;
    const float one = 1.0f, cap = 1e30f;
    for (index_t k = 0; k < n; k++) {
        e[k] = 1.0f;
        last[k] = u[j0 + k];
    }
    if (rows > 1) {
        const float *restrict w_row = w + j0;
        float *restrict r_row = ratio;
        for (index_t k = 0; k < n; k++) {
            float a = min_f(lam * w_row[k], cap);
            r_row[k] = a / (one + a);
        }
    }
    for (index_t i = 1; i < rows - 1; i++) {
        float *restrict u_row = u + i * u_stride + j0;
        const float *restrict w_row = w + i * w_stride + j0;
        const float *restrict r_prev = ratio + (i - 1) * n;
        float *restrict r_row = ratio + i * n;
        for (index_t k = 0; k < n; k++) {
            float g = r_prev[k] * e[k];
            float ek = one + g;
            float f = u_row[k];
            float z = f + (g / ek) * (last[k] - f);
            u_row[k] = z;
            last[k] = z;
            float a = min_f(lam * w_row[k], cap);
            r_row[k] = a / (ek + a);
            e[k] = ek;
        }
    }
    if (rows > 1) {
        float *restrict u_row = u + (rows - 1) * u_stride + j0;
        const float *restrict r_prev = ratio + (rows - 2) * n;
        for (index_t k = 0; k < n; k++) {
            float g = r_prev[k] * e[k];
            float f = u_row[k];
            float z = f + (g / (one + g)) * (last[k] - f);
            u_row[k] = z;
            last[k] = z;
        }
    }
    for (index_t i = rows - 2; i >= 0; i--) {
        float *restrict u_row = u + i * u_stride + j0;
        const float *restrict r_row = ratio + i * n;
        for (index_t k = 0; k < n; k++) {
            float z = u_row[k];
            float v = z + r_row[k] * (last[k] - z);
            u_row[k] = v;
            last[k] = v;
        }
    }
}

/* Scratch of a sweep of n columns over rows: 0 on success, -1 when out of memory. */
static float *sweep_scratch(index_t rows, index_t n)
{
    return (float *)malloc(sizeof(float) * (size_t)(rows * n + 2 * n + 1));
}

EXPORT int dr_sweep_columns(float *u, index_t u_stride, const float *w, index_t w_stride, index_t rows, float lam,
                            index_t j0, index_t j1)
{
    index_t n = j1 - j0;
    if (n <= 0 || rows <= 0) return 0;
    float *scratch = sweep_scratch(rows, n);
    if (!scratch) return -1;
    sweep_columns(u, u_stride, w, w_stride, rows, lam, j0, j1, scratch, scratch + rows * n, scratch + rows * n + n);
    free(scratch);
    return 0;
}

/* The sweeps of the blocks b0:b1 of `block` columns of a C-contiguous rows x cols u, one after the other. */
EXPORT int dr_solve_columns(float *u, const float *w, index_t rows, index_t cols, float lam, index_t block,
                            index_t b0, index_t b1)
{
    if (b1 <= b0 || rows <= 0) return 0;
    float *scratch = sweep_scratch(rows, block);
    if (!scratch) return -1;
    for (index_t b = b0; b < b1; b++) {
        index_t j0 = b * block, j1 = min_i(cols, (b + 1) * block);
        sweep_columns(u, cols, w, cols, rows, lam, j0, j1, scratch, scratch + rows * block,
                      scratch + rows * block + block);
    }
    free(scratch);
    return 0;
}

static inline int32_t color_distance2(const uint8_t *a, const uint8_t *b, index_t channels)
{
    if (channels == 3) {
        int32_t d0 = (int32_t)a[0] - (int32_t)b[0];
        int32_t d1 = (int32_t)a[1] - (int32_t)b[1];
        int32_t d2 = (int32_t)a[2] - (int32_t)b[2];
        return d0 * d0 + d1 * d1 + d2 * d2;
    }
    int32_t total = 0;
    for (index_t c = 0; c < channels; c++) {
        int32_t d = (int32_t)a[c] - (int32_t)b[c];
        total += d * d;
    }
    return total;
}

#if defined(__AVX2__)
/* Channel ch of eight RGB pixels (24 bytes at p) as eight int32 lanes; g0 and g1 are the 16 bytes at p and at p + 8
 * (pixels 0-3 are bytes 3 k + ch of g0, pixels 4-7 bytes 4 + 3 k + ch of g1). */
static inline __m256i rgb8_channel(__m128i g0, __m128i g1, int ch)
{
    const char c = (char)ch;
    __m128i low = _mm_shuffle_epi8(g0, _mm_setr_epi8(c, c + 3, c + 6, c + 9, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,
                                                     -1, -1));
    __m128i high = _mm_shuffle_epi8(g1, _mm_setr_epi8(-1, -1, -1, -1, c + 4, c + 7, c + 10, c + 13, -1, -1, -1, -1,
                                                      -1, -1, -1, -1));
    return _mm256_cvtepu8_epi32(_mm_or_si128(low, high));
}

/* lut[(int32_t)d] of eight floats d (whole numbers within the table). */
static inline __m256 lut8(const float *lut, __m256 d) { return _mm256_i32gather_ps(lut, _mm256_cvttps_epi32(d), 4); }
#endif

/* out[j] = lut[|a_j - b_j|^2] for the n pixels a_j = a + 3 j, b_j = b + 3 j of 3 channels (reads a[0 .. 3 n) and
 * b[0 .. 3 n) only). The squared distance is an exact integer, so any order of its sums gives its value. */
static void color_weight_run3(float *restrict out, const uint8_t *a, const uint8_t *b, const float *lut, index_t n)
{
    index_t j = 0;
#if defined(__AVX2__)
    for (; j + 8 <= n; j += 8) {
        const __m128i a0 = _mm_loadu_si128((const __m128i *)(a + 3 * j));
        const __m128i a1 = _mm_loadu_si128((const __m128i *)(a + 3 * j + 8));
        const __m128i b0 = _mm_loadu_si128((const __m128i *)(b + 3 * j));
        const __m128i b1 = _mm_loadu_si128((const __m128i *)(b + 3 * j + 8));
        __m256i total = _mm256_setzero_si256();
        for (int c = 0; c < 3; c++) {
            __m256i d = _mm256_sub_epi32(rgb8_channel(a0, a1, c), rgb8_channel(b0, b1, c));
            total = _mm256_add_epi32(total, _mm256_mullo_epi32(d, d));
        }
        _mm256_storeu_ps(out + j, _mm256_i32gather_ps(lut, total, 4));
    }
#endif
    for (; j < n; j++) out[j] = lut[color_distance2(a + 3 * j, b + 3 * j, 3)];
}

/* lut[|dc|^2] between horizontal (wx) and vertical (wy) neighbours of a rows x cols x channels uint8 guide,
 * rows i0:i1. */
EXPORT void dr_color_weight_rows(const uint8_t *guide, index_t rows, index_t cols, index_t channels,
                                 const float *lut, float *wx, float *wy, index_t i0, index_t i1)
{
    if (cols <= 0) return;
    for (index_t i = i0; i < i1; i++) {
        const uint8_t *restrict row = guide + i * cols * channels;
        float *restrict out = wx + i * cols;
        if (channels == 3) {
            color_weight_run3(out, row + 3, row, lut, cols - 1);
        } else {
            for (index_t j = 0; j < cols - 1; j++)
                out[j] = lut[color_distance2(row + channels * (j + 1), row + channels * j, channels)];
        }
        out[cols - 1] = 0.0f;
        float *restrict out_y = wy + i * cols;
        if (i + 1 < rows) {
            const uint8_t *restrict below = row + cols * channels;
            if (channels == 3) {
                color_weight_run3(out_y, below, row, lut, cols);
            } else {
                for (index_t j = 0; j < cols; j++)
                    out_y[j] = lut[color_distance2(below + channels * j, row + channels * j, channels)];
            }
        } else {
            for (index_t j = 0; j < cols; j++) out_y[j] = 0.0f;
        }
    }
}

/* dr_color_weight_rows times exp(-|dx| * inv_sigma) of the depth x (rows x cols), rows i0:i1. */
EXPORT void dr_edge_weight_rows(const uint8_t *guide, index_t rows, index_t cols, index_t channels, const float *lut,
                                const float *x, float inv_sigma, float *wx, float *wy, index_t i0, index_t i1)
{
    if (cols <= 0) return;
    for (index_t i = i0; i < i1; i++) {
        dr_color_weight_rows(guide, rows, cols, channels, lut, wx, wy, i, i + 1);
        const float *restrict x_row = x + i * cols;
        float *restrict out = wx + i * cols;
        for (index_t j = 0; j < cols - 1; j++) out[j] *= exp_f32(-fabsf(x_row[j + 1] - x_row[j]) * inv_sigma);
        if (i + 1 < rows) {
            const float *restrict below = x_row + cols;
            float *restrict out_y = wy + i * cols;
            for (index_t j = 0; j < cols; j++) out_y[j] *= exp_f32(-fabsf(below[j] - x_row[j]) * inv_sigma);
        }
    }
}

/* w * exp(-|dx| * inv_sigma) for horizontal and vertical neighbours of x (rows x cols), rows i0:i1. */
EXPORT void dr_depth_weight_rows(const float *x, index_t rows, index_t cols, float inv_sigma, const float *wx,
                                 const float *wy, float *out_x, float *out_y, index_t i0, index_t i1)
{
    if (cols <= 0) return;
    for (index_t i = i0; i < i1; i++) {
        const float *restrict x_row = x + i * cols, *restrict w_row = wx + i * cols;
        float *restrict out_row = out_x + i * cols;
        for (index_t j = 0; j < cols - 1; j++)
            out_row[j] = w_row[j] * exp_f32(-fabsf(x_row[j + 1] - x_row[j]) * inv_sigma);
        out_row[cols - 1] = 0.0f;
        float *restrict out_col = out_y + i * cols;
        if (i + 1 < rows) {
            const float *restrict below = x_row + cols, *restrict w_col = wy + i * cols;
            for (index_t j = 0; j < cols; j++) out_col[j] = w_col[j] * exp_f32(-fabsf(below[j] - x_row[j]) * inv_sigma);
        } else {
            for (index_t j = 0; j < cols; j++) out_col[j] = 0.0f;
        }
    }
}

/* ---- gbp's kernels between two grids (methods/_resample_jit.py) ---- */

static inline float similar(const float *lut, const uint8_t *a0, const uint8_t *a1, const uint8_t *a2, index_t ka,
                            uint8_t b0, uint8_t b1, uint8_t b2)
{
    float d0 = (float)a0[ka] - (float)b0;
    float d1 = (float)a1[ka] - (float)b1;
    float d2 = (float)a2[ka] - (float)b2;
    return lut[(int32_t)(d0 * d0 + d1 * d1 + d2 * d2)];
}

/* Output pixel c of one row of dr_enlarge_rows: n0..n2 and x_near the near small row's color planes and values,
 * f0..f2 and x_far the far one's, row the guide's row (W pixels of 3 channels). */
static inline void enlarge_pixel(float *restrict out_row, index_t c, index_t w, const uint8_t *restrict row,
                                 const uint8_t *restrict n0, const uint8_t *restrict n1, const uint8_t *restrict n2,
                                 const uint8_t *restrict f0, const uint8_t *restrict f1, const uint8_t *restrict f2,
                                 const float *restrict x_near, const float *restrict x_far, const float *restrict lut)
{
    const float tiny = 1e-30f;
    index_t k = c >> 1;
    index_t kk = (c % 2 == 0) ? max_i(k - 1, 0) : min_i(k + 1, w - 1);
    uint8_t b0 = row[3 * c], b1 = row[3 * c + 1], b2 = row[3 * c + 2];
    float w_nn = 9.0f * (similar(lut, n0, n1, n2, k, b0, b1, b2) + tiny);
    float w_nf = 3.0f * (similar(lut, n0, n1, n2, kk, b0, b1, b2) + tiny);
    float w_fn = 3.0f * (similar(lut, f0, f1, f2, k, b0, b1, b2) + tiny);
    float w_ff = similar(lut, f0, f1, f2, kk, b0, b1, b2) + tiny;
    out_row[c] = (w_nn * x_near[k] + w_nf * x_near[kk] + w_fn * x_far[k] + w_ff * x_far[kk])
                 / (w_nn + w_nf + w_fn + w_ff);
}

/* One output row of dr_enlarge_rows: the near small row's planes n0..n2 and values x_near, the far one's f0..f2
 * and x_far, the guide's row (W pixels of 3 channels). */
static void enlarge_row(float *restrict out_row, index_t W, index_t w, const uint8_t *restrict row,
                        const uint8_t *restrict n0, const uint8_t *restrict n1, const uint8_t *restrict n2,
                        const uint8_t *restrict f0, const uint8_t *restrict f1, const uint8_t *restrict f2,
                        const float *restrict x_near, const float *restrict x_far, const float *restrict lut)
{
    index_t c = 0;
#if defined(__AVX2__)
    /* eight output pixels c0 .. c0 + 7 (c0 even) at a time, away from the borders (no clamp of kk): their near small
     * pixels are k = c0 / 2 + 0, 0, 1, 1, .., 3, 3 and their far ones k - 1 (even c) or k + 1 (odd c), all within
     * the eight small pixels from c0 / 2 - 1 on. Each lane does the loop's operations in its order and types. */
    if (W >= 16) {
        for (; c < 8; c++)          /* the first eight by the scalar path: a step reads from c / 2 - 1 on */
            enlarge_pixel(out_row, c, w, row, n0, n1, n2, f0, f1, f2, x_near, x_far, lut);
        const __m256i near_at = _mm256_setr_epi32(1, 1, 2, 2, 3, 3, 4, 4);
        const __m256i far_at = _mm256_setr_epi32(0, 2, 1, 3, 2, 4, 3, 5);
        const __m128i near_bytes = _mm_setr_epi8(1, 1, 2, 2, 3, 3, 4, 4, -1, -1, -1, -1, -1, -1, -1, -1);
        const __m128i far_bytes = _mm_setr_epi8(0, 2, 1, 3, 2, 4, 3, 5, -1, -1, -1, -1, -1, -1, -1, -1);
        const __m256 v_tiny = _mm256_set1_ps(1e-30f), nine = _mm256_set1_ps(9.0f), three = _mm256_set1_ps(3.0f);
        const uint8_t *near_planes[3] = {n0, n1, n2}, *far_planes[3] = {f0, f1, f2};
        for (; c + 8 <= W && c / 2 + 7 <= w; c += 8) {
            const index_t base = c / 2 - 1;
            const __m128i g0 = _mm_loadu_si128((const __m128i *)(row + 3 * c));
            const __m128i g1 = _mm_loadu_si128((const __m128i *)(row + 3 * c + 8));
            __m256 d_nn = _mm256_setzero_ps(), d_nf = d_nn, d_fn = d_nn, d_ff = d_nn;
            for (int ch = 0; ch < 3; ch++) {
                __m256 b = _mm256_cvtepi32_ps(rgb8_channel(g0, g1, ch));
                __m128i pn = _mm_loadl_epi64((const __m128i *)(near_planes[ch] + base));
                __m128i pf = _mm_loadl_epi64((const __m128i *)(far_planes[ch] + base));
                __m256 a_nn = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_shuffle_epi8(pn, near_bytes)));
                __m256 a_nf = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_shuffle_epi8(pn, far_bytes)));
                __m256 a_fn = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_shuffle_epi8(pf, near_bytes)));
                __m256 a_ff = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_shuffle_epi8(pf, far_bytes)));
                __m256 e_nn = _mm256_sub_ps(a_nn, b), e_nf = _mm256_sub_ps(a_nf, b);
                __m256 e_fn = _mm256_sub_ps(a_fn, b), e_ff = _mm256_sub_ps(a_ff, b);
                d_nn = _mm256_add_ps(d_nn, _mm256_mul_ps(e_nn, e_nn));  /* 0 + d0 * d0 is d0 * d0, a square */
                d_nf = _mm256_add_ps(d_nf, _mm256_mul_ps(e_nf, e_nf));
                d_fn = _mm256_add_ps(d_fn, _mm256_mul_ps(e_fn, e_fn));
                d_ff = _mm256_add_ps(d_ff, _mm256_mul_ps(e_ff, e_ff));
            }
            __m256 w_nn = _mm256_mul_ps(nine, _mm256_add_ps(lut8(lut, d_nn), v_tiny));
            __m256 w_nf = _mm256_mul_ps(three, _mm256_add_ps(lut8(lut, d_nf), v_tiny));
            __m256 w_fn = _mm256_mul_ps(three, _mm256_add_ps(lut8(lut, d_fn), v_tiny));
            __m256 w_ff = _mm256_add_ps(lut8(lut, d_ff), v_tiny);
            __m256 xn = _mm256_loadu_ps(x_near + base), xf = _mm256_loadu_ps(x_far + base);
            __m256 sum = _mm256_mul_ps(w_nn, _mm256_permutevar8x32_ps(xn, near_at));
            sum = _mm256_add_ps(sum, _mm256_mul_ps(w_nf, _mm256_permutevar8x32_ps(xn, far_at)));
            sum = _mm256_add_ps(sum, _mm256_mul_ps(w_fn, _mm256_permutevar8x32_ps(xf, near_at)));
            sum = _mm256_add_ps(sum, _mm256_mul_ps(w_ff, _mm256_permutevar8x32_ps(xf, far_at)));
            __m256 weight = _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(w_nn, w_nf), w_fn), w_ff);
            _mm256_storeu_ps(out_row + c, _mm256_div_ps(sum, weight));
        }
    }
#endif
    for (; c < W; c++) enlarge_pixel(out_row, c, w, row, n0, n1, n2, f0, f1, f2, x_near, x_far, lut);
}

/* Rows i0:i1 of the guided x2 enlargement out (H x W) of x (h x w): s0, s1, s2 the small guide's color planes
 * (h x w each), guide the (H, W, 3) one. Output pixel (i, c) blends the small pixels of rows q = i / 2 (near)
 * and p (far: q - 1 for an even i, q + 1 for an odd one, clamped), columns k = c / 2 (near) and kk (far, the
 * same way), with bilinear weights 9, 3, 3, 1 times each one's color likeness. */
EXPORT void dr_enlarge_rows(const float *x, index_t h, index_t w, const uint8_t *s0, const uint8_t *s1,
                            const uint8_t *s2, const uint8_t *guide, index_t W, const float *lut, float *out,
                            index_t i0, index_t i1)
{
    for (index_t i = i0; i < i1; i++) {
        index_t q = i >> 1;
        index_t p = (i % 2 == 0) ? max_i(q - 1, 0) : min_i(q + 1, h - 1);
        enlarge_row(out + i * W, W, w, guide + i * W * 3, s0 + q * w, s1 + q * w, s2 + q * w, s0 + p * w,
                    s1 + p * w, s2 + p * w, x + q * w, x + p * w, lut);
    }
}

/* One row of dr_clip_rows: x_row clipped to [low, high], then to lower_row[col[j]], upper_row[col[j]]. */
static void clip_row(float *restrict x_row, index_t n, float low, float high, const float *restrict lower_row,
                     const float *restrict upper_row, const int32_t *restrict col)
{
    for (index_t j = 0; j < n; j++) {
        float v = min_f(max_f(x_row[j], low), high);
        x_row[j] = min_f(max_f(v, lower_row[col[j]]), upper_row[col[j]]);
    }
}

/* Rows i0:i1 of x (rows_x x cols_x): clip to [low, high], then to [lower, upper][rows[i], cols[j]] (bounds of
 * bound_cols columns). */
EXPORT void dr_clip_rows(float *x, index_t cols_x, float low, float high, const float *lower, const float *upper,
                         index_t bound_cols, const int32_t *rows, const int32_t *cols, index_t i0, index_t i1)
{
    for (index_t i = i0; i < i1; i++)
        clip_row(x + i * cols_x, cols_x, low, high, lower + (index_t)rows[i] * bound_cols,
                 upper + (index_t)rows[i] * bound_cols, cols);
}

/* One row of dr_clip_toward_rows. */
static void clip_toward_row(float *restrict x_row, index_t n, const float *restrict w_row,
                            const float *restrict lower_row, const float *restrict upper_row,
                            const int32_t *restrict col)
{
    for (index_t j = 0; j < n; j++) {
        float v = x_row[j];
        float clipped = min_f(max_f(v, lower_row[col[j]]), upper_row[col[j]]);
        x_row[j] = v + (clipped - v) * w_row[j];
    }
}

/* Rows i0:i1 of x: x + (clip(x) - x) * weight, clip to the bounds as dr_clip_rows's second clip. */
EXPORT void dr_clip_toward_rows(float *x, index_t cols_x, const float *weight, const float *lower,
                                const float *upper, index_t bound_cols, const int32_t *rows, const int32_t *cols,
                                index_t i0, index_t i1)
{
    for (index_t i = i0; i < i1; i++)
        clip_toward_row(x + i * cols_x, cols_x, weight + i * cols_x, lower + (index_t)rows[i] * bound_cols,
                        upper + (index_t)rows[i] * bound_cols, cols);
}

/* Rows i0:i1 of out = sqrt(x * x + y * y) (rows of cols floats), each operation rounded to float32 as numpy's
 * float32 x * x, += y * y and sqrt do (fattening._hypot, which runs where this library is not built). */
static void hypot_row(float *restrict out, const float *restrict x, const float *restrict y, index_t n)
{
    for (index_t j = 0; j < n; j++) {
        float s = x[j] * x[j];
        s += y[j] * y[j];
        out[j] = sqrtf(s);
    }
}

EXPORT void dr_hypot_rows(const float *x, const float *y, float *out, index_t cols, index_t i0, index_t i1)
{
    for (index_t i = i0; i < i1; i++) hypot_row(out + i * cols, x + i * cols, y + i * cols, cols);
}

/* ---- the hole filling's rays (_fill.py) ---- */

/* The depth of the nearest finite pixel seen from each pixel of a rows x cols float32 map in one direction
 * (0 to the left, 1 to the right, 2 above, 3 below; the pixel itself included) within reach pixels, else NaN,
 * into out: _fill._nearest_along's values. Rows k0:k1 for directions 0 and 1, columns k0:k1 for 2 and 3. */
EXPORT int dr_nearest_seen(const float *depth, index_t rows, index_t cols, double reach, int direction, float *out,
                           index_t k0, index_t k1)
{
    const float none = NAN;
    if (direction < 2) {
        for (index_t i = k0; i < k1; i++) {
            const float *row = depth + i * cols;
            float *out_row = out + i * cols;
            index_t last = -1;
            if (direction == 0) {
                for (index_t j = 0; j < cols; j++) {
                    if (isfinite(row[j])) last = j;
                    out_row[j] = last >= 0 && (double)(j - last) <= reach ? row[last] : none;
                }
            } else {
                for (index_t j = cols - 1; j >= 0; j--) {
                    if (isfinite(row[j])) last = j;
                    out_row[j] = last >= 0 && (double)(last - j) <= reach ? row[last] : none;
                }
            }
        }
        return 0;
    }
    if (k1 <= k0) return 0;
    index_t *last = (index_t *)malloc(sizeof(index_t) * (size_t)(k1 - k0));
    if (!last) return -1;
    for (index_t j = k0; j < k1; j++) last[j - k0] = -1;
    for (index_t step = 0; step < rows; step++) {
        index_t i = direction == 2 ? step : rows - 1 - step;
        const float *row = depth + i * cols;
        float *out_row = out + i * cols;
        for (index_t j = k0; j < k1; j++) {
            if (isfinite(row[j])) last[j - k0] = i;
            index_t seen = last[j - k0];
            double distance = direction == 2 ? (double)(i - seen) : (double)(seen - i);
            out_row[j] = seen >= 0 && distance <= reach ? depth[seen * cols + j] : none;
        }
    }
    free(last);
    return 0;
}

/* ---- step 1b's per-pixel search (methods/gbp/_offsets_jit.py) ---- */

/* image (rows x cols) at (x, y), bilinear, the border replicated; as numba types it: the differences of two
 * float32 pixels in float32, the rest in double. */
static inline double bilinear(const float *image, index_t rows, index_t cols, double x, double y)
{
    x = min_d(max_d(x, 0.0), (double)cols - 1.0);
    y = min_d(max_d(y, 0.0), (double)rows - 1.0);
    index_t x0 = (index_t)floor(x), y0 = (index_t)floor(y);
    index_t x1 = min_i(x0 + 1, cols - 1), y1 = min_i(y0 + 1, rows - 1);
    double fx = x - (double)x0, fy = y - (double)y0;
    const float *r0 = image + y0 * cols, *r1 = image + y1 * cols;
    double top = (double)r0[x0] + fx * (double)(r0[x1] - r0[x0]);
    double bottom = (double)r1[x0] + fx * (double)(r1[x1] - r1[x0]);
    return top + fy * (bottom - top);
}

#if defined(__AVX2__)
/* bilinear() at the four points (x[k], y[k]), into out[0..3]: each lane does bilinear()'s operations in its order
 * and types (the clamps as its selections, floor, the float32 differences), so the values are its bits. The image
 * must have fewer than 2**31 pixels. */
static inline void bilinear4_at(const float *image, index_t rows, index_t cols, __m256d x, __m256d y, double *out)
{
    const __m256d zero = _mm256_setzero_pd();
    const __m256d last_x = _mm256_set1_pd((double)cols - 1.0), last_y = _mm256_set1_pd((double)rows - 1.0);
    /* x = min_d(max_d(x, 0), cols - 1): max_d(a, b) is b only when b > a, min_d(a, b) only when b < a */
    x = _mm256_blendv_pd(x, zero, _mm256_cmp_pd(zero, x, _CMP_GT_OQ));
    x = _mm256_blendv_pd(x, last_x, _mm256_cmp_pd(last_x, x, _CMP_LT_OQ));
    y = _mm256_blendv_pd(y, zero, _mm256_cmp_pd(zero, y, _CMP_GT_OQ));
    y = _mm256_blendv_pd(y, last_y, _mm256_cmp_pd(last_y, y, _CMP_LT_OQ));
    __m256d fx0 = _mm256_floor_pd(x), fy0 = _mm256_floor_pd(y);
    __m128i x0 = _mm256_cvttpd_epi32(fx0), y0 = _mm256_cvttpd_epi32(fy0);
    __m128i x1 = _mm_min_epi32(_mm_add_epi32(x0, _mm_set1_epi32(1)), _mm_set1_epi32((int)(cols - 1)));
    __m128i y1 = _mm_min_epi32(_mm_add_epi32(y0, _mm_set1_epi32(1)), _mm_set1_epi32((int)(rows - 1)));
    __m256d fx = _mm256_sub_pd(x, fx0), fy = _mm256_sub_pd(y, fy0);
    __m128i width = _mm_set1_epi32((int)cols);
    __m128i r0 = _mm_mullo_epi32(y0, width), r1 = _mm_mullo_epi32(y1, width);
    __m128 a = _mm_i32gather_ps(image, _mm_add_epi32(r0, x0), 4), b = _mm_i32gather_ps(image, _mm_add_epi32(r0, x1), 4);
    __m128 c = _mm_i32gather_ps(image, _mm_add_epi32(r1, x0), 4), d = _mm_i32gather_ps(image, _mm_add_epi32(r1, x1), 4);
    __m256d top = _mm256_add_pd(_mm256_cvtps_pd(a), _mm256_mul_pd(fx, _mm256_cvtps_pd(_mm_sub_ps(b, a))));
    __m256d bottom = _mm256_add_pd(_mm256_cvtps_pd(c), _mm256_mul_pd(fx, _mm256_cvtps_pd(_mm_sub_ps(d, c))));
    _mm256_storeu_pd(out, _mm256_add_pd(top, _mm256_mul_pd(fy, _mm256_sub_pd(bottom, top))));
}

/* bilinear() at the four points (j + t nx, i + t ny) of the four t (t = +-1 gives j +- nx exactly). */
static inline void bilinear4(const float *image, index_t rows, index_t cols, index_t j, index_t i, float nx,
                             float ny, __m256d t, double *out)
{
    __m256d x = _mm256_add_pd(_mm256_set1_pd((double)j), _mm256_mul_pd(t, _mm256_set1_pd((double)nx)));
    __m256d y = _mm256_add_pd(_mm256_set1_pd((double)i), _mm256_mul_pd(t, _mm256_set1_pd((double)ny)));
    bilinear4_at(image, rows, cols, x, y, out);
}
#endif

/* The profile of edges along (nx, ny) at pixel (i, j) of the ridge; its peak's offset and the gradient's angle go to
 * offsets[n], angles[n] where it is clear. Returns the new n. */
static inline int64_t profile_peak(const float *edges, index_t rows, index_t cols, index_t i, index_t j, float nx,
                                   float ny, int64_t reach, double peak_ratio, double *profile, double *offsets,
                                   double *angles, int64_t n, int small_image)
{
    const int64_t steps = 2 * reach + 1;
    int64_t k = 0;
#if defined(__AVX2__)
    if (small_image)                             /* four samples at a time, the same operations */
        for (; k + 4 <= steps; k += 4) {
            double t = (double)(k - reach);
            bilinear4(edges, rows, cols, j, i, nx, ny, _mm256_set_pd(t + 3.0, t + 2.0, t + 1.0, t), profile + k);
        }
#else
    (void)small_image;
#endif
    for (; k < steps; k++) {
        int64_t t = k - reach;
        profile[k] = bilinear(edges, rows, cols, (double)j + (double)t * (double)nx,
                              (double)i + (double)t * (double)ny);
    }
    double total = 0.0;
    int64_t peak = 0;
    for (k = 0; k < steps; k++) {
        total += profile[k];
        if (profile[k] > profile[peak]) peak = k;
    }
    if (peak == 0 || peak == steps - 1 || profile[peak] <= peak_ratio / (double)steps * (total + 1e-6))
        return n;                                /* no clear color edge within reach */
    double before = profile[peak - 1], top = profile[peak], after = profile[peak + 1];
    double curvature = before - 2.0 * top + after;
    double shift = curvature < 0.0 ? 0.5 * (before - after) / curvature : 0.0;
    offsets[n] = (double)(peak - reach) + shift;
    angles[n] = (double)atan2f(ny, nx);
    return n + 1;
}

/* Rows i0:i1 of the search (see jump_offsets): row i's results go to offsets[row_start[i]:] in column order,
 * their count to found[i]. Returns -1 when out of memory. */
EXPORT int dr_search(const uint8_t *band, const float *magnitude, const float *gx, const float *gy,
                     const float *edges, index_t rows, index_t cols, int64_t reach, double peak_ratio,
                     const int64_t *row_start, double *offsets, double *angles, int64_t *found, index_t i0,
                     index_t i1)
{
    const int64_t steps = 2 * reach + 1;
    const int small_image = rows * cols < ((index_t)1 << 31);   /* bilinear4's int32 offsets */
    double *profile = (double *)malloc(sizeof(double) * (size_t)steps);
    if (!profile) return -1;
    for (index_t i = i0; i < i1; i++) {
        int64_t n = row_start[i];
#if defined(__AVX2__)
        /* the ridge test of two band pixels at once (their two neighbours along the gradient: four lanes); a
         * pixel waits for the next one, and the row's last one alone is tested with its neighbours twice */
        index_t waiting = -1;
        float wait_x = 0.0f, wait_y = 0.0f;
#endif
        for (index_t j = 0; j < cols; j++) {
            float here = magnitude[i * cols + j];
            if (!band[i * cols + j] || here <= 0.0f) continue;
            float nx = gx[i * cols + j] / here, ny = gy[i * cols + j] / here;
            if (!(isfinite(nx) && isfinite(ny))) continue;   /* no direction: a gradient that overflowed float32 */
#if defined(__AVX2__)
            if (small_image) {
                if (waiting < 0) {
                    waiting = j, wait_x = nx, wait_y = ny;
                    continue;
                }
                double beside[4];
                __m256d x = _mm256_set_pd((double)j - (double)nx, (double)j + (double)nx,
                                          (double)waiting - (double)wait_x, (double)waiting + (double)wait_x);
                __m256d y = _mm256_set_pd((double)i - (double)ny, (double)i + (double)ny,
                                          (double)i - (double)wait_y, (double)i + (double)wait_y);
                bilinear4_at(magnitude, rows, cols, x, y, beside);
                double there = (double)magnitude[i * cols + waiting];
                if (!(there < beside[0] || there < beside[1]))  /* on the ridge of the depth gradient */
                    n = profile_peak(edges, rows, cols, i, waiting, wait_x, wait_y, reach, peak_ratio, profile,
                                     offsets, angles, n, small_image);
                waiting = -1;
                if (!((double)here < beside[2] || (double)here < beside[3]))
                    n = profile_peak(edges, rows, cols, i, j, nx, ny, reach, peak_ratio, profile, offsets, angles,
                                     n, small_image);
                continue;
            }
#endif
            if ((double)here < bilinear(magnitude, rows, cols, (double)j + (double)nx, (double)i + (double)ny)
                || (double)here < bilinear(magnitude, rows, cols, (double)j - (double)nx, (double)i - (double)ny))
                continue;                                /* not on the ridge of the depth gradient */
            n = profile_peak(edges, rows, cols, i, j, nx, ny, reach, peak_ratio, profile, offsets, angles, n,
                             small_image);
        }
#if defined(__AVX2__)
        if (waiting >= 0) {
            double beside[4];
            bilinear4(magnitude, rows, cols, waiting, i, wait_x, wait_y, _mm256_set_pd(-1.0, 1.0, -1.0, 1.0),
                      beside);
            double there = (double)magnitude[i * cols + waiting];
            if (!(there < beside[0] || there < beside[1]))
                n = profile_peak(edges, rows, cols, i, waiting, wait_x, wait_y, reach, peak_ratio, profile, offsets,
                                 angles, n, small_image);
        }
#endif
        found[i] = n - row_start[i];
    }
    free(profile);
    return 0;
}

/* ---- the geodesic nearest seed (_geodesic_jit.py) ---- */

/* passes forward and backward raster passes over the free pixels of a rows x cols grid: each takes the smaller
 * of its distance and a neighbour's plus the step's cost (float32), and that neighbour's source. */
EXPORT void dr_geodesic_sweeps(const float *cost_x, const float *cost_y, const uint8_t *free_, float *distance,
                               int64_t *source, index_t rows, index_t cols, index_t passes)
{
    for (index_t pass = 0; pass < passes; pass++) {
        for (index_t i = 0; i < rows; i++) {               /* forward: from the top and the left */
            for (index_t j = 0; j < cols; j++) {
                index_t at = i * cols + j;
                if (!free_[at]) continue;
                float best = distance[at];
                int64_t origin = source[at];
                if (i > 0) {
                    float d = distance[at - cols] + cost_y[at - cols];
                    if (d < best) { best = d; origin = source[at - cols]; }
                }
                if (j > 0) {
                    float d = distance[at - 1] + cost_x[at - 1];
                    if (d < best) { best = d; origin = source[at - 1]; }
                }
                distance[at] = best;
                source[at] = origin;
            }
        }
        for (index_t i = rows - 1; i >= 0; i--) {          /* backward: from the bottom and the right */
            for (index_t j = cols - 1; j >= 0; j--) {
                index_t at = i * cols + j;
                if (!free_[at]) continue;
                float best = distance[at];
                int64_t origin = source[at];
                if (i < rows - 1) {
                    float d = distance[at + cols] + cost_y[at];
                    if (d < best) { best = d; origin = source[at + cols]; }
                }
                if (j < cols - 1) {
                    float d = distance[at + 1] + cost_x[at];
                    if (d < best) { best = d; origin = source[at + 1]; }
                }
                distance[at] = best;
                source[at] = origin;
            }
        }
    }
}

/* An importable module, so that the package's loader finds this library's file by its name. */
static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_kernels",
                                    "gbp's kernels in C, called through ctypes (depthrefine._native).", -1, NULL};

PyMODINIT_FUNC PyInit__kernels(void) { return PyModule_Create(&module); }

/* =====================================================================================================
 * The thesis method's kernels (methods/thesis/_jit.py), each the numba kernel of the same name operation for
 * operation, in its types and order (tests/test_native.py compares them bit for bit). This section stands apart
 * from gbp's above so that changes to the two do not meet.
 * ===================================================================================================== */

/* quantize_lab on a float32 (rows, cols, 3) patch. ranges gets (a_min, a_max, b_min, b_max, f_min, f_max),
 * n_cls the three class counts, sum_l the three classes' L* sums: float64, each in row-major pixel order, adding
 * 0.0 for a pixel of another class as the numba kernel does. Each row is binned in a loop that vectorises, then
 * its sums run in pixel order. */
EXPORT void dr_quantize_lab(const float *restrict lab, index_t rows, index_t cols, float inv_step, float half,
                            int unify, float black, float white, int32_t *restrict qa, int32_t *restrict qb,
                            int32_t *restrict first, int64_t *restrict ranges, int64_t *restrict n_cls,
                            double *restrict sum_l)
{
    int32_t a_lo = INT32_MAX, b_lo = INT32_MAX, f_lo = INT32_MAX;
    int32_t a_hi = INT32_MIN, b_hi = INT32_MIN, f_hi = INT32_MIN;
    int64_t c0 = 0, c2 = 0;
    double s0 = 0.0, s1 = 0.0, s2 = 0.0;
    for (index_t i = 0; i < rows; i++) {
        const float *restrict row = lab + i * cols * 3;
        int32_t *restrict ra = qa + i * cols, *restrict rb = qb + i * cols, *restrict rf = first + i * cols;
        for (index_t j = 0; j < cols; j++) {
            int32_t a = (int32_t)floorf(row[3 * j + 1] * inv_step + half);
            int32_t b = (int32_t)floorf(row[3 * j + 2] * inv_step + half);
            ra[j] = a; rb[j] = b;
            a_lo = a < a_lo ? a : a_lo; a_hi = a > a_hi ? a : a_hi;
            b_lo = b < b_lo ? b : b_lo; b_hi = b > b_hi ? b : b_hi;
        }
        if (unify) {
            for (index_t j = 0; j < cols; j++) {
                float light = row[3 * j];
                int32_t f = 1 - (int32_t)(light <= black) + (int32_t)(light >= white);
                rf[j] = f;
                f_lo = f < f_lo ? f : f_lo; f_hi = f > f_hi ? f : f_hi;
                c0 += f == 0;
                c2 += f == 2;
            }
            /* the sums in pixel order; "wide if f == k else 0.0" as a selection of bits (no branch) */
            for (index_t j = 0; j < cols; j++) {
                uint64_t wide = double_bits((double)row[3 * j]);
                int32_t f = rf[j];
                s0 += bits_double(wide & (0 - (uint64_t)(f == 0)));
                s1 += bits_double(wide & (0 - (uint64_t)(f == 1)));
                s2 += bits_double(wide & (0 - (uint64_t)(f == 2)));
            }
        } else {
            for (index_t j = 0; j < cols; j++) {
                int32_t f = (int32_t)floorf(row[3 * j] * inv_step + half);
                rf[j] = f;
                f_lo = f < f_lo ? f : f_lo; f_hi = f > f_hi ? f : f_hi;
            }
        }
    }
    ranges[0] = a_lo; ranges[1] = a_hi; ranges[2] = b_lo; ranges[3] = b_hi; ranges[4] = f_lo; ranges[5] = f_hi;
    n_cls[0] = c0; n_cls[1] = unify ? (int64_t)(rows * cols) - c0 - c2 : 0; n_cls[2] = c2;
    sum_l[0] = s0; sum_l[1] = s1; sum_l[2] = s2;
}

/* feature_codes: code = ((first - f0) * na + qa - a0) * nb + qb - b0 in int64, stored as int32; its histogram
 * into counts when n_counts > 0 (integer counts: the order of the additions does not matter). */
EXPORT void dr_feature_codes(const int32_t *restrict qa, const int32_t *restrict qb, const int32_t *restrict first,
                             index_t n, int64_t a0, int64_t na, int64_t b0, int64_t nb, int64_t f0,
                             int32_t *restrict code, int64_t *restrict counts, index_t n_counts)
{
    for (index_t p = 0; p < n; p++)
        code[p] = (int32_t)((((int64_t)first[p] - f0) * na + ((int64_t)qa[p] - a0)) * nb + ((int64_t)qb[p] - b0));
    if (n_counts > 0 && n > 0 && n_counts <= (1 << 14) && n < ((index_t)1 << 31)) {
        /* four partial histograms, pixel p into partial p % 4: neighbouring pixels mostly share their bin, and one
         * histogram would wait on the previous pixel's store (integer counts: the sum is the same) */
        uint32_t *part = calloc(4 * (size_t)n_counts, sizeof(uint32_t));
        if (part) {
            index_t p = 0;
            for (; p + 4 <= n; p += 4) {
                part[code[p]]++;
                part[n_counts + code[p + 1]]++;
                part[2 * n_counts + code[p + 2]]++;
                part[3 * n_counts + code[p + 3]]++;
            }
            for (; p < n; p++) part[code[p]]++;
            for (index_t c = 0; c < n_counts; c++)
                counts[c] += (int64_t)part[c] + part[n_counts + c] + part[2 * n_counts + c] + part[3 * n_counts + c];
            free(part);
            return;
        }
    }
    if (n_counts > 0)
        for (index_t p = 0; p < n; p++) counts[code[p]] += 1;
}

/* lookup: out[p] = table[index[p]]. */
EXPORT void dr_lookup(const int16_t *restrict table, const int32_t *restrict index, index_t n, int16_t *restrict out)
{
    for (index_t p = 0; p < n; p++)
        out[p] = table[index[p]];
}

/* _assign: the nearest of the float32 means (the first on ties), distances summed in float32 in dimension order. */
static void thesis_assign(const float *restrict x, index_t n, index_t dims, const float *restrict means, index_t k,
                          int32_t *restrict labels)
{
    if (dims == 3) {    /* the thesis's (L*, a*, b*): the same operations, 64 points at a time (they vectorise) */
        for (index_t i0 = 0; i0 < n; i0 += 64) {
            index_t m = n - i0 < 64 ? n - i0 : 64;
            const float *restrict xs = x + 3 * i0;
            int32_t best[64];
            float best_d[64];
            for (index_t j = 0; j < k; j++) {
                const float m0 = means[3 * j], m1 = means[3 * j + 1], m2 = means[3 * j + 2];
                for (index_t q = 0; q < m; q++) {
                    float d0 = xs[3 * q] - m0, d1 = xs[3 * q + 1] - m1, d2 = xs[3 * q + 2] - m2;
                    float d = d0 * d0;
                    d = d + d1 * d1;
                    d = d + d2 * d2;
                    int take = j == 0 || d < best_d[q];
                    best[q] = take ? (int32_t)j : best[q];
                    best_d[q] = take ? d : best_d[q];
                }
            }
            memcpy(labels + i0, best, (size_t)m * sizeof(int32_t));
        }
        return;
    }
    for (index_t i = 0; i < n; i++) {
        int32_t best = 0;
        float best_d = 0.0f;
        for (index_t j = 0; j < k; j++) {
            float d = 0.0f;
            for (index_t e = 0; e < dims; e++) {
                float diff = x[i * dims + e] - means[j * dims + e];
                float sq = diff * diff;
                d = e == 0 ? sq : d + sq;
            }
            if (j == 0 || d < best_d) { best = (int32_t)j; best_d = d; }
        }
        labels[i] = best;
    }
}

/* lloyd: iterations rounds of k-means from means_in (k, dims); labels renumbered over the clusters used, their
 * means into means_out (capacity k rows). Returns the clusters kept, -1 when scratch memory is short, -2 when a
 * round keeps no cluster (no positive weight; segment.kmeans refuses such weights before). */
EXPORT int64_t dr_lloyd(const float *restrict x, const double *restrict w, index_t n, index_t dims,
                        const double *restrict means_in, index_t k, int64_t iterations, int32_t *restrict labels,
                        double *restrict means_out)
{
    size_t kd = (size_t)(k > 0 ? k : 1) * (size_t)(dims > 0 ? dims : 1);
    double *means = malloc(kd * sizeof(double)), *sums = malloc(kd * sizeof(double));
    double *counts = malloc((size_t)(k > 0 ? k : 1) * sizeof(double));
    float *means32 = malloc(kd * sizeof(float));
    int64_t *remap = malloc((size_t)(k > 0 ? k : 1) * sizeof(int64_t));
    int64_t result = -1;
    if (!means || !sums || !counts || !means32 || !remap) goto done;
    if (k == 0) { result = -2; goto done; }
    memcpy(means, means_in, (size_t)k * (size_t)dims * sizeof(double));
    for (index_t q = 0; q < k * dims; q++) means32[q] = (float)means[q];
    thesis_assign(x, n, dims, means32, k, labels);
    for (int64_t round = 0; round < iterations; round++) {
        for (index_t c = 0; c < k; c++) counts[c] = 0.0;
        for (index_t q = 0; q < k * dims; q++) sums[q] = 0.0;
        for (index_t i = 0; i < n; i++) {
            index_t c = labels[i];
            counts[c] += w[i];
            for (index_t e = 0; e < dims; e++)
                sums[c * dims + e] += w[i] * (double)x[i * dims + e];
        }
        index_t m = 0;
        for (index_t c = 0; c < k; c++) {
            if (counts[c] > 0) {
                for (index_t e = 0; e < dims; e++)
                    means[m * dims + e] = sums[c * dims + e] / counts[c];
                m++;
            }
        }
        if (m == 0) { result = -2; goto done; }
        k = m;
        for (index_t q = 0; q < k * dims; q++) means32[q] = (float)means[q];
        thesis_assign(x, n, dims, means32, k, labels);
    }
    for (index_t c = 0; c < k; c++) remap[c] = 0;
    for (index_t i = 0; i < n; i++) remap[labels[i]] = 1;
    index_t used = 0;
    for (index_t c = 0; c < k; c++) {
        if (remap[c]) {
            memcpy(means_out + used * dims, means + c * dims, (size_t)dims * sizeof(double));
            remap[c] = used++;
        }
    }
    for (index_t i = 0; i < n; i++) labels[i] = (int32_t)remap[labels[i]];
    result = used;
done:
    free(means); free(sums); free(counts); free(means32); free(remap);
    return result;
}

/* grow_samples: each cluster's samples grown by one pixel, a new pixel taking the value of its first sampled
 * neighbour in _jit._NEIGHBOURS' order. masks, grown (k, rows, cols) bool; values (k, rows, cols) float64. */
EXPORT void dr_grow_samples(const uint8_t *restrict masks, index_t k, index_t rows, index_t cols,
                            const double *restrict corrected, double *restrict values, uint8_t *restrict grown)
{
    static const int NEIGHBOURS[8][2] = {{0, -1}, {-1, 0}, {1, 0}, {0, 1}, {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
    for (index_t c = 0; c < k; c++) {
        const uint8_t *mask = masks + c * rows * cols;
        uint8_t *g = grown + c * rows * cols;
        double *v = values + c * rows * cols;
        for (index_t i = 0; i < rows; i++) {
            for (index_t j = 0; j < cols; j++) {
                index_t at = i * cols + j;
                if (mask[at]) { g[at] = 1; v[at] = corrected[at]; continue; }
                g[at] = 0;
                v[at] = 0.0;
                for (int q = 0; q < 8; q++) {
                    index_t y = i + NEIGHBOURS[q][0], x = j + NEIGHBOURS[q][1];
                    if (0 <= y && y < rows && 0 <= x && x < cols && mask[y * cols + x]) {
                        g[at] = 1;
                        v[at] = corrected[y * cols + x];
                        break;
                    }
                }
            }
        }
    }
}

/* interpolate_patch: bilinear in float32 where a pixel's cell is its cluster's, else the ratio of the bilinear
 * interpolations of weighted and present (k, n_lr, w_lr) in float64. Returns the count of non-finite results, or
 * -1 when scratch memory is short. */
EXPORT int64_t dr_interpolate_patch(const float *restrict filled, index_t n_lr, index_t w_lr,
                                    const int16_t *restrict cell_label, const int16_t *restrict labels, index_t rows,
                                    index_t cols, const double *restrict weighted, const double *restrict present,
                                    const int64_t *restrict i0, const int64_t *restrict i1, const double *restrict fr,
                                    const int64_t *restrict j0, const int64_t *restrict j1, const double *restrict fc,
                                    float *restrict out)
{
    float *along = malloc(((size_t)n_lr * (size_t)cols + 1) * sizeof(float));
    int16_t *cell = malloc(((size_t)n_lr * (size_t)cols + 1) * sizeof(int16_t));
    float *fc32 = malloc(((size_t)cols + 1) * sizeof(float));
    int64_t bad = 0;
    if (!along || !cell || !fc32) { bad = -1; goto done; }
    for (index_t c = 0; c < cols; c++) fc32[c] = (float)fc[c];
    for (index_t i = 0; i < n_lr; i++) {
        const float *f_row = filled + i * w_lr;
        const int16_t *l_row = cell_label + i * w_lr;
        for (index_t c = 0; c < cols; c++) {
            float left = f_row[j0[c]];
            along[i * cols + c] = left + fc32[c] * (f_row[j1[c]] - left);
            cell[i * cols + c] = l_row[j0[c]];
        }
    }
    index_t plane = n_lr * w_lr;
    for (index_t r = 0; r < rows; r++) {
        index_t a0 = i0[r], a1 = i1[r];
        float f = (float)fr[r];
        const float *top = along + a0 * cols, *bottom = along + a1 * cols;
        const int16_t *own = cell + a0 * cols, *label_row = labels + r * cols;
        float *row = out + r * cols;
        for (index_t c = 0; c < cols; c++)
            row[c] = top[c] + f * (bottom[c] - top[c]);
        for (index_t c = 0; c < cols; c++) {
            int16_t label = label_row[c];
            if (own[c] == label) continue;
            index_t b0 = j0[c], b1 = j1[c];
            const double *p = weighted + label * plane, *q = present + label * plane;
            double t = p[a0 * w_lr + b0] + fc[c] * (p[a0 * w_lr + b1] - p[a0 * w_lr + b0]);
            double u = p[a1 * w_lr + b0] + fc[c] * (p[a1 * w_lr + b1] - p[a1 * w_lr + b0]);
            double num = t + fr[r] * (u - t);
            t = q[a0 * w_lr + b0] + fc[c] * (q[a0 * w_lr + b1] - q[a0 * w_lr + b0]);
            u = q[a1 * w_lr + b0] + fc[c] * (q[a1 * w_lr + b1] - q[a1 * w_lr + b0]);
            double den = t + fr[r] * (u - t);
            if (den > 0) {
                row[c] = (float)(num / den);
                if (!isfinite(row[c])) bad++;
            } else {
                row[c] = NAN;
                bad++;
            }
        }
    }
done:
    free(along); free(cell); free(fc32);
    return bad;
}

/* fill_missing: non-finite pixels of result take fallback[near_rows[r], near_cols[c]] (float64 when is_double,
 * else float32; rows fallback_stride elements apart). */
EXPORT void dr_fill_missing(float *restrict result, index_t rows, index_t cols, const void *restrict fallback,
                            int is_double, index_t fallback_stride, const int64_t *restrict near_rows,
                            const int64_t *restrict near_cols)
{
    for (index_t r = 0; r < rows; r++) {
        float *restrict row = result + r * cols;
        int any = 0;        /* first whether the row has a non-finite pixel at all, in a loop that vectorises */
        for (index_t c = 0; c < cols; c++) {
            uint32_t bits;
            memcpy(&bits, row + c, 4);
            any |= (bits & 0x7f800000u) == 0x7f800000u;
        }
        if (!any) continue;
        for (index_t c = 0; c < cols; c++) {
            if (isfinite(row[c])) continue;
            index_t from = near_rows[r] * fallback_stride + near_cols[c];
            row[c] = is_double ? (float)((const double *)fallback)[from] : ((const float *)fallback)[from];
        }
    }
}

/* correct_values on n float64 values into out; counts (n_bins) and dominant (n_bins) are scratch. */
static void thesis_correct_values(const double *restrict values, index_t n, double origin, double bin_width,
                                  index_t n_bins, double dominant_fraction, double tolerance, double *restrict out,
                                  int64_t *restrict counts, double *restrict dominant)
{
    for (index_t b = 0; b < n_bins; b++) counts[b] = 0;
    index_t n_valid = 0;
    for (index_t i = 0; i < n; i++) {
        double v = values[i];
        if (isfinite(v)) {
            n_valid++;
            int64_t b = (int64_t)floor((v - origin) / bin_width + 0.5);
            b = b > 0 ? b : 0;
            b = b < n_bins - 1 ? b : n_bins - 1;
            counts[b] += 1;
        }
    }
    if (n_valid == 0) {
        for (index_t i = 0; i < n; i++) out[i] = NAN;
        return;
    }
    int64_t peak = counts[0];
    index_t fullest_bin = 0;
    for (index_t b = 1; b < n_bins; b++)
        if (counts[b] > peak) { peak = counts[b]; fullest_bin = b; }
    double fullest = origin + (double)fullest_bin * bin_width;
    index_t n_dom = 0;
    for (index_t b = 0; b < n_bins; b++)
        if (counts[b] == peak || (double)counts[b] > dominant_fraction * (double)peak)
            dominant[n_dom++] = origin + (double)b * bin_width;
    for (index_t i = 0; i < n; i++) {
        double v = values[i];
        if (!isfinite(v)) { out[i] = fullest; continue; }
        double best = dominant[0], best_d = fabs(v - best);
        for (index_t j = 1; j < n_dom; j++) {
            double d = fabs(v - dominant[j]);
            if (d < best_d) { best = dominant[j]; best_d = d; }
        }
        out[i] = best_d > tolerance ? best : v;
    }
}

/* correct_values (n_bins >= 1). Returns -1 when scratch memory is short, else 0. */
EXPORT int dr_correct_values(const double *restrict values, index_t n, double origin, double bin_width,
                             index_t n_bins, double dominant_fraction, double tolerance, double *restrict out)
{
    int64_t *counts = malloc((size_t)n_bins * sizeof(int64_t));
    double *dominant = malloc((size_t)n_bins * sizeof(double));
    int status = -1;
    if (counts && dominant) {
        thesis_correct_values(values, n, origin, bin_width, n_bins, dominant_fraction, tolerance, out, counts,
                              dominant);
        status = 0;
    }
    free(counts); free(dominant);
    return status;
}

/* correct_patch: per cluster c < k, the float32 depth samples labelled c (int16 samples; strides in elements)
 * corrected, or copied without correct, into out (rows, cols) float64. Returns -1 when memory is short, else 0. */
EXPORT int dr_correct_patch(const float *restrict depth, index_t d_row, index_t d_col,
                            const int16_t *restrict samples, index_t s_row, index_t s_col, index_t rows,
                            index_t cols, int64_t k, int correct, double origin, double bin_width, index_t n_bins,
                            double dominant_fraction, double tolerance, double *restrict out)
{
    size_t n_all = (size_t)rows * (size_t)cols + 1;
    double *values = malloc(n_all * sizeof(double)), *fixed = malloc(n_all * sizeof(double));
    int64_t *counts = malloc(((size_t)n_bins + 1) * sizeof(int64_t));
    double *dominant = malloc(((size_t)n_bins + 1) * sizeof(double));
    int status = -1;
    if (!values || !fixed || !counts || !dominant) goto done;
    for (int64_t c = 0; c < k; c++) {
        index_t n = 0;
        for (index_t i = 0; i < rows; i++)
            for (index_t j = 0; j < cols; j++)
                if (samples[i * s_row + j * s_col] == c) values[n++] = (double)depth[i * d_row + j * d_col];
        if (n == 0) continue;
        if (correct)
            thesis_correct_values(values, n, origin, bin_width, n_bins, dominant_fraction, tolerance, fixed, counts,
                                  dominant);
        else
            memcpy(fixed, values, (size_t)n * sizeof(double));
        n = 0;
        for (index_t i = 0; i < rows; i++)
            for (index_t j = 0; j < cols; j++)
                if (samples[i * s_row + j * s_col] == c) out[i * cols + j] = fixed[n++];
    }
    status = 0;
done:
    free(values); free(fixed); free(counts); free(dominant);
    return status;
}

/* ---- BEGIN GENERATED by depthrefine.methods.thesis.median.c_kernels_source: do not edit by hand ---- */
/* Min/max-network medians (methods/thesis/median.py): the kernels of _median_kernels.py, the same
 * program, stages, rows and lanes. A min or max of two integers is exact in any order. */

#define MEDIAN_MIN(a, b) ((b) < (a) ? (b) : (a))
#define MEDIAN_MAX(a, b) ((b) > (a) ? (b) : (a))

#define MEDIAN3(T, NAME, CH, STRIP, WIDTH) \
static void NAME(const T *restrict flat, T *restrict oflat, index_t rows, index_t lanes, index_t y0, index_t y1, \
                 T *restrict buf) \
{ \
    for (index_t y = y0; y < y1; y += 2) { \
        for (index_t c0 = 0; c0 < lanes; c0 += STRIP) { \
            index_t m = min_i(STRIP, lanes - c0), n_in = m + 2 * CH; \
            index_t lo = max_i(0, 1 * CH - c0), hi = min_i(n_in, 1 * CH + lanes - c0); \
            for (index_t r = 0; r < 4; r++) { \
                const T *src = flat + min_i(max_i(y + r - 1, 0), rows - 1) * lanes; \
                T *o = buf + r * WIDTH; \
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 1 * CH, (size_t)(hi - lo) * sizeof(T)); \
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % CH]; \
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - CH + (c0 + j) % CH]; \
            } \
            for (index_t x = 0; x < (STRIP + 2 * CH + 31) / 32 * 32; x++) { \
                T t4 = MEDIAN_MIN(buf[1 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 0 * CH + x]); \
                buf[4 * WIDTH + 0 * CH + x] = t4; \
                T t5 = MEDIAN_MAX(buf[1 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 0 * CH + x]); \
                buf[5 * WIDTH + 0 * CH + x] = t5; \
                T t24 = MEDIAN_MIN(buf[0 * WIDTH + 0 * CH + x], buf[0 * WIDTH + 1 * CH + x]); \
                buf[6 * WIDTH + 0 * CH + x] = t24; \
                T t25 = MEDIAN_MAX(buf[0 * WIDTH + 0 * CH + x], buf[0 * WIDTH + 1 * CH + x]); \
                buf[7 * WIDTH + 0 * CH + x] = t25; \
                T t36 = MEDIAN_MIN(buf[3 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 1 * CH + x]); \
                buf[8 * WIDTH + 0 * CH + x] = t36; \
                T t37 = MEDIAN_MAX(buf[3 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 1 * CH + x]); \
                buf[9 * WIDTH + 0 * CH + x] = t37; \
            } \
            for (index_t x = 0; x < (STRIP + 1 * CH + 31) / 32 * 32; x++) { \
                T t6 = MEDIAN_MIN(buf[4 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 1 * CH + x]); \
                buf[2 * WIDTH + 0 * CH + x] = t6; \
                T t7 = MEDIAN_MAX(buf[4 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 1 * CH + x]); \
                T t8 = MEDIAN_MIN(buf[5 * WIDTH + 0 * CH + x], buf[5 * WIDTH + 1 * CH + x]); \
                T t9 = MEDIAN_MAX(buf[5 * WIDTH + 0 * CH + x], buf[5 * WIDTH + 1 * CH + x]); \
                buf[1 * WIDTH + 0 * CH + x] = t9; \
                T t10 = MEDIAN_MIN(t8, t7); \
                buf[10 * WIDTH + 0 * CH + x] = t10; \
                T t11 = MEDIAN_MAX(t8, t7); \
                buf[11 * WIDTH + 0 * CH + x] = t11; \
                T t26 = MEDIAN_MIN(buf[0 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 1 * CH + x]); \
                buf[12 * WIDTH + 0 * CH + x] = t26; \
                T t27 = MEDIAN_MAX(buf[0 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 1 * CH + x]); \
                T t28 = MEDIAN_MIN(buf[7 * WIDTH + 1 * CH + x], t27); \
                buf[13 * WIDTH + 0 * CH + x] = t28; \
                T t29 = MEDIAN_MAX(buf[7 * WIDTH + 1 * CH + x], t27); \
                buf[14 * WIDTH + 0 * CH + x] = t29; \
                T t38 = MEDIAN_MIN(buf[3 * WIDTH + 0 * CH + x], buf[8 * WIDTH + 1 * CH + x]); \
                buf[15 * WIDTH + 0 * CH + x] = t38; \
                T t39 = MEDIAN_MAX(buf[3 * WIDTH + 0 * CH + x], buf[8 * WIDTH + 1 * CH + x]); \
                T t40 = MEDIAN_MIN(buf[9 * WIDTH + 1 * CH + x], t39); \
                buf[16 * WIDTH + 0 * CH + x] = t40; \
                T t41 = MEDIAN_MAX(buf[9 * WIDTH + 1 * CH + x], t39); \
                buf[17 * WIDTH + 0 * CH + x] = t41; \
            } \
            for (index_t x = 0; x < (STRIP + 0 * CH + 31) / 32 * 32; x++) { \
                T t13 = MEDIAN_MAX(buf[4 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 1 * CH + x]); \
                T t14 = MEDIAN_MIN(buf[11 * WIDTH + 1 * CH + x], t13); \
                T t15 = MEDIAN_MAX(buf[11 * WIDTH + 1 * CH + x], t13); \
                T t16 = MEDIAN_MIN(buf[5 * WIDTH + 0 * CH + x], buf[10 * WIDTH + 1 * CH + x]); \
                T t17 = MEDIAN_MAX(buf[5 * WIDTH + 0 * CH + x], buf[10 * WIDTH + 1 * CH + x]); \
                T t18 = MEDIAN_MIN(buf[1 * WIDTH + 1 * CH + x], t17); \
                T t20 = MEDIAN_MIN(t16, t14); \
                T t21 = MEDIAN_MAX(t16, t14); \
                T t22 = MEDIAN_MIN(t18, t15); \
                T t23 = MEDIAN_MAX(t18, t15); \
                T t30 = MEDIAN_MAX(t20, buf[14 * WIDTH + 0 * CH + x]); \
                T t31 = MEDIAN_MAX(t21, buf[13 * WIDTH + 0 * CH + x]); \
                T t32 = MEDIAN_MAX(t22, buf[12 * WIDTH + 0 * CH + x]); \
                T t33 = MEDIAN_MIN(t30, t31); \
                T t34 = MEDIAN_MIN(t33, t32); \
                T t35 = MEDIAN_MIN(t34, t23); \
                buf[9 * WIDTH + 0 * CH + x] = t35; \
                T t42 = MEDIAN_MAX(t20, buf[17 * WIDTH + 0 * CH + x]); \
                T t43 = MEDIAN_MAX(t21, buf[16 * WIDTH + 0 * CH + x]); \
                T t44 = MEDIAN_MAX(t22, buf[15 * WIDTH + 0 * CH + x]); \
                T t45 = MEDIAN_MIN(t42, t43); \
                T t46 = MEDIAN_MIN(t45, t44); \
                T t47 = MEDIAN_MIN(t46, t23); \
                buf[8 * WIDTH + 0 * CH + x] = t47; \
            } \
            memcpy(oflat + y * lanes + c0, buf + 9 * WIDTH, (size_t)m * sizeof(T)); \
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 8 * WIDTH, (size_t)m * sizeof(T)); \
        } \
    } \
}
MEDIAN3(uint8_t, median3_c1_uint8, 1, 256, 320)
MEDIAN3(uint16_t, median3_c1_uint16, 1, 256, 320)
MEDIAN3(uint8_t, median3_c3_uint8, 3, 256, 320)
MEDIAN3(uint16_t, median3_c3_uint16, 3, 256, 320)

#define MEDIAN5(T, NAME, CH, STRIP, WIDTH) \
static void NAME(const T *restrict flat, T *restrict oflat, index_t rows, index_t lanes, index_t y0, index_t y1, \
                 T *restrict buf) \
{ \
    for (index_t y = y0; y < y1; y += 2) { \
        for (index_t c0 = 0; c0 < lanes; c0 += STRIP) { \
            index_t m = min_i(STRIP, lanes - c0), n_in = m + 4 * CH; \
            index_t lo = max_i(0, 2 * CH - c0), hi = min_i(n_in, 2 * CH + lanes - c0); \
            for (index_t r = 0; r < 6; r++) { \
                const T *src = flat + min_i(max_i(y + r - 2, 0), rows - 1) * lanes; \
                T *o = buf + r * WIDTH; \
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 2 * CH, (size_t)(hi - lo) * sizeof(T)); \
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % CH]; \
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - CH + (c0 + j) % CH]; \
            } \
            for (index_t x = 0; x < (STRIP + 4 * CH + 31) / 32 * 32; x++) { \
                T t6 = MEDIAN_MIN(buf[1 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 0 * CH + x]); \
                T t7 = MEDIAN_MAX(buf[1 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 0 * CH + x]); \
                T t8 = MEDIAN_MIN(buf[3 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 0 * CH + x]); \
                T t9 = MEDIAN_MAX(buf[3 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 0 * CH + x]); \
                T t10 = MEDIAN_MIN(t6, t8); \
                buf[6 * WIDTH + 0 * CH + x] = t10; \
                T t11 = MEDIAN_MAX(t6, t8); \
                T t12 = MEDIAN_MIN(t7, t9); \
                T t13 = MEDIAN_MAX(t7, t9); \
                buf[7 * WIDTH + 0 * CH + x] = t13; \
                T t14 = MEDIAN_MIN(t12, t11); \
                buf[8 * WIDTH + 0 * CH + x] = t14; \
                T t15 = MEDIAN_MAX(t12, t11); \
                buf[9 * WIDTH + 0 * CH + x] = t15; \
                T t142 = MEDIAN_MIN(buf[0 * WIDTH + 0 * CH + x], buf[0 * WIDTH + 1 * CH + x]); \
                buf[10 * WIDTH + 0 * CH + x] = t142; \
                T t143 = MEDIAN_MAX(buf[0 * WIDTH + 0 * CH + x], buf[0 * WIDTH + 1 * CH + x]); \
                buf[11 * WIDTH + 0 * CH + x] = t143; \
                T t168 = MEDIAN_MIN(buf[5 * WIDTH + 0 * CH + x], buf[5 * WIDTH + 1 * CH + x]); \
                buf[12 * WIDTH + 0 * CH + x] = t168; \
                T t169 = MEDIAN_MAX(buf[5 * WIDTH + 0 * CH + x], buf[5 * WIDTH + 1 * CH + x]); \
                buf[13 * WIDTH + 0 * CH + x] = t169; \
            } \
            for (index_t x = 0; x < (STRIP + 3 * CH + 31) / 32 * 32; x++) { \
                T t16 = MEDIAN_MIN(buf[6 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 1 * CH + x]); \
                buf[4 * WIDTH + 0 * CH + x] = t16; \
                T t17 = MEDIAN_MAX(buf[6 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 1 * CH + x]); \
                T t18 = MEDIAN_MIN(buf[9 * WIDTH + 0 * CH + x], buf[9 * WIDTH + 1 * CH + x]); \
                T t19 = MEDIAN_MAX(buf[9 * WIDTH + 0 * CH + x], buf[9 * WIDTH + 1 * CH + x]); \
                T t20 = MEDIAN_MIN(t18, t17); \
                T t21 = MEDIAN_MAX(t18, t17); \
                T t22 = MEDIAN_MIN(buf[8 * WIDTH + 0 * CH + x], buf[8 * WIDTH + 1 * CH + x]); \
                T t23 = MEDIAN_MAX(buf[8 * WIDTH + 0 * CH + x], buf[8 * WIDTH + 1 * CH + x]); \
                T t24 = MEDIAN_MIN(buf[7 * WIDTH + 0 * CH + x], buf[7 * WIDTH + 1 * CH + x]); \
                T t25 = MEDIAN_MAX(buf[7 * WIDTH + 0 * CH + x], buf[7 * WIDTH + 1 * CH + x]); \
                buf[3 * WIDTH + 0 * CH + x] = t25; \
                T t26 = MEDIAN_MIN(t24, t23); \
                T t27 = MEDIAN_MAX(t24, t23); \
                T t28 = MEDIAN_MIN(t22, t20); \
                buf[2 * WIDTH + 0 * CH + x] = t28; \
                T t29 = MEDIAN_MAX(t22, t20); \
                buf[1 * WIDTH + 0 * CH + x] = t29; \
                T t30 = MEDIAN_MIN(t26, t21); \
                buf[14 * WIDTH + 0 * CH + x] = t30; \
                T t31 = MEDIAN_MAX(t26, t21); \
                buf[15 * WIDTH + 0 * CH + x] = t31; \
                T t32 = MEDIAN_MIN(t27, t19); \
                buf[16 * WIDTH + 0 * CH + x] = t32; \
                T t33 = MEDIAN_MAX(t27, t19); \
                buf[17 * WIDTH + 0 * CH + x] = t33; \
                T t144 = MEDIAN_MIN(buf[0 * WIDTH + 0 * CH + x], buf[10 * WIDTH + 1 * CH + x]); \
                buf[18 * WIDTH + 0 * CH + x] = t144; \
                T t145 = MEDIAN_MAX(buf[0 * WIDTH + 0 * CH + x], buf[10 * WIDTH + 1 * CH + x]); \
                T t146 = MEDIAN_MIN(buf[11 * WIDTH + 1 * CH + x], t145); \
                buf[19 * WIDTH + 0 * CH + x] = t146; \
                T t147 = MEDIAN_MAX(buf[11 * WIDTH + 1 * CH + x], t145); \
                buf[20 * WIDTH + 0 * CH + x] = t147; \
                T t170 = MEDIAN_MIN(buf[5 * WIDTH + 0 * CH + x], buf[12 * WIDTH + 1 * CH + x]); \
                buf[21 * WIDTH + 0 * CH + x] = t170; \
                T t171 = MEDIAN_MAX(buf[5 * WIDTH + 0 * CH + x], buf[12 * WIDTH + 1 * CH + x]); \
                T t172 = MEDIAN_MIN(buf[13 * WIDTH + 1 * CH + x], t171); \
                buf[22 * WIDTH + 0 * CH + x] = t172; \
                T t173 = MEDIAN_MAX(buf[13 * WIDTH + 1 * CH + x], t171); \
                buf[23 * WIDTH + 0 * CH + x] = t173; \
            } \
            for (index_t x = 0; x < (STRIP + 2 * CH + 31) / 32 * 32; x++) { \
                T t34 = MEDIAN_MIN(buf[6 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 1 * CH + x]); \
                buf[5 * WIDTH + 0 * CH + x] = t34; \
                T t35 = MEDIAN_MAX(buf[6 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 1 * CH + x]); \
                T t36 = MEDIAN_MIN(buf[15 * WIDTH + 1 * CH + x], t35); \
                T t37 = MEDIAN_MAX(buf[15 * WIDTH + 1 * CH + x], t35); \
                T t38 = MEDIAN_MIN(buf[9 * WIDTH + 0 * CH + x], buf[1 * WIDTH + 1 * CH + x]); \
                T t39 = MEDIAN_MAX(buf[9 * WIDTH + 0 * CH + x], buf[1 * WIDTH + 1 * CH + x]); \
                T t40 = MEDIAN_MIN(buf[17 * WIDTH + 1 * CH + x], t39); \
                T t41 = MEDIAN_MAX(buf[17 * WIDTH + 1 * CH + x], t39); \
                T t42 = MEDIAN_MIN(t38, t36); \
                T t43 = MEDIAN_MAX(t38, t36); \
                T t44 = MEDIAN_MIN(t40, t37); \
                T t45 = MEDIAN_MAX(t40, t37); \
                T t46 = MEDIAN_MIN(buf[8 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 1 * CH + x]); \
                T t47 = MEDIAN_MAX(buf[8 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 1 * CH + x]); \
                T t48 = MEDIAN_MIN(buf[16 * WIDTH + 1 * CH + x], t47); \
                T t49 = MEDIAN_MAX(buf[16 * WIDTH + 1 * CH + x], t47); \
                T t50 = MEDIAN_MIN(buf[7 * WIDTH + 0 * CH + x], buf[14 * WIDTH + 1 * CH + x]); \
                T t51 = MEDIAN_MAX(buf[7 * WIDTH + 0 * CH + x], buf[14 * WIDTH + 1 * CH + x]); \
                T t52 = MEDIAN_MIN(buf[3 * WIDTH + 1 * CH + x], t51); \
                T t53 = MEDIAN_MAX(buf[3 * WIDTH + 1 * CH + x], t51); \
                buf[0 * WIDTH + 0 * CH + x] = t53; \
                T t54 = MEDIAN_MIN(t50, t48); \
                T t55 = MEDIAN_MAX(t50, t48); \
                T t56 = MEDIAN_MIN(t52, t49); \
                T t57 = MEDIAN_MAX(t52, t49); \
                T t58 = MEDIAN_MIN(t46, t42); \
                buf[24 * WIDTH + 0 * CH + x] = t58; \
                T t59 = MEDIAN_MAX(t46, t42); \
                buf[25 * WIDTH + 0 * CH + x] = t59; \
                T t60 = MEDIAN_MIN(t54, t43); \
                buf[26 * WIDTH + 0 * CH + x] = t60; \
                T t61 = MEDIAN_MAX(t54, t43); \
                buf[27 * WIDTH + 0 * CH + x] = t61; \
                T t62 = MEDIAN_MIN(t55, t44); \
                buf[28 * WIDTH + 0 * CH + x] = t62; \
                T t63 = MEDIAN_MAX(t55, t44); \
                buf[29 * WIDTH + 0 * CH + x] = t63; \
                T t64 = MEDIAN_MIN(t56, t45); \
                buf[30 * WIDTH + 0 * CH + x] = t64; \
                T t65 = MEDIAN_MAX(t56, t45); \
                buf[31 * WIDTH + 0 * CH + x] = t65; \
                T t66 = MEDIAN_MIN(t57, t41); \
                buf[32 * WIDTH + 0 * CH + x] = t66; \
                T t67 = MEDIAN_MAX(t57, t41); \
                buf[33 * WIDTH + 0 * CH + x] = t67; \
                T t148 = MEDIAN_MIN(buf[10 * WIDTH + 0 * CH + x], buf[18 * WIDTH + 2 * CH + x]); \
                buf[34 * WIDTH + 0 * CH + x] = t148; \
                T t149 = MEDIAN_MAX(buf[10 * WIDTH + 0 * CH + x], buf[18 * WIDTH + 2 * CH + x]); \
                T t150 = MEDIAN_MIN(buf[20 * WIDTH + 2 * CH + x], t149); \
                T t151 = MEDIAN_MAX(buf[20 * WIDTH + 2 * CH + x], t149); \
                T t152 = MEDIAN_MIN(buf[11 * WIDTH + 0 * CH + x], buf[19 * WIDTH + 2 * CH + x]); \
                T t153 = MEDIAN_MAX(buf[11 * WIDTH + 0 * CH + x], buf[19 * WIDTH + 2 * CH + x]); \
                T t154 = MEDIAN_MIN(t152, t150); \
                buf[35 * WIDTH + 0 * CH + x] = t154; \
                T t155 = MEDIAN_MAX(t152, t150); \
                buf[36 * WIDTH + 0 * CH + x] = t155; \
                T t156 = MEDIAN_MIN(t153, t151); \
                buf[37 * WIDTH + 0 * CH + x] = t156; \
                T t157 = MEDIAN_MAX(t153, t151); \
                buf[38 * WIDTH + 0 * CH + x] = t157; \
                T t174 = MEDIAN_MIN(buf[12 * WIDTH + 0 * CH + x], buf[21 * WIDTH + 2 * CH + x]); \
                buf[39 * WIDTH + 0 * CH + x] = t174; \
                T t175 = MEDIAN_MAX(buf[12 * WIDTH + 0 * CH + x], buf[21 * WIDTH + 2 * CH + x]); \
                T t176 = MEDIAN_MIN(buf[23 * WIDTH + 2 * CH + x], t175); \
                T t177 = MEDIAN_MAX(buf[23 * WIDTH + 2 * CH + x], t175); \
                T t178 = MEDIAN_MIN(buf[13 * WIDTH + 0 * CH + x], buf[22 * WIDTH + 2 * CH + x]); \
                T t179 = MEDIAN_MAX(buf[13 * WIDTH + 0 * CH + x], buf[22 * WIDTH + 2 * CH + x]); \
                T t180 = MEDIAN_MIN(t178, t176); \
                buf[40 * WIDTH + 0 * CH + x] = t180; \
                T t181 = MEDIAN_MAX(t178, t176); \
                buf[41 * WIDTH + 0 * CH + x] = t181; \
                T t182 = MEDIAN_MIN(t179, t177); \
                buf[42 * WIDTH + 0 * CH + x] = t182; \
                T t183 = MEDIAN_MAX(t179, t177); \
                buf[43 * WIDTH + 0 * CH + x] = t183; \
            } \
            for (index_t x = 0; x < (STRIP + 0 * CH + 31) / 32 * 32; x++) { \
                T t69 = MEDIAN_MAX(buf[4 * WIDTH + 0 * CH + x], buf[5 * WIDTH + 2 * CH + x]); \
                T t70 = MEDIAN_MIN(buf[31 * WIDTH + 2 * CH + x], t69); \
                T t71 = MEDIAN_MAX(buf[31 * WIDTH + 2 * CH + x], t69); \
                T t72 = MEDIAN_MIN(buf[15 * WIDTH + 0 * CH + x], buf[27 * WIDTH + 2 * CH + x]); \
                T t73 = MEDIAN_MAX(buf[15 * WIDTH + 0 * CH + x], buf[27 * WIDTH + 2 * CH + x]); \
                T t75 = MEDIAN_MAX(t72, t70); \
                T t76 = MEDIAN_MIN(t73, t71); \
                T t79 = MEDIAN_MAX(buf[1 * WIDTH + 0 * CH + x], buf[25 * WIDTH + 2 * CH + x]); \
                T t80 = MEDIAN_MIN(buf[33 * WIDTH + 2 * CH + x], t79); \
                T t82 = MEDIAN_MIN(buf[17 * WIDTH + 0 * CH + x], buf[29 * WIDTH + 2 * CH + x]); \
                T t84 = MEDIAN_MIN(t82, t80); \
                T t85 = MEDIAN_MAX(t82, t80); \
                T t91 = MEDIAN_MAX(t84, t75); \
                T t92 = MEDIAN_MIN(t85, t76); \
                T t93 = MEDIAN_MAX(t85, t76); \
                T t97 = MEDIAN_MAX(buf[2 * WIDTH + 0 * CH + x], buf[24 * WIDTH + 2 * CH + x]); \
                T t98 = MEDIAN_MIN(buf[32 * WIDTH + 2 * CH + x], t97); \
                T t99 = MEDIAN_MAX(buf[32 * WIDTH + 2 * CH + x], t97); \
                T t100 = MEDIAN_MIN(buf[16 * WIDTH + 0 * CH + x], buf[28 * WIDTH + 2 * CH + x]); \
                T t101 = MEDIAN_MAX(buf[16 * WIDTH + 0 * CH + x], buf[28 * WIDTH + 2 * CH + x]); \
                T t103 = MEDIAN_MAX(t100, t98); \
                T t104 = MEDIAN_MIN(t101, t99); \
                T t107 = MEDIAN_MAX(buf[14 * WIDTH + 0 * CH + x], buf[26 * WIDTH + 2 * CH + x]); \
                T t108 = MEDIAN_MIN(buf[0 * WIDTH + 2 * CH + x], t107); \
                T t110 = MEDIAN_MIN(buf[3 * WIDTH + 0 * CH + x], buf[30 * WIDTH + 2 * CH + x]); \
                T t112 = MEDIAN_MIN(t110, t108); \
                T t113 = MEDIAN_MAX(t110, t108); \
                T t118 = MEDIAN_MIN(t112, t103); \
                T t119 = MEDIAN_MAX(t112, t103); \
                T t120 = MEDIAN_MIN(t113, t104); \
                T t130 = MEDIAN_MIN(t118, t91); \
                T t131 = MEDIAN_MAX(t118, t91); \
                T t132 = MEDIAN_MIN(t119, t92); \
                T t133 = MEDIAN_MAX(t119, t92); \
                T t134 = MEDIAN_MIN(t120, t93); \
                T t135 = MEDIAN_MAX(t120, t93); \
                T t158 = MEDIAN_MAX(t130, buf[38 * WIDTH + 0 * CH + x]); \
                T t159 = MEDIAN_MAX(t131, buf[37 * WIDTH + 0 * CH + x]); \
                T t160 = MEDIAN_MAX(t132, buf[36 * WIDTH + 0 * CH + x]); \
                T t161 = MEDIAN_MAX(t133, buf[35 * WIDTH + 0 * CH + x]); \
                T t162 = MEDIAN_MAX(t134, buf[34 * WIDTH + 0 * CH + x]); \
                T t163 = MEDIAN_MIN(t158, t159); \
                T t164 = MEDIAN_MIN(t163, t160); \
                T t165 = MEDIAN_MIN(t164, t161); \
                T t166 = MEDIAN_MIN(t165, t162); \
                T t167 = MEDIAN_MIN(t166, t135); \
                buf[23 * WIDTH + 0 * CH + x] = t167; \
                T t184 = MEDIAN_MAX(t130, buf[43 * WIDTH + 0 * CH + x]); \
                T t185 = MEDIAN_MAX(t131, buf[42 * WIDTH + 0 * CH + x]); \
                T t186 = MEDIAN_MAX(t132, buf[41 * WIDTH + 0 * CH + x]); \
                T t187 = MEDIAN_MAX(t133, buf[40 * WIDTH + 0 * CH + x]); \
                T t188 = MEDIAN_MAX(t134, buf[39 * WIDTH + 0 * CH + x]); \
                T t189 = MEDIAN_MIN(t184, t185); \
                T t190 = MEDIAN_MIN(t189, t186); \
                T t191 = MEDIAN_MIN(t190, t187); \
                T t192 = MEDIAN_MIN(t191, t188); \
                T t193 = MEDIAN_MIN(t192, t135); \
                buf[22 * WIDTH + 0 * CH + x] = t193; \
            } \
            memcpy(oflat + y * lanes + c0, buf + 23 * WIDTH, (size_t)m * sizeof(T)); \
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 22 * WIDTH, (size_t)m * sizeof(T)); \
        } \
    } \
}
MEDIAN5(uint8_t, median5_c1_uint8, 1, 256, 320)
MEDIAN5(uint16_t, median5_c1_uint16, 1, 256, 320)
MEDIAN5(uint8_t, median5_c3_uint8, 3, 256, 320)
MEDIAN5(uint16_t, median5_c3_uint16, 3, 256, 320)

#define MEDIAN7(T, NAME, CH, STRIP, WIDTH) \
static void NAME(const T *restrict flat, T *restrict oflat, index_t rows, index_t lanes, index_t y0, index_t y1, \
                 T *restrict buf) \
{ \
    for (index_t y = y0; y < y1; y += 2) { \
        for (index_t c0 = 0; c0 < lanes; c0 += STRIP) { \
            index_t m = min_i(STRIP, lanes - c0), n_in = m + 6 * CH; \
            index_t lo = max_i(0, 3 * CH - c0), hi = min_i(n_in, 3 * CH + lanes - c0); \
            for (index_t r = 0; r < 8; r++) { \
                const T *src = flat + min_i(max_i(y + r - 3, 0), rows - 1) * lanes; \
                T *o = buf + r * WIDTH; \
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 3 * CH, (size_t)(hi - lo) * sizeof(T)); \
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % CH]; \
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - CH + (c0 + j) % CH]; \
            } \
            for (index_t x = 0; x < (STRIP + 6 * CH + 31) / 32 * 32; x++) { \
                T t8 = MEDIAN_MIN(buf[2 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 0 * CH + x]); \
                T t9 = MEDIAN_MAX(buf[2 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 0 * CH + x]); \
                T t10 = MEDIAN_MIN(buf[1 * WIDTH + 0 * CH + x], t8); \
                T t11 = MEDIAN_MAX(buf[1 * WIDTH + 0 * CH + x], t8); \
                T t12 = MEDIAN_MIN(t9, t11); \
                T t13 = MEDIAN_MAX(t9, t11); \
                T t14 = MEDIAN_MIN(buf[5 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 0 * CH + x]); \
                T t15 = MEDIAN_MAX(buf[5 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 0 * CH + x]); \
                T t16 = MEDIAN_MIN(buf[4 * WIDTH + 0 * CH + x], t14); \
                T t17 = MEDIAN_MAX(buf[4 * WIDTH + 0 * CH + x], t14); \
                T t18 = MEDIAN_MIN(t15, t17); \
                T t19 = MEDIAN_MAX(t15, t17); \
                T t20 = MEDIAN_MIN(t10, t16); \
                buf[8 * WIDTH + 0 * CH + x] = t20; \
                T t21 = MEDIAN_MAX(t10, t16); \
                T t22 = MEDIAN_MIN(t13, t19); \
                T t23 = MEDIAN_MAX(t13, t19); \
                buf[9 * WIDTH + 0 * CH + x] = t23; \
                T t24 = MEDIAN_MIN(t22, t21); \
                T t25 = MEDIAN_MAX(t22, t21); \
                T t26 = MEDIAN_MIN(t12, t18); \
                T t27 = MEDIAN_MAX(t12, t18); \
                T t28 = MEDIAN_MIN(t26, t24); \
                buf[10 * WIDTH + 0 * CH + x] = t28; \
                T t29 = MEDIAN_MAX(t26, t24); \
                buf[11 * WIDTH + 0 * CH + x] = t29; \
                T t30 = MEDIAN_MIN(t27, t25); \
                buf[12 * WIDTH + 0 * CH + x] = t30; \
                T t31 = MEDIAN_MAX(t27, t25); \
                buf[13 * WIDTH + 0 * CH + x] = t31; \
                T t420 = MEDIAN_MIN(buf[0 * WIDTH + 0 * CH + x], buf[0 * WIDTH + 1 * CH + x]); \
                buf[14 * WIDTH + 0 * CH + x] = t420; \
                T t421 = MEDIAN_MAX(buf[0 * WIDTH + 0 * CH + x], buf[0 * WIDTH + 1 * CH + x]); \
                buf[15 * WIDTH + 0 * CH + x] = t421; \
                T t462 = MEDIAN_MIN(buf[7 * WIDTH + 0 * CH + x], buf[7 * WIDTH + 1 * CH + x]); \
                buf[16 * WIDTH + 0 * CH + x] = t462; \
                T t463 = MEDIAN_MAX(buf[7 * WIDTH + 0 * CH + x], buf[7 * WIDTH + 1 * CH + x]); \
                buf[17 * WIDTH + 0 * CH + x] = t463; \
            } \
            for (index_t x = 0; x < (STRIP + 5 * CH + 31) / 32 * 32; x++) { \
                T t32 = MEDIAN_MIN(buf[8 * WIDTH + 0 * CH + x], buf[8 * WIDTH + 1 * CH + x]); \
                buf[6 * WIDTH + 0 * CH + x] = t32; \
                T t33 = MEDIAN_MAX(buf[8 * WIDTH + 0 * CH + x], buf[8 * WIDTH + 1 * CH + x]); \
                T t34 = MEDIAN_MIN(buf[13 * WIDTH + 0 * CH + x], buf[13 * WIDTH + 1 * CH + x]); \
                T t35 = MEDIAN_MAX(buf[13 * WIDTH + 0 * CH + x], buf[13 * WIDTH + 1 * CH + x]); \
                T t36 = MEDIAN_MIN(t34, t33); \
                T t37 = MEDIAN_MAX(t34, t33); \
                T t38 = MEDIAN_MIN(buf[11 * WIDTH + 0 * CH + x], buf[11 * WIDTH + 1 * CH + x]); \
                T t39 = MEDIAN_MAX(buf[11 * WIDTH + 0 * CH + x], buf[11 * WIDTH + 1 * CH + x]); \
                T t40 = MEDIAN_MIN(t38, t36); \
                T t41 = MEDIAN_MAX(t38, t36); \
                T t42 = MEDIAN_MIN(t39, t37); \
                T t43 = MEDIAN_MAX(t39, t37); \
                T t44 = MEDIAN_MIN(buf[10 * WIDTH + 0 * CH + x], buf[10 * WIDTH + 1 * CH + x]); \
                T t45 = MEDIAN_MAX(buf[10 * WIDTH + 0 * CH + x], buf[10 * WIDTH + 1 * CH + x]); \
                T t46 = MEDIAN_MIN(buf[9 * WIDTH + 0 * CH + x], buf[9 * WIDTH + 1 * CH + x]); \
                T t47 = MEDIAN_MAX(buf[9 * WIDTH + 0 * CH + x], buf[9 * WIDTH + 1 * CH + x]); \
                buf[5 * WIDTH + 0 * CH + x] = t47; \
                T t48 = MEDIAN_MIN(t46, t45); \
                T t49 = MEDIAN_MAX(t46, t45); \
                T t50 = MEDIAN_MIN(buf[12 * WIDTH + 0 * CH + x], buf[12 * WIDTH + 1 * CH + x]); \
                T t51 = MEDIAN_MAX(buf[12 * WIDTH + 0 * CH + x], buf[12 * WIDTH + 1 * CH + x]); \
                T t52 = MEDIAN_MIN(t50, t48); \
                T t53 = MEDIAN_MAX(t50, t48); \
                T t54 = MEDIAN_MIN(t51, t49); \
                T t55 = MEDIAN_MAX(t51, t49); \
                T t56 = MEDIAN_MIN(t44, t40); \
                buf[4 * WIDTH + 0 * CH + x] = t56; \
                T t57 = MEDIAN_MAX(t44, t40); \
                buf[3 * WIDTH + 0 * CH + x] = t57; \
                T t58 = MEDIAN_MIN(t52, t41); \
                buf[2 * WIDTH + 0 * CH + x] = t58; \
                T t59 = MEDIAN_MAX(t52, t41); \
                buf[1 * WIDTH + 0 * CH + x] = t59; \
                T t60 = MEDIAN_MIN(t53, t42); \
                buf[18 * WIDTH + 0 * CH + x] = t60; \
                T t61 = MEDIAN_MAX(t53, t42); \
                buf[19 * WIDTH + 0 * CH + x] = t61; \
                T t62 = MEDIAN_MIN(t54, t43); \
                buf[20 * WIDTH + 0 * CH + x] = t62; \
                T t63 = MEDIAN_MAX(t54, t43); \
                buf[21 * WIDTH + 0 * CH + x] = t63; \
                T t64 = MEDIAN_MIN(t55, t35); \
                buf[22 * WIDTH + 0 * CH + x] = t64; \
                T t65 = MEDIAN_MAX(t55, t35); \
                buf[23 * WIDTH + 0 * CH + x] = t65; \
                T t422 = MEDIAN_MIN(buf[0 * WIDTH + 0 * CH + x], buf[14 * WIDTH + 1 * CH + x]); \
                buf[24 * WIDTH + 0 * CH + x] = t422; \
                T t423 = MEDIAN_MAX(buf[0 * WIDTH + 0 * CH + x], buf[14 * WIDTH + 1 * CH + x]); \
                T t424 = MEDIAN_MIN(buf[15 * WIDTH + 1 * CH + x], t423); \
                buf[25 * WIDTH + 0 * CH + x] = t424; \
                T t425 = MEDIAN_MAX(buf[15 * WIDTH + 1 * CH + x], t423); \
                buf[26 * WIDTH + 0 * CH + x] = t425; \
                T t426 = MEDIAN_MIN(buf[14 * WIDTH + 0 * CH + x], buf[14 * WIDTH + 2 * CH + x]); \
                buf[27 * WIDTH + 0 * CH + x] = t426; \
                T t427 = MEDIAN_MAX(buf[14 * WIDTH + 0 * CH + x], buf[14 * WIDTH + 2 * CH + x]); \
                T t428 = MEDIAN_MIN(buf[15 * WIDTH + 0 * CH + x], buf[15 * WIDTH + 2 * CH + x]); \
                T t429 = MEDIAN_MAX(buf[15 * WIDTH + 0 * CH + x], buf[15 * WIDTH + 2 * CH + x]); \
                buf[28 * WIDTH + 0 * CH + x] = t429; \
                T t430 = MEDIAN_MIN(t428, t427); \
                buf[29 * WIDTH + 0 * CH + x] = t430; \
                T t431 = MEDIAN_MAX(t428, t427); \
                buf[30 * WIDTH + 0 * CH + x] = t431; \
                T t464 = MEDIAN_MIN(buf[7 * WIDTH + 0 * CH + x], buf[16 * WIDTH + 1 * CH + x]); \
                buf[31 * WIDTH + 0 * CH + x] = t464; \
                T t465 = MEDIAN_MAX(buf[7 * WIDTH + 0 * CH + x], buf[16 * WIDTH + 1 * CH + x]); \
                T t466 = MEDIAN_MIN(buf[17 * WIDTH + 1 * CH + x], t465); \
                buf[32 * WIDTH + 0 * CH + x] = t466; \
                T t467 = MEDIAN_MAX(buf[17 * WIDTH + 1 * CH + x], t465); \
                buf[33 * WIDTH + 0 * CH + x] = t467; \
                T t468 = MEDIAN_MIN(buf[16 * WIDTH + 0 * CH + x], buf[16 * WIDTH + 2 * CH + x]); \
                buf[34 * WIDTH + 0 * CH + x] = t468; \
                T t469 = MEDIAN_MAX(buf[16 * WIDTH + 0 * CH + x], buf[16 * WIDTH + 2 * CH + x]); \
                T t470 = MEDIAN_MIN(buf[17 * WIDTH + 0 * CH + x], buf[17 * WIDTH + 2 * CH + x]); \
                T t471 = MEDIAN_MAX(buf[17 * WIDTH + 0 * CH + x], buf[17 * WIDTH + 2 * CH + x]); \
                buf[35 * WIDTH + 0 * CH + x] = t471; \
                T t472 = MEDIAN_MIN(t470, t469); \
                buf[36 * WIDTH + 0 * CH + x] = t472; \
                T t473 = MEDIAN_MAX(t470, t469); \
                buf[37 * WIDTH + 0 * CH + x] = t473; \
            } \
            for (index_t x = 0; x < (STRIP + 3 * CH + 31) / 32 * 32; x++) { \
                T t66 = MEDIAN_MIN(buf[8 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 1 * CH + x]); \
                buf[17 * WIDTH + 0 * CH + x] = t66; \
                T t67 = MEDIAN_MAX(buf[8 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 1 * CH + x]); \
                T t68 = MEDIAN_MIN(buf[21 * WIDTH + 1 * CH + x], t67); \
                T t69 = MEDIAN_MAX(buf[21 * WIDTH + 1 * CH + x], t67); \
                T t70 = MEDIAN_MIN(buf[13 * WIDTH + 0 * CH + x], buf[1 * WIDTH + 1 * CH + x]); \
                T t71 = MEDIAN_MAX(buf[13 * WIDTH + 0 * CH + x], buf[1 * WIDTH + 1 * CH + x]); \
                T t72 = MEDIAN_MIN(t70, t68); \
                T t73 = MEDIAN_MAX(t70, t68); \
                T t74 = MEDIAN_MIN(t71, t69); \
                T t75 = MEDIAN_MAX(t71, t69); \
                T t76 = MEDIAN_MIN(buf[11 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 1 * CH + x]); \
                T t77 = MEDIAN_MAX(buf[11 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 1 * CH + x]); \
                T t78 = MEDIAN_MIN(buf[23 * WIDTH + 1 * CH + x], t77); \
                T t79 = MEDIAN_MAX(buf[23 * WIDTH + 1 * CH + x], t77); \
                T t80 = MEDIAN_MIN(buf[19 * WIDTH + 1 * CH + x], t78); \
                T t81 = MEDIAN_MAX(buf[19 * WIDTH + 1 * CH + x], t78); \
                T t82 = MEDIAN_MIN(t76, t72); \
                T t83 = MEDIAN_MAX(t76, t72); \
                T t84 = MEDIAN_MIN(t80, t73); \
                T t85 = MEDIAN_MAX(t80, t73); \
                T t86 = MEDIAN_MIN(t81, t74); \
                T t87 = MEDIAN_MAX(t81, t74); \
                T t88 = MEDIAN_MIN(t79, t75); \
                T t89 = MEDIAN_MAX(t79, t75); \
                T t90 = MEDIAN_MIN(buf[10 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 1 * CH + x]); \
                T t91 = MEDIAN_MAX(buf[10 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 1 * CH + x]); \
                T t92 = MEDIAN_MIN(buf[22 * WIDTH + 1 * CH + x], t91); \
                T t93 = MEDIAN_MAX(buf[22 * WIDTH + 1 * CH + x], t91); \
                T t94 = MEDIAN_MIN(buf[9 * WIDTH + 0 * CH + x], buf[18 * WIDTH + 1 * CH + x]); \
                T t95 = MEDIAN_MAX(buf[9 * WIDTH + 0 * CH + x], buf[18 * WIDTH + 1 * CH + x]); \
                T t96 = MEDIAN_MIN(t94, t92); \
                T t97 = MEDIAN_MAX(t94, t92); \
                T t98 = MEDIAN_MIN(t95, t93); \
                T t99 = MEDIAN_MAX(t95, t93); \
                T t100 = MEDIAN_MIN(buf[12 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 1 * CH + x]); \
                T t101 = MEDIAN_MAX(buf[12 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 1 * CH + x]); \
                T t102 = MEDIAN_MIN(buf[5 * WIDTH + 1 * CH + x], t101); \
                T t103 = MEDIAN_MAX(buf[5 * WIDTH + 1 * CH + x], t101); \
                T t104 = MEDIAN_MIN(buf[20 * WIDTH + 1 * CH + x], t102); \
                T t105 = MEDIAN_MAX(buf[20 * WIDTH + 1 * CH + x], t102); \
                T t106 = MEDIAN_MIN(t100, t96); \
                T t107 = MEDIAN_MAX(t100, t96); \
                T t108 = MEDIAN_MIN(t104, t97); \
                T t109 = MEDIAN_MAX(t104, t97); \
                T t110 = MEDIAN_MIN(t105, t98); \
                T t111 = MEDIAN_MAX(t105, t98); \
                T t112 = MEDIAN_MIN(t103, t99); \
                T t113 = MEDIAN_MAX(t103, t99); \
                buf[16 * WIDTH + 0 * CH + x] = t113; \
                T t114 = MEDIAN_MIN(t90, t82); \
                buf[15 * WIDTH + 0 * CH + x] = t114; \
                T t115 = MEDIAN_MAX(t90, t82); \
                buf[14 * WIDTH + 0 * CH + x] = t115; \
                T t116 = MEDIAN_MIN(t106, t83); \
                buf[7 * WIDTH + 0 * CH + x] = t116; \
                T t117 = MEDIAN_MAX(t106, t83); \
                buf[0 * WIDTH + 0 * CH + x] = t117; \
                T t118 = MEDIAN_MIN(t107, t84); \
                buf[38 * WIDTH + 0 * CH + x] = t118; \
                T t119 = MEDIAN_MAX(t107, t84); \
                buf[39 * WIDTH + 0 * CH + x] = t119; \
                T t120 = MEDIAN_MIN(t108, t85); \
                buf[40 * WIDTH + 0 * CH + x] = t120; \
                T t121 = MEDIAN_MAX(t108, t85); \
                buf[41 * WIDTH + 0 * CH + x] = t121; \
                T t122 = MEDIAN_MIN(t109, t86); \
                buf[42 * WIDTH + 0 * CH + x] = t122; \
                T t123 = MEDIAN_MAX(t109, t86); \
                buf[43 * WIDTH + 0 * CH + x] = t123; \
                T t124 = MEDIAN_MIN(t110, t87); \
                buf[44 * WIDTH + 0 * CH + x] = t124; \
                T t125 = MEDIAN_MAX(t110, t87); \
                buf[45 * WIDTH + 0 * CH + x] = t125; \
                T t126 = MEDIAN_MIN(t111, t88); \
                buf[46 * WIDTH + 0 * CH + x] = t126; \
                T t127 = MEDIAN_MAX(t111, t88); \
                buf[47 * WIDTH + 0 * CH + x] = t127; \
                T t128 = MEDIAN_MIN(t112, t89); \
                buf[48 * WIDTH + 0 * CH + x] = t128; \
                T t129 = MEDIAN_MAX(t112, t89); \
                buf[49 * WIDTH + 0 * CH + x] = t129; \
                T t130 = MEDIAN_MIN(buf[6 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 2 * CH + x]); \
                buf[50 * WIDTH + 0 * CH + x] = t130; \
                T t131 = MEDIAN_MAX(buf[6 * WIDTH + 0 * CH + x], buf[6 * WIDTH + 2 * CH + x]); \
                T t132 = MEDIAN_MIN(buf[21 * WIDTH + 0 * CH + x], buf[21 * WIDTH + 2 * CH + x]); \
                T t133 = MEDIAN_MAX(buf[21 * WIDTH + 0 * CH + x], buf[21 * WIDTH + 2 * CH + x]); \
                T t134 = MEDIAN_MIN(t132, t131); \
                T t135 = MEDIAN_MAX(t132, t131); \
                T t136 = MEDIAN_MIN(buf[1 * WIDTH + 0 * CH + x], buf[1 * WIDTH + 2 * CH + x]); \
                T t137 = MEDIAN_MAX(buf[1 * WIDTH + 0 * CH + x], buf[1 * WIDTH + 2 * CH + x]); \
                T t138 = MEDIAN_MIN(t136, t134); \
                T t139 = MEDIAN_MAX(t136, t134); \
                T t140 = MEDIAN_MIN(t137, t135); \
                T t141 = MEDIAN_MAX(t137, t135); \
                T t142 = MEDIAN_MIN(buf[3 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 2 * CH + x]); \
                T t143 = MEDIAN_MAX(buf[3 * WIDTH + 0 * CH + x], buf[3 * WIDTH + 2 * CH + x]); \
                T t144 = MEDIAN_MIN(buf[23 * WIDTH + 0 * CH + x], buf[23 * WIDTH + 2 * CH + x]); \
                T t145 = MEDIAN_MAX(buf[23 * WIDTH + 0 * CH + x], buf[23 * WIDTH + 2 * CH + x]); \
                T t146 = MEDIAN_MIN(t144, t143); \
                T t147 = MEDIAN_MAX(t144, t143); \
                T t148 = MEDIAN_MIN(buf[19 * WIDTH + 0 * CH + x], buf[19 * WIDTH + 2 * CH + x]); \
                T t149 = MEDIAN_MAX(buf[19 * WIDTH + 0 * CH + x], buf[19 * WIDTH + 2 * CH + x]); \
                T t150 = MEDIAN_MIN(t148, t146); \
                T t151 = MEDIAN_MAX(t148, t146); \
                T t152 = MEDIAN_MIN(t149, t147); \
                T t153 = MEDIAN_MAX(t149, t147); \
                T t154 = MEDIAN_MIN(t142, t138); \
                T t155 = MEDIAN_MAX(t142, t138); \
                T t156 = MEDIAN_MIN(t150, t139); \
                T t157 = MEDIAN_MAX(t150, t139); \
                T t158 = MEDIAN_MIN(t151, t140); \
                T t159 = MEDIAN_MAX(t151, t140); \
                T t160 = MEDIAN_MIN(t152, t141); \
                T t161 = MEDIAN_MAX(t152, t141); \
                T t162 = MEDIAN_MIN(t153, t133); \
                T t163 = MEDIAN_MAX(t153, t133); \
                T t164 = MEDIAN_MIN(buf[4 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 2 * CH + x]); \
                T t165 = MEDIAN_MAX(buf[4 * WIDTH + 0 * CH + x], buf[4 * WIDTH + 2 * CH + x]); \
                T t166 = MEDIAN_MIN(buf[22 * WIDTH + 0 * CH + x], buf[22 * WIDTH + 2 * CH + x]); \
                T t167 = MEDIAN_MAX(buf[22 * WIDTH + 0 * CH + x], buf[22 * WIDTH + 2 * CH + x]); \
                T t168 = MEDIAN_MIN(t166, t165); \
                T t169 = MEDIAN_MAX(t166, t165); \
                T t170 = MEDIAN_MIN(buf[18 * WIDTH + 0 * CH + x], buf[18 * WIDTH + 2 * CH + x]); \
                T t171 = MEDIAN_MAX(buf[18 * WIDTH + 0 * CH + x], buf[18 * WIDTH + 2 * CH + x]); \
                T t172 = MEDIAN_MIN(t170, t168); \
                T t173 = MEDIAN_MAX(t170, t168); \
                T t174 = MEDIAN_MIN(t171, t169); \
                T t175 = MEDIAN_MAX(t171, t169); \
                T t176 = MEDIAN_MIN(buf[2 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 2 * CH + x]); \
                T t177 = MEDIAN_MAX(buf[2 * WIDTH + 0 * CH + x], buf[2 * WIDTH + 2 * CH + x]); \
                T t178 = MEDIAN_MIN(buf[5 * WIDTH + 0 * CH + x], buf[5 * WIDTH + 2 * CH + x]); \
                T t179 = MEDIAN_MAX(buf[5 * WIDTH + 0 * CH + x], buf[5 * WIDTH + 2 * CH + x]); \
                buf[51 * WIDTH + 0 * CH + x] = t179; \
                T t180 = MEDIAN_MIN(t178, t177); \
                T t181 = MEDIAN_MAX(t178, t177); \
                T t182 = MEDIAN_MIN(buf[20 * WIDTH + 0 * CH + x], buf[20 * WIDTH + 2 * CH + x]); \
                T t183 = MEDIAN_MAX(buf[20 * WIDTH + 0 * CH + x], buf[20 * WIDTH + 2 * CH + x]); \
                T t184 = MEDIAN_MIN(t182, t180); \
                T t185 = MEDIAN_MAX(t182, t180); \
                T t186 = MEDIAN_MIN(t183, t181); \
                T t187 = MEDIAN_MAX(t183, t181); \
                T t188 = MEDIAN_MIN(t176, t172); \
                T t189 = MEDIAN_MAX(t176, t172); \
                T t190 = MEDIAN_MIN(t184, t173); \
                T t191 = MEDIAN_MAX(t184, t173); \
                T t192 = MEDIAN_MIN(t185, t174); \
                T t193 = MEDIAN_MAX(t185, t174); \
                T t194 = MEDIAN_MIN(t186, t175); \
                T t195 = MEDIAN_MAX(t186, t175); \
                T t196 = MEDIAN_MIN(t187, t167); \
                T t197 = MEDIAN_MAX(t187, t167); \
                T t198 = MEDIAN_MIN(t164, t154); \
                buf[52 * WIDTH + 0 * CH + x] = t198; \
                T t199 = MEDIAN_MAX(t164, t154); \
                buf[53 * WIDTH + 0 * CH + x] = t199; \
                T t200 = MEDIAN_MIN(t188, t155); \
                buf[54 * WIDTH + 0 * CH + x] = t200; \
                T t201 = MEDIAN_MAX(t188, t155); \
                buf[55 * WIDTH + 0 * CH + x] = t201; \
                T t202 = MEDIAN_MIN(t189, t156); \
                buf[56 * WIDTH + 0 * CH + x] = t202; \
                T t203 = MEDIAN_MAX(t189, t156); \
                buf[57 * WIDTH + 0 * CH + x] = t203; \
                T t204 = MEDIAN_MIN(t190, t157); \
                buf[58 * WIDTH + 0 * CH + x] = t204; \
                T t205 = MEDIAN_MAX(t190, t157); \
                buf[59 * WIDTH + 0 * CH + x] = t205; \
                T t206 = MEDIAN_MIN(t191, t158); \
                buf[60 * WIDTH + 0 * CH + x] = t206; \
                T t207 = MEDIAN_MAX(t191, t158); \
                buf[61 * WIDTH + 0 * CH + x] = t207; \
                T t208 = MEDIAN_MIN(t192, t159); \
                buf[62 * WIDTH + 0 * CH + x] = t208; \
                T t209 = MEDIAN_MAX(t192, t159); \
                buf[63 * WIDTH + 0 * CH + x] = t209; \
                T t210 = MEDIAN_MIN(t193, t160); \
                buf[64 * WIDTH + 0 * CH + x] = t210; \
                T t211 = MEDIAN_MAX(t193, t160); \
                buf[65 * WIDTH + 0 * CH + x] = t211; \
                T t212 = MEDIAN_MIN(t194, t161); \
                buf[66 * WIDTH + 0 * CH + x] = t212; \
                T t213 = MEDIAN_MAX(t194, t161); \
                buf[67 * WIDTH + 0 * CH + x] = t213; \
                T t214 = MEDIAN_MIN(t195, t162); \
                buf[68 * WIDTH + 0 * CH + x] = t214; \
                T t215 = MEDIAN_MAX(t195, t162); \
                buf[69 * WIDTH + 0 * CH + x] = t215; \
                T t216 = MEDIAN_MIN(t196, t163); \
                buf[70 * WIDTH + 0 * CH + x] = t216; \
                T t217 = MEDIAN_MAX(t196, t163); \
                buf[71 * WIDTH + 0 * CH + x] = t217; \
                T t218 = MEDIAN_MIN(t197, t145); \
                buf[72 * WIDTH + 0 * CH + x] = t218; \
                T t219 = MEDIAN_MAX(t197, t145); \
                buf[73 * WIDTH + 0 * CH + x] = t219; \
                T t432 = MEDIAN_MIN(buf[24 * WIDTH + 0 * CH + x], buf[27 * WIDTH + 3 * CH + x]); \
                buf[74 * WIDTH + 0 * CH + x] = t432; \
                T t433 = MEDIAN_MAX(buf[24 * WIDTH + 0 * CH + x], buf[27 * WIDTH + 3 * CH + x]); \
                T t434 = MEDIAN_MIN(buf[26 * WIDTH + 0 * CH + x], buf[30 * WIDTH + 3 * CH + x]); \
                T t435 = MEDIAN_MAX(buf[26 * WIDTH + 0 * CH + x], buf[30 * WIDTH + 3 * CH + x]); \
                T t436 = MEDIAN_MIN(t434, t433); \
                T t437 = MEDIAN_MAX(t434, t433); \
                T t438 = MEDIAN_MIN(buf[25 * WIDTH + 0 * CH + x], buf[29 * WIDTH + 3 * CH + x]); \
                T t439 = MEDIAN_MAX(buf[25 * WIDTH + 0 * CH + x], buf[29 * WIDTH + 3 * CH + x]); \
                T t440 = MEDIAN_MIN(buf[28 * WIDTH + 3 * CH + x], t439); \
                T t441 = MEDIAN_MAX(buf[28 * WIDTH + 3 * CH + x], t439); \
                T t442 = MEDIAN_MIN(t438, t436); \
                buf[75 * WIDTH + 0 * CH + x] = t442; \
                T t443 = MEDIAN_MAX(t438, t436); \
                buf[76 * WIDTH + 0 * CH + x] = t443; \
                T t444 = MEDIAN_MIN(t440, t437); \
                buf[77 * WIDTH + 0 * CH + x] = t444; \
                T t445 = MEDIAN_MAX(t440, t437); \
                buf[78 * WIDTH + 0 * CH + x] = t445; \
                T t446 = MEDIAN_MIN(t441, t435); \
                buf[79 * WIDTH + 0 * CH + x] = t446; \
                T t447 = MEDIAN_MAX(t441, t435); \
                buf[80 * WIDTH + 0 * CH + x] = t447; \
                T t474 = MEDIAN_MIN(buf[31 * WIDTH + 0 * CH + x], buf[34 * WIDTH + 3 * CH + x]); \
                buf[81 * WIDTH + 0 * CH + x] = t474; \
                T t475 = MEDIAN_MAX(buf[31 * WIDTH + 0 * CH + x], buf[34 * WIDTH + 3 * CH + x]); \
                T t476 = MEDIAN_MIN(buf[33 * WIDTH + 0 * CH + x], buf[37 * WIDTH + 3 * CH + x]); \
                T t477 = MEDIAN_MAX(buf[33 * WIDTH + 0 * CH + x], buf[37 * WIDTH + 3 * CH + x]); \
                T t478 = MEDIAN_MIN(t476, t475); \
                T t479 = MEDIAN_MAX(t476, t475); \
                T t480 = MEDIAN_MIN(buf[32 * WIDTH + 0 * CH + x], buf[36 * WIDTH + 3 * CH + x]); \
                T t481 = MEDIAN_MAX(buf[32 * WIDTH + 0 * CH + x], buf[36 * WIDTH + 3 * CH + x]); \
                T t482 = MEDIAN_MIN(buf[35 * WIDTH + 3 * CH + x], t481); \
                T t483 = MEDIAN_MAX(buf[35 * WIDTH + 3 * CH + x], t481); \
                T t484 = MEDIAN_MIN(t480, t478); \
                buf[82 * WIDTH + 0 * CH + x] = t484; \
                T t485 = MEDIAN_MAX(t480, t478); \
                buf[83 * WIDTH + 0 * CH + x] = t485; \
                T t486 = MEDIAN_MIN(t482, t479); \
                buf[84 * WIDTH + 0 * CH + x] = t486; \
                T t487 = MEDIAN_MAX(t482, t479); \
                buf[85 * WIDTH + 0 * CH + x] = t487; \
                T t488 = MEDIAN_MIN(t483, t477); \
                buf[86 * WIDTH + 0 * CH + x] = t488; \
                T t489 = MEDIAN_MAX(t483, t477); \
                buf[87 * WIDTH + 0 * CH + x] = t489; \
            } \
            for (index_t x = 0; x < (STRIP + 0 * CH + 31) / 32 * 32; x++) { \
                T t221 = MEDIAN_MAX(buf[17 * WIDTH + 0 * CH + x], buf[50 * WIDTH + 3 * CH + x]); \
                T t222 = MEDIAN_MIN(buf[49 * WIDTH + 0 * CH + x], buf[67 * WIDTH + 3 * CH + x]); \
                T t225 = MEDIAN_MAX(t222, t221); \
                T t227 = MEDIAN_MAX(buf[41 * WIDTH + 0 * CH + x], buf[59 * WIDTH + 3 * CH + x]); \
                T t230 = MEDIAN_MIN(t227, t225); \
                T t233 = MEDIAN_MAX(buf[0 * WIDTH + 0 * CH + x], buf[55 * WIDTH + 3 * CH + x]); \
                T t234 = MEDIAN_MIN(buf[71 * WIDTH + 3 * CH + x], t233); \
                T t236 = MEDIAN_MIN(buf[45 * WIDTH + 0 * CH + x], buf[63 * WIDTH + 3 * CH + x]); \
                T t239 = MEDIAN_MAX(t236, t234); \
                T t246 = MEDIAN_MIN(t239, t230); \
                T t247 = MEDIAN_MAX(t239, t230); \
                T t253 = MEDIAN_MAX(buf[14 * WIDTH + 0 * CH + x], buf[53 * WIDTH + 3 * CH + x]); \
                T t254 = MEDIAN_MIN(buf[69 * WIDTH + 3 * CH + x], t253); \
                T t255 = MEDIAN_MAX(buf[69 * WIDTH + 3 * CH + x], t253); \
                T t256 = MEDIAN_MIN(buf[43 * WIDTH + 0 * CH + x], buf[61 * WIDTH + 3 * CH + x]); \
                T t257 = MEDIAN_MAX(buf[43 * WIDTH + 0 * CH + x], buf[61 * WIDTH + 3 * CH + x]); \
                T t259 = MEDIAN_MAX(t256, t254); \
                T t260 = MEDIAN_MIN(t257, t255); \
                T t263 = MEDIAN_MAX(buf[39 * WIDTH + 0 * CH + x], buf[57 * WIDTH + 3 * CH + x]); \
                T t264 = MEDIAN_MIN(buf[73 * WIDTH + 3 * CH + x], t263); \
                T t266 = MEDIAN_MIN(buf[47 * WIDTH + 0 * CH + x], buf[65 * WIDTH + 3 * CH + x]); \
                T t268 = MEDIAN_MIN(t266, t264); \
                T t269 = MEDIAN_MAX(t266, t264); \
                T t275 = MEDIAN_MAX(t268, t259); \
                T t276 = MEDIAN_MIN(t269, t260); \
                T t288 = MEDIAN_MIN(t275, t246); \
                T t289 = MEDIAN_MAX(t275, t246); \
                T t290 = MEDIAN_MIN(t276, t247); \
                T t291 = MEDIAN_MAX(t276, t247); \
                T t301 = MEDIAN_MAX(buf[15 * WIDTH + 0 * CH + x], buf[52 * WIDTH + 3 * CH + x]); \
                T t302 = MEDIAN_MIN(buf[16 * WIDTH + 0 * CH + x], buf[68 * WIDTH + 3 * CH + x]); \
                T t304 = MEDIAN_MIN(t302, t301); \
                T t305 = MEDIAN_MAX(t302, t301); \
                T t306 = MEDIAN_MIN(buf[42 * WIDTH + 0 * CH + x], buf[60 * WIDTH + 3 * CH + x]); \
                T t307 = MEDIAN_MAX(buf[42 * WIDTH + 0 * CH + x], buf[60 * WIDTH + 3 * CH + x]); \
                T t309 = MEDIAN_MAX(t306, t304); \
                T t310 = MEDIAN_MIN(t307, t305); \
                T t313 = MEDIAN_MAX(buf[38 * WIDTH + 0 * CH + x], buf[56 * WIDTH + 3 * CH + x]); \
                T t314 = MEDIAN_MIN(buf[72 * WIDTH + 3 * CH + x], t313); \
                T t316 = MEDIAN_MIN(buf[46 * WIDTH + 0 * CH + x], buf[64 * WIDTH + 3 * CH + x]); \
                T t318 = MEDIAN_MIN(t316, t314); \
                T t319 = MEDIAN_MAX(t316, t314); \
                T t325 = MEDIAN_MAX(t318, t309); \
                T t326 = MEDIAN_MIN(t319, t310); \
                T t327 = MEDIAN_MAX(t319, t310); \
                T t333 = MEDIAN_MAX(buf[7 * WIDTH + 0 * CH + x], buf[54 * WIDTH + 3 * CH + x]); \
                T t334 = MEDIAN_MIN(buf[70 * WIDTH + 3 * CH + x], t333); \
                T t335 = MEDIAN_MAX(buf[70 * WIDTH + 3 * CH + x], t333); \
                T t336 = MEDIAN_MIN(buf[44 * WIDTH + 0 * CH + x], buf[62 * WIDTH + 3 * CH + x]); \
                T t337 = MEDIAN_MAX(buf[44 * WIDTH + 0 * CH + x], buf[62 * WIDTH + 3 * CH + x]); \
                T t339 = MEDIAN_MAX(t336, t334); \
                T t340 = MEDIAN_MIN(t337, t335); \
                T t343 = MEDIAN_MAX(buf[40 * WIDTH + 0 * CH + x], buf[58 * WIDTH + 3 * CH + x]); \
                T t344 = MEDIAN_MIN(buf[51 * WIDTH + 3 * CH + x], t343); \
                T t346 = MEDIAN_MIN(buf[48 * WIDTH + 0 * CH + x], buf[66 * WIDTH + 3 * CH + x]); \
                T t348 = MEDIAN_MIN(t346, t344); \
                T t349 = MEDIAN_MAX(t346, t344); \
                T t354 = MEDIAN_MIN(t348, t339); \
                T t355 = MEDIAN_MAX(t348, t339); \
                T t356 = MEDIAN_MIN(t349, t340); \
                T t367 = MEDIAN_MAX(t354, t325); \
                T t368 = MEDIAN_MIN(t355, t326); \
                T t369 = MEDIAN_MAX(t355, t326); \
                T t370 = MEDIAN_MIN(t356, t327); \
                T t396 = MEDIAN_MIN(t367, t288); \
                T t397 = MEDIAN_MAX(t367, t288); \
                T t398 = MEDIAN_MIN(t368, t289); \
                T t399 = MEDIAN_MAX(t368, t289); \
                T t400 = MEDIAN_MIN(t369, t290); \
                T t401 = MEDIAN_MAX(t369, t290); \
                T t402 = MEDIAN_MIN(t370, t291); \
                T t403 = MEDIAN_MAX(t370, t291); \
                T t448 = MEDIAN_MAX(t396, buf[80 * WIDTH + 0 * CH + x]); \
                T t449 = MEDIAN_MAX(t397, buf[79 * WIDTH + 0 * CH + x]); \
                T t450 = MEDIAN_MAX(t398, buf[78 * WIDTH + 0 * CH + x]); \
                T t451 = MEDIAN_MAX(t399, buf[77 * WIDTH + 0 * CH + x]); \
                T t452 = MEDIAN_MAX(t400, buf[76 * WIDTH + 0 * CH + x]); \
                T t453 = MEDIAN_MAX(t401, buf[75 * WIDTH + 0 * CH + x]); \
                T t454 = MEDIAN_MAX(t402, buf[74 * WIDTH + 0 * CH + x]); \
                T t455 = MEDIAN_MIN(t448, t449); \
                T t456 = MEDIAN_MIN(t455, t450); \
                T t457 = MEDIAN_MIN(t456, t451); \
                T t458 = MEDIAN_MIN(t457, t452); \
                T t459 = MEDIAN_MIN(t458, t453); \
                T t460 = MEDIAN_MIN(t459, t454); \
                T t461 = MEDIAN_MIN(t460, t403); \
                buf[37 * WIDTH + 0 * CH + x] = t461; \
                T t490 = MEDIAN_MAX(t396, buf[87 * WIDTH + 0 * CH + x]); \
                T t491 = MEDIAN_MAX(t397, buf[86 * WIDTH + 0 * CH + x]); \
                T t492 = MEDIAN_MAX(t398, buf[85 * WIDTH + 0 * CH + x]); \
                T t493 = MEDIAN_MAX(t399, buf[84 * WIDTH + 0 * CH + x]); \
                T t494 = MEDIAN_MAX(t400, buf[83 * WIDTH + 0 * CH + x]); \
                T t495 = MEDIAN_MAX(t401, buf[82 * WIDTH + 0 * CH + x]); \
                T t496 = MEDIAN_MAX(t402, buf[81 * WIDTH + 0 * CH + x]); \
                T t497 = MEDIAN_MIN(t490, t491); \
                T t498 = MEDIAN_MIN(t497, t492); \
                T t499 = MEDIAN_MIN(t498, t493); \
                T t500 = MEDIAN_MIN(t499, t494); \
                T t501 = MEDIAN_MIN(t500, t495); \
                T t502 = MEDIAN_MIN(t501, t496); \
                T t503 = MEDIAN_MIN(t502, t403); \
                buf[36 * WIDTH + 0 * CH + x] = t503; \
            } \
            memcpy(oflat + y * lanes + c0, buf + 37 * WIDTH, (size_t)m * sizeof(T)); \
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 36 * WIDTH, (size_t)m * sizeof(T)); \
        } \
    } \
}
MEDIAN7(uint8_t, median7_c1_uint8, 1, 256, 320)
MEDIAN7(uint16_t, median7_c1_uint16, 1, 256, 320)
MEDIAN7(uint8_t, median7_c3_uint8, 3, 256, 320)
MEDIAN7(uint16_t, median7_c3_uint16, 3, 256, 320)

/* Rows y0 .. y1-1 of the size x size median of flat ((rows, lanes) lanes, channels interleaved, elements of
 * itemsize bytes) into oflat. Returns -2 when no kernel is generated for them, -1 when memory is short. */
EXPORT int dr_median(const void *flat, void *oflat, index_t rows, index_t lanes, int size, int channels,
                     int itemsize, index_t y0, index_t y1)
{
    void *buf = NULL;
    if (size == 3 && channels == 1 && itemsize == 1) {
        buf = calloc(5760, 1);
        if (buf) median3_c1_uint8(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 3 && channels == 1 && itemsize == 2) {
        buf = calloc(5760, 2);
        if (buf) median3_c1_uint16(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 3 && channels == 3 && itemsize == 1) {
        buf = calloc(5760, 1);
        if (buf) median3_c3_uint8(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 3 && channels == 3 && itemsize == 2) {
        buf = calloc(5760, 2);
        if (buf) median3_c3_uint16(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 5 && channels == 1 && itemsize == 1) {
        buf = calloc(14080, 1);
        if (buf) median5_c1_uint8(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 5 && channels == 1 && itemsize == 2) {
        buf = calloc(14080, 2);
        if (buf) median5_c1_uint16(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 5 && channels == 3 && itemsize == 1) {
        buf = calloc(14080, 1);
        if (buf) median5_c3_uint8(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 5 && channels == 3 && itemsize == 2) {
        buf = calloc(14080, 2);
        if (buf) median5_c3_uint16(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 7 && channels == 1 && itemsize == 1) {
        buf = calloc(28160, 1);
        if (buf) median7_c1_uint8(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 7 && channels == 1 && itemsize == 2) {
        buf = calloc(28160, 2);
        if (buf) median7_c1_uint16(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 7 && channels == 3 && itemsize == 1) {
        buf = calloc(28160, 1);
        if (buf) median7_c3_uint8(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else if (size == 7 && channels == 3 && itemsize == 2) {
        buf = calloc(28160, 2);
        if (buf) median7_c3_uint16(flat, oflat, rows, lanes, y0, y1, buf);
    }
    else
        return -2;
    int status = buf ? 0 : -1;
    free(buf);
    return status;
}
/* ---- END GENERATED ---- */
