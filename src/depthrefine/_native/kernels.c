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
#define DEPTHREFINE_KERNELS_ABI 3

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
            for (index_t j = 0; j < cols - 1; j++) out[j] = lut[color_distance2(row + 3 * (j + 1), row + 3 * j, 3)];
        } else {
            for (index_t j = 0; j < cols - 1; j++)
                out[j] = lut[color_distance2(row + channels * (j + 1), row + channels * j, channels)];
        }
        out[cols - 1] = 0.0f;
        float *restrict out_y = wy + i * cols;
        if (i + 1 < rows) {
            const uint8_t *restrict below = row + cols * channels;
            if (channels == 3) {
                for (index_t j = 0; j < cols; j++) out_y[j] = lut[color_distance2(below + 3 * j, row + 3 * j, 3)];
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

/* One output row of dr_enlarge_rows: n near small rows' planes n0..n2 and values x_near, the far ones f0..f2,
 * x_far, the guide's row (W pixels of 3 channels). */
static void enlarge_row(float *restrict out_row, index_t W, index_t w, const uint8_t *restrict row,
                        const uint8_t *restrict n0, const uint8_t *restrict n1, const uint8_t *restrict n2,
                        const uint8_t *restrict f0, const uint8_t *restrict f1, const uint8_t *restrict f2,
                        const float *restrict x_near, const float *restrict x_far, const float *restrict lut)
{
    const float tiny = 1e-30f;
    for (index_t c = 0; c < W; c++) {
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
        profile[k] = bilinear(edges, rows, cols, (double)j + (double)t * (double)nx, (double)i + (double)t * (double)ny);
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
