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
 * round keeps no cluster (no positive weight: the numba kernel's result is then left to it). */
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

static void median3_c1_uint8(const uint8_t *restrict flat, uint8_t *restrict oflat, index_t rows, index_t lanes,
                             index_t y0, index_t y1, uint8_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 2;
            index_t lo = max_i(0, 1 - c0), hi = min_i(n_in, 1 + lanes - c0);
            for (index_t r = 0; r < 4; r++) {
                const uint8_t *src = flat + min_i(max_i(y + r - 1, 0), rows - 1) * lanes;
                uint8_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 1, (size_t)(hi - lo) * sizeof(uint8_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 1];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 1 + (c0 + j) % 1];
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t4 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                buf[1280 + x] = t4;
                uint8_t t5 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                buf[1600 + x] = t5;
                uint8_t t24 = MEDIAN_MIN(buf[0 + x], buf[1 + x]);
                buf[1920 + x] = t24;
                uint8_t t25 = MEDIAN_MAX(buf[0 + x], buf[1 + x]);
                buf[2240 + x] = t25;
                uint8_t t36 = MEDIAN_MIN(buf[960 + x], buf[961 + x]);
                buf[2560 + x] = t36;
                uint8_t t37 = MEDIAN_MAX(buf[960 + x], buf[961 + x]);
                buf[2880 + x] = t37;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t6 = MEDIAN_MIN(buf[1280 + x], buf[1281 + x]);
                buf[640 + x] = t6;
                uint8_t t7 = MEDIAN_MAX(buf[1280 + x], buf[1281 + x]);
                uint8_t t8 = MEDIAN_MIN(buf[1600 + x], buf[1601 + x]);
                uint8_t t9 = MEDIAN_MAX(buf[1600 + x], buf[1601 + x]);
                buf[320 + x] = t9;
                uint8_t t10 = MEDIAN_MIN(t8, t7);
                buf[3200 + x] = t10;
                uint8_t t11 = MEDIAN_MAX(t8, t7);
                buf[3520 + x] = t11;
                uint8_t t26 = MEDIAN_MIN(buf[0 + x], buf[1921 + x]);
                buf[3840 + x] = t26;
                uint8_t t27 = MEDIAN_MAX(buf[0 + x], buf[1921 + x]);
                uint8_t t28 = MEDIAN_MIN(buf[2241 + x], t27);
                buf[4160 + x] = t28;
                uint8_t t29 = MEDIAN_MAX(buf[2241 + x], t27);
                buf[4480 + x] = t29;
                uint8_t t38 = MEDIAN_MIN(buf[960 + x], buf[2561 + x]);
                buf[4800 + x] = t38;
                uint8_t t39 = MEDIAN_MAX(buf[960 + x], buf[2561 + x]);
                uint8_t t40 = MEDIAN_MIN(buf[2881 + x], t39);
                buf[5120 + x] = t40;
                uint8_t t41 = MEDIAN_MAX(buf[2881 + x], t39);
                buf[5440 + x] = t41;
            }
            for (index_t x = 0; x < 256; x++) {
                uint8_t t13 = MEDIAN_MAX(buf[1280 + x], buf[641 + x]);
                uint8_t t14 = MEDIAN_MIN(buf[3521 + x], t13);
                uint8_t t15 = MEDIAN_MAX(buf[3521 + x], t13);
                uint8_t t16 = MEDIAN_MIN(buf[1600 + x], buf[3201 + x]);
                uint8_t t17 = MEDIAN_MAX(buf[1600 + x], buf[3201 + x]);
                uint8_t t18 = MEDIAN_MIN(buf[321 + x], t17);
                uint8_t t20 = MEDIAN_MIN(t16, t14);
                uint8_t t21 = MEDIAN_MAX(t16, t14);
                uint8_t t22 = MEDIAN_MIN(t18, t15);
                uint8_t t23 = MEDIAN_MAX(t18, t15);
                uint8_t t30 = MEDIAN_MAX(t20, buf[4480 + x]);
                uint8_t t31 = MEDIAN_MAX(t21, buf[4160 + x]);
                uint8_t t32 = MEDIAN_MAX(t22, buf[3840 + x]);
                uint8_t t33 = MEDIAN_MIN(t30, t31);
                uint8_t t34 = MEDIAN_MIN(t33, t32);
                uint8_t t35 = MEDIAN_MIN(t34, t23);
                buf[2880 + x] = t35;
                uint8_t t42 = MEDIAN_MAX(t20, buf[5440 + x]);
                uint8_t t43 = MEDIAN_MAX(t21, buf[5120 + x]);
                uint8_t t44 = MEDIAN_MAX(t22, buf[4800 + x]);
                uint8_t t45 = MEDIAN_MIN(t42, t43);
                uint8_t t46 = MEDIAN_MIN(t45, t44);
                uint8_t t47 = MEDIAN_MIN(t46, t23);
                buf[2560 + x] = t47;
            }
            memcpy(oflat + y * lanes + c0, buf + 2880, (size_t)m * sizeof(uint8_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 2560, (size_t)m * sizeof(uint8_t));
        }
    }
}

static void median3_c1_uint16(const uint16_t *restrict flat, uint16_t *restrict oflat, index_t rows, index_t lanes,
                              index_t y0, index_t y1, uint16_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 2;
            index_t lo = max_i(0, 1 - c0), hi = min_i(n_in, 1 + lanes - c0);
            for (index_t r = 0; r < 4; r++) {
                const uint16_t *src = flat + min_i(max_i(y + r - 1, 0), rows - 1) * lanes;
                uint16_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 1, (size_t)(hi - lo) * sizeof(uint16_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 1];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 1 + (c0 + j) % 1];
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t4 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                buf[1280 + x] = t4;
                uint16_t t5 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                buf[1600 + x] = t5;
                uint16_t t24 = MEDIAN_MIN(buf[0 + x], buf[1 + x]);
                buf[1920 + x] = t24;
                uint16_t t25 = MEDIAN_MAX(buf[0 + x], buf[1 + x]);
                buf[2240 + x] = t25;
                uint16_t t36 = MEDIAN_MIN(buf[960 + x], buf[961 + x]);
                buf[2560 + x] = t36;
                uint16_t t37 = MEDIAN_MAX(buf[960 + x], buf[961 + x]);
                buf[2880 + x] = t37;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t6 = MEDIAN_MIN(buf[1280 + x], buf[1281 + x]);
                buf[640 + x] = t6;
                uint16_t t7 = MEDIAN_MAX(buf[1280 + x], buf[1281 + x]);
                uint16_t t8 = MEDIAN_MIN(buf[1600 + x], buf[1601 + x]);
                uint16_t t9 = MEDIAN_MAX(buf[1600 + x], buf[1601 + x]);
                buf[320 + x] = t9;
                uint16_t t10 = MEDIAN_MIN(t8, t7);
                buf[3200 + x] = t10;
                uint16_t t11 = MEDIAN_MAX(t8, t7);
                buf[3520 + x] = t11;
                uint16_t t26 = MEDIAN_MIN(buf[0 + x], buf[1921 + x]);
                buf[3840 + x] = t26;
                uint16_t t27 = MEDIAN_MAX(buf[0 + x], buf[1921 + x]);
                uint16_t t28 = MEDIAN_MIN(buf[2241 + x], t27);
                buf[4160 + x] = t28;
                uint16_t t29 = MEDIAN_MAX(buf[2241 + x], t27);
                buf[4480 + x] = t29;
                uint16_t t38 = MEDIAN_MIN(buf[960 + x], buf[2561 + x]);
                buf[4800 + x] = t38;
                uint16_t t39 = MEDIAN_MAX(buf[960 + x], buf[2561 + x]);
                uint16_t t40 = MEDIAN_MIN(buf[2881 + x], t39);
                buf[5120 + x] = t40;
                uint16_t t41 = MEDIAN_MAX(buf[2881 + x], t39);
                buf[5440 + x] = t41;
            }
            for (index_t x = 0; x < 256; x++) {
                uint16_t t13 = MEDIAN_MAX(buf[1280 + x], buf[641 + x]);
                uint16_t t14 = MEDIAN_MIN(buf[3521 + x], t13);
                uint16_t t15 = MEDIAN_MAX(buf[3521 + x], t13);
                uint16_t t16 = MEDIAN_MIN(buf[1600 + x], buf[3201 + x]);
                uint16_t t17 = MEDIAN_MAX(buf[1600 + x], buf[3201 + x]);
                uint16_t t18 = MEDIAN_MIN(buf[321 + x], t17);
                uint16_t t20 = MEDIAN_MIN(t16, t14);
                uint16_t t21 = MEDIAN_MAX(t16, t14);
                uint16_t t22 = MEDIAN_MIN(t18, t15);
                uint16_t t23 = MEDIAN_MAX(t18, t15);
                uint16_t t30 = MEDIAN_MAX(t20, buf[4480 + x]);
                uint16_t t31 = MEDIAN_MAX(t21, buf[4160 + x]);
                uint16_t t32 = MEDIAN_MAX(t22, buf[3840 + x]);
                uint16_t t33 = MEDIAN_MIN(t30, t31);
                uint16_t t34 = MEDIAN_MIN(t33, t32);
                uint16_t t35 = MEDIAN_MIN(t34, t23);
                buf[2880 + x] = t35;
                uint16_t t42 = MEDIAN_MAX(t20, buf[5440 + x]);
                uint16_t t43 = MEDIAN_MAX(t21, buf[5120 + x]);
                uint16_t t44 = MEDIAN_MAX(t22, buf[4800 + x]);
                uint16_t t45 = MEDIAN_MIN(t42, t43);
                uint16_t t46 = MEDIAN_MIN(t45, t44);
                uint16_t t47 = MEDIAN_MIN(t46, t23);
                buf[2560 + x] = t47;
            }
            memcpy(oflat + y * lanes + c0, buf + 2880, (size_t)m * sizeof(uint16_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 2560, (size_t)m * sizeof(uint16_t));
        }
    }
}

static void median3_c3_uint8(const uint8_t *restrict flat, uint8_t *restrict oflat, index_t rows, index_t lanes,
                             index_t y0, index_t y1, uint8_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 6;
            index_t lo = max_i(0, 3 - c0), hi = min_i(n_in, 3 + lanes - c0);
            for (index_t r = 0; r < 4; r++) {
                const uint8_t *src = flat + min_i(max_i(y + r - 1, 0), rows - 1) * lanes;
                uint8_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 3, (size_t)(hi - lo) * sizeof(uint8_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 3];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 3 + (c0 + j) % 3];
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t4 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                buf[1280 + x] = t4;
                uint8_t t5 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                buf[1600 + x] = t5;
                uint8_t t24 = MEDIAN_MIN(buf[0 + x], buf[3 + x]);
                buf[1920 + x] = t24;
                uint8_t t25 = MEDIAN_MAX(buf[0 + x], buf[3 + x]);
                buf[2240 + x] = t25;
                uint8_t t36 = MEDIAN_MIN(buf[960 + x], buf[963 + x]);
                buf[2560 + x] = t36;
                uint8_t t37 = MEDIAN_MAX(buf[960 + x], buf[963 + x]);
                buf[2880 + x] = t37;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t6 = MEDIAN_MIN(buf[1280 + x], buf[1283 + x]);
                buf[640 + x] = t6;
                uint8_t t7 = MEDIAN_MAX(buf[1280 + x], buf[1283 + x]);
                uint8_t t8 = MEDIAN_MIN(buf[1600 + x], buf[1603 + x]);
                uint8_t t9 = MEDIAN_MAX(buf[1600 + x], buf[1603 + x]);
                buf[320 + x] = t9;
                uint8_t t10 = MEDIAN_MIN(t8, t7);
                buf[3200 + x] = t10;
                uint8_t t11 = MEDIAN_MAX(t8, t7);
                buf[3520 + x] = t11;
                uint8_t t26 = MEDIAN_MIN(buf[0 + x], buf[1923 + x]);
                buf[3840 + x] = t26;
                uint8_t t27 = MEDIAN_MAX(buf[0 + x], buf[1923 + x]);
                uint8_t t28 = MEDIAN_MIN(buf[2243 + x], t27);
                buf[4160 + x] = t28;
                uint8_t t29 = MEDIAN_MAX(buf[2243 + x], t27);
                buf[4480 + x] = t29;
                uint8_t t38 = MEDIAN_MIN(buf[960 + x], buf[2563 + x]);
                buf[4800 + x] = t38;
                uint8_t t39 = MEDIAN_MAX(buf[960 + x], buf[2563 + x]);
                uint8_t t40 = MEDIAN_MIN(buf[2883 + x], t39);
                buf[5120 + x] = t40;
                uint8_t t41 = MEDIAN_MAX(buf[2883 + x], t39);
                buf[5440 + x] = t41;
            }
            for (index_t x = 0; x < 256; x++) {
                uint8_t t13 = MEDIAN_MAX(buf[1280 + x], buf[643 + x]);
                uint8_t t14 = MEDIAN_MIN(buf[3523 + x], t13);
                uint8_t t15 = MEDIAN_MAX(buf[3523 + x], t13);
                uint8_t t16 = MEDIAN_MIN(buf[1600 + x], buf[3203 + x]);
                uint8_t t17 = MEDIAN_MAX(buf[1600 + x], buf[3203 + x]);
                uint8_t t18 = MEDIAN_MIN(buf[323 + x], t17);
                uint8_t t20 = MEDIAN_MIN(t16, t14);
                uint8_t t21 = MEDIAN_MAX(t16, t14);
                uint8_t t22 = MEDIAN_MIN(t18, t15);
                uint8_t t23 = MEDIAN_MAX(t18, t15);
                uint8_t t30 = MEDIAN_MAX(t20, buf[4480 + x]);
                uint8_t t31 = MEDIAN_MAX(t21, buf[4160 + x]);
                uint8_t t32 = MEDIAN_MAX(t22, buf[3840 + x]);
                uint8_t t33 = MEDIAN_MIN(t30, t31);
                uint8_t t34 = MEDIAN_MIN(t33, t32);
                uint8_t t35 = MEDIAN_MIN(t34, t23);
                buf[2880 + x] = t35;
                uint8_t t42 = MEDIAN_MAX(t20, buf[5440 + x]);
                uint8_t t43 = MEDIAN_MAX(t21, buf[5120 + x]);
                uint8_t t44 = MEDIAN_MAX(t22, buf[4800 + x]);
                uint8_t t45 = MEDIAN_MIN(t42, t43);
                uint8_t t46 = MEDIAN_MIN(t45, t44);
                uint8_t t47 = MEDIAN_MIN(t46, t23);
                buf[2560 + x] = t47;
            }
            memcpy(oflat + y * lanes + c0, buf + 2880, (size_t)m * sizeof(uint8_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 2560, (size_t)m * sizeof(uint8_t));
        }
    }
}

static void median3_c3_uint16(const uint16_t *restrict flat, uint16_t *restrict oflat, index_t rows, index_t lanes,
                              index_t y0, index_t y1, uint16_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 6;
            index_t lo = max_i(0, 3 - c0), hi = min_i(n_in, 3 + lanes - c0);
            for (index_t r = 0; r < 4; r++) {
                const uint16_t *src = flat + min_i(max_i(y + r - 1, 0), rows - 1) * lanes;
                uint16_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 3, (size_t)(hi - lo) * sizeof(uint16_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 3];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 3 + (c0 + j) % 3];
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t4 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                buf[1280 + x] = t4;
                uint16_t t5 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                buf[1600 + x] = t5;
                uint16_t t24 = MEDIAN_MIN(buf[0 + x], buf[3 + x]);
                buf[1920 + x] = t24;
                uint16_t t25 = MEDIAN_MAX(buf[0 + x], buf[3 + x]);
                buf[2240 + x] = t25;
                uint16_t t36 = MEDIAN_MIN(buf[960 + x], buf[963 + x]);
                buf[2560 + x] = t36;
                uint16_t t37 = MEDIAN_MAX(buf[960 + x], buf[963 + x]);
                buf[2880 + x] = t37;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t6 = MEDIAN_MIN(buf[1280 + x], buf[1283 + x]);
                buf[640 + x] = t6;
                uint16_t t7 = MEDIAN_MAX(buf[1280 + x], buf[1283 + x]);
                uint16_t t8 = MEDIAN_MIN(buf[1600 + x], buf[1603 + x]);
                uint16_t t9 = MEDIAN_MAX(buf[1600 + x], buf[1603 + x]);
                buf[320 + x] = t9;
                uint16_t t10 = MEDIAN_MIN(t8, t7);
                buf[3200 + x] = t10;
                uint16_t t11 = MEDIAN_MAX(t8, t7);
                buf[3520 + x] = t11;
                uint16_t t26 = MEDIAN_MIN(buf[0 + x], buf[1923 + x]);
                buf[3840 + x] = t26;
                uint16_t t27 = MEDIAN_MAX(buf[0 + x], buf[1923 + x]);
                uint16_t t28 = MEDIAN_MIN(buf[2243 + x], t27);
                buf[4160 + x] = t28;
                uint16_t t29 = MEDIAN_MAX(buf[2243 + x], t27);
                buf[4480 + x] = t29;
                uint16_t t38 = MEDIAN_MIN(buf[960 + x], buf[2563 + x]);
                buf[4800 + x] = t38;
                uint16_t t39 = MEDIAN_MAX(buf[960 + x], buf[2563 + x]);
                uint16_t t40 = MEDIAN_MIN(buf[2883 + x], t39);
                buf[5120 + x] = t40;
                uint16_t t41 = MEDIAN_MAX(buf[2883 + x], t39);
                buf[5440 + x] = t41;
            }
            for (index_t x = 0; x < 256; x++) {
                uint16_t t13 = MEDIAN_MAX(buf[1280 + x], buf[643 + x]);
                uint16_t t14 = MEDIAN_MIN(buf[3523 + x], t13);
                uint16_t t15 = MEDIAN_MAX(buf[3523 + x], t13);
                uint16_t t16 = MEDIAN_MIN(buf[1600 + x], buf[3203 + x]);
                uint16_t t17 = MEDIAN_MAX(buf[1600 + x], buf[3203 + x]);
                uint16_t t18 = MEDIAN_MIN(buf[323 + x], t17);
                uint16_t t20 = MEDIAN_MIN(t16, t14);
                uint16_t t21 = MEDIAN_MAX(t16, t14);
                uint16_t t22 = MEDIAN_MIN(t18, t15);
                uint16_t t23 = MEDIAN_MAX(t18, t15);
                uint16_t t30 = MEDIAN_MAX(t20, buf[4480 + x]);
                uint16_t t31 = MEDIAN_MAX(t21, buf[4160 + x]);
                uint16_t t32 = MEDIAN_MAX(t22, buf[3840 + x]);
                uint16_t t33 = MEDIAN_MIN(t30, t31);
                uint16_t t34 = MEDIAN_MIN(t33, t32);
                uint16_t t35 = MEDIAN_MIN(t34, t23);
                buf[2880 + x] = t35;
                uint16_t t42 = MEDIAN_MAX(t20, buf[5440 + x]);
                uint16_t t43 = MEDIAN_MAX(t21, buf[5120 + x]);
                uint16_t t44 = MEDIAN_MAX(t22, buf[4800 + x]);
                uint16_t t45 = MEDIAN_MIN(t42, t43);
                uint16_t t46 = MEDIAN_MIN(t45, t44);
                uint16_t t47 = MEDIAN_MIN(t46, t23);
                buf[2560 + x] = t47;
            }
            memcpy(oflat + y * lanes + c0, buf + 2880, (size_t)m * sizeof(uint16_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 2560, (size_t)m * sizeof(uint16_t));
        }
    }
}

static void median5_c1_uint8(const uint8_t *restrict flat, uint8_t *restrict oflat, index_t rows, index_t lanes,
                             index_t y0, index_t y1, uint8_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 4;
            index_t lo = max_i(0, 2 - c0), hi = min_i(n_in, 2 + lanes - c0);
            for (index_t r = 0; r < 6; r++) {
                const uint8_t *src = flat + min_i(max_i(y + r - 2, 0), rows - 1) * lanes;
                uint8_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 2, (size_t)(hi - lo) * sizeof(uint8_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 1];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 1 + (c0 + j) % 1];
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t6 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                uint8_t t7 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                uint8_t t8 = MEDIAN_MIN(buf[960 + x], buf[1280 + x]);
                uint8_t t9 = MEDIAN_MAX(buf[960 + x], buf[1280 + x]);
                uint8_t t10 = MEDIAN_MIN(t6, t8);
                buf[1920 + x] = t10;
                uint8_t t11 = MEDIAN_MAX(t6, t8);
                uint8_t t12 = MEDIAN_MIN(t7, t9);
                uint8_t t13 = MEDIAN_MAX(t7, t9);
                buf[2240 + x] = t13;
                uint8_t t14 = MEDIAN_MIN(t12, t11);
                buf[2560 + x] = t14;
                uint8_t t15 = MEDIAN_MAX(t12, t11);
                buf[2880 + x] = t15;
                uint8_t t142 = MEDIAN_MIN(buf[0 + x], buf[1 + x]);
                buf[3200 + x] = t142;
                uint8_t t143 = MEDIAN_MAX(buf[0 + x], buf[1 + x]);
                buf[3520 + x] = t143;
                uint8_t t168 = MEDIAN_MIN(buf[1600 + x], buf[1601 + x]);
                buf[3840 + x] = t168;
                uint8_t t169 = MEDIAN_MAX(buf[1600 + x], buf[1601 + x]);
                buf[4160 + x] = t169;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t16 = MEDIAN_MIN(buf[1920 + x], buf[1921 + x]);
                buf[1280 + x] = t16;
                uint8_t t17 = MEDIAN_MAX(buf[1920 + x], buf[1921 + x]);
                uint8_t t18 = MEDIAN_MIN(buf[2880 + x], buf[2881 + x]);
                uint8_t t19 = MEDIAN_MAX(buf[2880 + x], buf[2881 + x]);
                uint8_t t20 = MEDIAN_MIN(t18, t17);
                uint8_t t21 = MEDIAN_MAX(t18, t17);
                uint8_t t22 = MEDIAN_MIN(buf[2560 + x], buf[2561 + x]);
                uint8_t t23 = MEDIAN_MAX(buf[2560 + x], buf[2561 + x]);
                uint8_t t24 = MEDIAN_MIN(buf[2240 + x], buf[2241 + x]);
                uint8_t t25 = MEDIAN_MAX(buf[2240 + x], buf[2241 + x]);
                buf[960 + x] = t25;
                uint8_t t26 = MEDIAN_MIN(t24, t23);
                uint8_t t27 = MEDIAN_MAX(t24, t23);
                uint8_t t28 = MEDIAN_MIN(t22, t20);
                buf[640 + x] = t28;
                uint8_t t29 = MEDIAN_MAX(t22, t20);
                buf[320 + x] = t29;
                uint8_t t30 = MEDIAN_MIN(t26, t21);
                buf[4480 + x] = t30;
                uint8_t t31 = MEDIAN_MAX(t26, t21);
                buf[4800 + x] = t31;
                uint8_t t32 = MEDIAN_MIN(t27, t19);
                buf[5120 + x] = t32;
                uint8_t t33 = MEDIAN_MAX(t27, t19);
                buf[5440 + x] = t33;
                uint8_t t144 = MEDIAN_MIN(buf[0 + x], buf[3201 + x]);
                buf[5760 + x] = t144;
                uint8_t t145 = MEDIAN_MAX(buf[0 + x], buf[3201 + x]);
                uint8_t t146 = MEDIAN_MIN(buf[3521 + x], t145);
                buf[6080 + x] = t146;
                uint8_t t147 = MEDIAN_MAX(buf[3521 + x], t145);
                buf[6400 + x] = t147;
                uint8_t t170 = MEDIAN_MIN(buf[1600 + x], buf[3841 + x]);
                buf[6720 + x] = t170;
                uint8_t t171 = MEDIAN_MAX(buf[1600 + x], buf[3841 + x]);
                uint8_t t172 = MEDIAN_MIN(buf[4161 + x], t171);
                buf[7040 + x] = t172;
                uint8_t t173 = MEDIAN_MAX(buf[4161 + x], t171);
                buf[7360 + x] = t173;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t34 = MEDIAN_MIN(buf[1920 + x], buf[1281 + x]);
                buf[1600 + x] = t34;
                uint8_t t35 = MEDIAN_MAX(buf[1920 + x], buf[1281 + x]);
                uint8_t t36 = MEDIAN_MIN(buf[4801 + x], t35);
                uint8_t t37 = MEDIAN_MAX(buf[4801 + x], t35);
                uint8_t t38 = MEDIAN_MIN(buf[2880 + x], buf[321 + x]);
                uint8_t t39 = MEDIAN_MAX(buf[2880 + x], buf[321 + x]);
                uint8_t t40 = MEDIAN_MIN(buf[5441 + x], t39);
                uint8_t t41 = MEDIAN_MAX(buf[5441 + x], t39);
                uint8_t t42 = MEDIAN_MIN(t38, t36);
                uint8_t t43 = MEDIAN_MAX(t38, t36);
                uint8_t t44 = MEDIAN_MIN(t40, t37);
                uint8_t t45 = MEDIAN_MAX(t40, t37);
                uint8_t t46 = MEDIAN_MIN(buf[2560 + x], buf[641 + x]);
                uint8_t t47 = MEDIAN_MAX(buf[2560 + x], buf[641 + x]);
                uint8_t t48 = MEDIAN_MIN(buf[5121 + x], t47);
                uint8_t t49 = MEDIAN_MAX(buf[5121 + x], t47);
                uint8_t t50 = MEDIAN_MIN(buf[2240 + x], buf[4481 + x]);
                uint8_t t51 = MEDIAN_MAX(buf[2240 + x], buf[4481 + x]);
                uint8_t t52 = MEDIAN_MIN(buf[961 + x], t51);
                uint8_t t53 = MEDIAN_MAX(buf[961 + x], t51);
                buf[0 + x] = t53;
                uint8_t t54 = MEDIAN_MIN(t50, t48);
                uint8_t t55 = MEDIAN_MAX(t50, t48);
                uint8_t t56 = MEDIAN_MIN(t52, t49);
                uint8_t t57 = MEDIAN_MAX(t52, t49);
                uint8_t t58 = MEDIAN_MIN(t46, t42);
                buf[7680 + x] = t58;
                uint8_t t59 = MEDIAN_MAX(t46, t42);
                buf[8000 + x] = t59;
                uint8_t t60 = MEDIAN_MIN(t54, t43);
                buf[8320 + x] = t60;
                uint8_t t61 = MEDIAN_MAX(t54, t43);
                buf[8640 + x] = t61;
                uint8_t t62 = MEDIAN_MIN(t55, t44);
                buf[8960 + x] = t62;
                uint8_t t63 = MEDIAN_MAX(t55, t44);
                buf[9280 + x] = t63;
                uint8_t t64 = MEDIAN_MIN(t56, t45);
                buf[9600 + x] = t64;
                uint8_t t65 = MEDIAN_MAX(t56, t45);
                buf[9920 + x] = t65;
                uint8_t t66 = MEDIAN_MIN(t57, t41);
                buf[10240 + x] = t66;
                uint8_t t67 = MEDIAN_MAX(t57, t41);
                buf[10560 + x] = t67;
                uint8_t t148 = MEDIAN_MIN(buf[3200 + x], buf[5762 + x]);
                buf[10880 + x] = t148;
                uint8_t t149 = MEDIAN_MAX(buf[3200 + x], buf[5762 + x]);
                uint8_t t150 = MEDIAN_MIN(buf[6402 + x], t149);
                uint8_t t151 = MEDIAN_MAX(buf[6402 + x], t149);
                uint8_t t152 = MEDIAN_MIN(buf[3520 + x], buf[6082 + x]);
                uint8_t t153 = MEDIAN_MAX(buf[3520 + x], buf[6082 + x]);
                uint8_t t154 = MEDIAN_MIN(t152, t150);
                buf[11200 + x] = t154;
                uint8_t t155 = MEDIAN_MAX(t152, t150);
                buf[11520 + x] = t155;
                uint8_t t156 = MEDIAN_MIN(t153, t151);
                buf[11840 + x] = t156;
                uint8_t t157 = MEDIAN_MAX(t153, t151);
                buf[12160 + x] = t157;
                uint8_t t174 = MEDIAN_MIN(buf[3840 + x], buf[6722 + x]);
                buf[12480 + x] = t174;
                uint8_t t175 = MEDIAN_MAX(buf[3840 + x], buf[6722 + x]);
                uint8_t t176 = MEDIAN_MIN(buf[7362 + x], t175);
                uint8_t t177 = MEDIAN_MAX(buf[7362 + x], t175);
                uint8_t t178 = MEDIAN_MIN(buf[4160 + x], buf[7042 + x]);
                uint8_t t179 = MEDIAN_MAX(buf[4160 + x], buf[7042 + x]);
                uint8_t t180 = MEDIAN_MIN(t178, t176);
                buf[12800 + x] = t180;
                uint8_t t181 = MEDIAN_MAX(t178, t176);
                buf[13120 + x] = t181;
                uint8_t t182 = MEDIAN_MIN(t179, t177);
                buf[13440 + x] = t182;
                uint8_t t183 = MEDIAN_MAX(t179, t177);
                buf[13760 + x] = t183;
            }
            for (index_t x = 0; x < 256; x++) {
                uint8_t t69 = MEDIAN_MAX(buf[1280 + x], buf[1602 + x]);
                uint8_t t70 = MEDIAN_MIN(buf[9922 + x], t69);
                uint8_t t71 = MEDIAN_MAX(buf[9922 + x], t69);
                uint8_t t72 = MEDIAN_MIN(buf[4800 + x], buf[8642 + x]);
                uint8_t t73 = MEDIAN_MAX(buf[4800 + x], buf[8642 + x]);
                uint8_t t75 = MEDIAN_MAX(t72, t70);
                uint8_t t76 = MEDIAN_MIN(t73, t71);
                uint8_t t79 = MEDIAN_MAX(buf[320 + x], buf[8002 + x]);
                uint8_t t80 = MEDIAN_MIN(buf[10562 + x], t79);
                uint8_t t82 = MEDIAN_MIN(buf[5440 + x], buf[9282 + x]);
                uint8_t t84 = MEDIAN_MIN(t82, t80);
                uint8_t t85 = MEDIAN_MAX(t82, t80);
                uint8_t t91 = MEDIAN_MAX(t84, t75);
                uint8_t t92 = MEDIAN_MIN(t85, t76);
                uint8_t t93 = MEDIAN_MAX(t85, t76);
                uint8_t t97 = MEDIAN_MAX(buf[640 + x], buf[7682 + x]);
                uint8_t t98 = MEDIAN_MIN(buf[10242 + x], t97);
                uint8_t t99 = MEDIAN_MAX(buf[10242 + x], t97);
                uint8_t t100 = MEDIAN_MIN(buf[5120 + x], buf[8962 + x]);
                uint8_t t101 = MEDIAN_MAX(buf[5120 + x], buf[8962 + x]);
                uint8_t t103 = MEDIAN_MAX(t100, t98);
                uint8_t t104 = MEDIAN_MIN(t101, t99);
                uint8_t t107 = MEDIAN_MAX(buf[4480 + x], buf[8322 + x]);
                uint8_t t108 = MEDIAN_MIN(buf[2 + x], t107);
                uint8_t t110 = MEDIAN_MIN(buf[960 + x], buf[9602 + x]);
                uint8_t t112 = MEDIAN_MIN(t110, t108);
                uint8_t t113 = MEDIAN_MAX(t110, t108);
                uint8_t t118 = MEDIAN_MIN(t112, t103);
                uint8_t t119 = MEDIAN_MAX(t112, t103);
                uint8_t t120 = MEDIAN_MIN(t113, t104);
                uint8_t t130 = MEDIAN_MIN(t118, t91);
                uint8_t t131 = MEDIAN_MAX(t118, t91);
                uint8_t t132 = MEDIAN_MIN(t119, t92);
                uint8_t t133 = MEDIAN_MAX(t119, t92);
                uint8_t t134 = MEDIAN_MIN(t120, t93);
                uint8_t t135 = MEDIAN_MAX(t120, t93);
                uint8_t t158 = MEDIAN_MAX(t130, buf[12160 + x]);
                uint8_t t159 = MEDIAN_MAX(t131, buf[11840 + x]);
                uint8_t t160 = MEDIAN_MAX(t132, buf[11520 + x]);
                uint8_t t161 = MEDIAN_MAX(t133, buf[11200 + x]);
                uint8_t t162 = MEDIAN_MAX(t134, buf[10880 + x]);
                uint8_t t163 = MEDIAN_MIN(t158, t159);
                uint8_t t164 = MEDIAN_MIN(t163, t160);
                uint8_t t165 = MEDIAN_MIN(t164, t161);
                uint8_t t166 = MEDIAN_MIN(t165, t162);
                uint8_t t167 = MEDIAN_MIN(t166, t135);
                buf[7360 + x] = t167;
                uint8_t t184 = MEDIAN_MAX(t130, buf[13760 + x]);
                uint8_t t185 = MEDIAN_MAX(t131, buf[13440 + x]);
                uint8_t t186 = MEDIAN_MAX(t132, buf[13120 + x]);
                uint8_t t187 = MEDIAN_MAX(t133, buf[12800 + x]);
                uint8_t t188 = MEDIAN_MAX(t134, buf[12480 + x]);
                uint8_t t189 = MEDIAN_MIN(t184, t185);
                uint8_t t190 = MEDIAN_MIN(t189, t186);
                uint8_t t191 = MEDIAN_MIN(t190, t187);
                uint8_t t192 = MEDIAN_MIN(t191, t188);
                uint8_t t193 = MEDIAN_MIN(t192, t135);
                buf[7040 + x] = t193;
            }
            memcpy(oflat + y * lanes + c0, buf + 7360, (size_t)m * sizeof(uint8_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 7040, (size_t)m * sizeof(uint8_t));
        }
    }
}

static void median5_c1_uint16(const uint16_t *restrict flat, uint16_t *restrict oflat, index_t rows, index_t lanes,
                              index_t y0, index_t y1, uint16_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 4;
            index_t lo = max_i(0, 2 - c0), hi = min_i(n_in, 2 + lanes - c0);
            for (index_t r = 0; r < 6; r++) {
                const uint16_t *src = flat + min_i(max_i(y + r - 2, 0), rows - 1) * lanes;
                uint16_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 2, (size_t)(hi - lo) * sizeof(uint16_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 1];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 1 + (c0 + j) % 1];
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t6 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                uint16_t t7 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                uint16_t t8 = MEDIAN_MIN(buf[960 + x], buf[1280 + x]);
                uint16_t t9 = MEDIAN_MAX(buf[960 + x], buf[1280 + x]);
                uint16_t t10 = MEDIAN_MIN(t6, t8);
                buf[1920 + x] = t10;
                uint16_t t11 = MEDIAN_MAX(t6, t8);
                uint16_t t12 = MEDIAN_MIN(t7, t9);
                uint16_t t13 = MEDIAN_MAX(t7, t9);
                buf[2240 + x] = t13;
                uint16_t t14 = MEDIAN_MIN(t12, t11);
                buf[2560 + x] = t14;
                uint16_t t15 = MEDIAN_MAX(t12, t11);
                buf[2880 + x] = t15;
                uint16_t t142 = MEDIAN_MIN(buf[0 + x], buf[1 + x]);
                buf[3200 + x] = t142;
                uint16_t t143 = MEDIAN_MAX(buf[0 + x], buf[1 + x]);
                buf[3520 + x] = t143;
                uint16_t t168 = MEDIAN_MIN(buf[1600 + x], buf[1601 + x]);
                buf[3840 + x] = t168;
                uint16_t t169 = MEDIAN_MAX(buf[1600 + x], buf[1601 + x]);
                buf[4160 + x] = t169;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t16 = MEDIAN_MIN(buf[1920 + x], buf[1921 + x]);
                buf[1280 + x] = t16;
                uint16_t t17 = MEDIAN_MAX(buf[1920 + x], buf[1921 + x]);
                uint16_t t18 = MEDIAN_MIN(buf[2880 + x], buf[2881 + x]);
                uint16_t t19 = MEDIAN_MAX(buf[2880 + x], buf[2881 + x]);
                uint16_t t20 = MEDIAN_MIN(t18, t17);
                uint16_t t21 = MEDIAN_MAX(t18, t17);
                uint16_t t22 = MEDIAN_MIN(buf[2560 + x], buf[2561 + x]);
                uint16_t t23 = MEDIAN_MAX(buf[2560 + x], buf[2561 + x]);
                uint16_t t24 = MEDIAN_MIN(buf[2240 + x], buf[2241 + x]);
                uint16_t t25 = MEDIAN_MAX(buf[2240 + x], buf[2241 + x]);
                buf[960 + x] = t25;
                uint16_t t26 = MEDIAN_MIN(t24, t23);
                uint16_t t27 = MEDIAN_MAX(t24, t23);
                uint16_t t28 = MEDIAN_MIN(t22, t20);
                buf[640 + x] = t28;
                uint16_t t29 = MEDIAN_MAX(t22, t20);
                buf[320 + x] = t29;
                uint16_t t30 = MEDIAN_MIN(t26, t21);
                buf[4480 + x] = t30;
                uint16_t t31 = MEDIAN_MAX(t26, t21);
                buf[4800 + x] = t31;
                uint16_t t32 = MEDIAN_MIN(t27, t19);
                buf[5120 + x] = t32;
                uint16_t t33 = MEDIAN_MAX(t27, t19);
                buf[5440 + x] = t33;
                uint16_t t144 = MEDIAN_MIN(buf[0 + x], buf[3201 + x]);
                buf[5760 + x] = t144;
                uint16_t t145 = MEDIAN_MAX(buf[0 + x], buf[3201 + x]);
                uint16_t t146 = MEDIAN_MIN(buf[3521 + x], t145);
                buf[6080 + x] = t146;
                uint16_t t147 = MEDIAN_MAX(buf[3521 + x], t145);
                buf[6400 + x] = t147;
                uint16_t t170 = MEDIAN_MIN(buf[1600 + x], buf[3841 + x]);
                buf[6720 + x] = t170;
                uint16_t t171 = MEDIAN_MAX(buf[1600 + x], buf[3841 + x]);
                uint16_t t172 = MEDIAN_MIN(buf[4161 + x], t171);
                buf[7040 + x] = t172;
                uint16_t t173 = MEDIAN_MAX(buf[4161 + x], t171);
                buf[7360 + x] = t173;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t34 = MEDIAN_MIN(buf[1920 + x], buf[1281 + x]);
                buf[1600 + x] = t34;
                uint16_t t35 = MEDIAN_MAX(buf[1920 + x], buf[1281 + x]);
                uint16_t t36 = MEDIAN_MIN(buf[4801 + x], t35);
                uint16_t t37 = MEDIAN_MAX(buf[4801 + x], t35);
                uint16_t t38 = MEDIAN_MIN(buf[2880 + x], buf[321 + x]);
                uint16_t t39 = MEDIAN_MAX(buf[2880 + x], buf[321 + x]);
                uint16_t t40 = MEDIAN_MIN(buf[5441 + x], t39);
                uint16_t t41 = MEDIAN_MAX(buf[5441 + x], t39);
                uint16_t t42 = MEDIAN_MIN(t38, t36);
                uint16_t t43 = MEDIAN_MAX(t38, t36);
                uint16_t t44 = MEDIAN_MIN(t40, t37);
                uint16_t t45 = MEDIAN_MAX(t40, t37);
                uint16_t t46 = MEDIAN_MIN(buf[2560 + x], buf[641 + x]);
                uint16_t t47 = MEDIAN_MAX(buf[2560 + x], buf[641 + x]);
                uint16_t t48 = MEDIAN_MIN(buf[5121 + x], t47);
                uint16_t t49 = MEDIAN_MAX(buf[5121 + x], t47);
                uint16_t t50 = MEDIAN_MIN(buf[2240 + x], buf[4481 + x]);
                uint16_t t51 = MEDIAN_MAX(buf[2240 + x], buf[4481 + x]);
                uint16_t t52 = MEDIAN_MIN(buf[961 + x], t51);
                uint16_t t53 = MEDIAN_MAX(buf[961 + x], t51);
                buf[0 + x] = t53;
                uint16_t t54 = MEDIAN_MIN(t50, t48);
                uint16_t t55 = MEDIAN_MAX(t50, t48);
                uint16_t t56 = MEDIAN_MIN(t52, t49);
                uint16_t t57 = MEDIAN_MAX(t52, t49);
                uint16_t t58 = MEDIAN_MIN(t46, t42);
                buf[7680 + x] = t58;
                uint16_t t59 = MEDIAN_MAX(t46, t42);
                buf[8000 + x] = t59;
                uint16_t t60 = MEDIAN_MIN(t54, t43);
                buf[8320 + x] = t60;
                uint16_t t61 = MEDIAN_MAX(t54, t43);
                buf[8640 + x] = t61;
                uint16_t t62 = MEDIAN_MIN(t55, t44);
                buf[8960 + x] = t62;
                uint16_t t63 = MEDIAN_MAX(t55, t44);
                buf[9280 + x] = t63;
                uint16_t t64 = MEDIAN_MIN(t56, t45);
                buf[9600 + x] = t64;
                uint16_t t65 = MEDIAN_MAX(t56, t45);
                buf[9920 + x] = t65;
                uint16_t t66 = MEDIAN_MIN(t57, t41);
                buf[10240 + x] = t66;
                uint16_t t67 = MEDIAN_MAX(t57, t41);
                buf[10560 + x] = t67;
                uint16_t t148 = MEDIAN_MIN(buf[3200 + x], buf[5762 + x]);
                buf[10880 + x] = t148;
                uint16_t t149 = MEDIAN_MAX(buf[3200 + x], buf[5762 + x]);
                uint16_t t150 = MEDIAN_MIN(buf[6402 + x], t149);
                uint16_t t151 = MEDIAN_MAX(buf[6402 + x], t149);
                uint16_t t152 = MEDIAN_MIN(buf[3520 + x], buf[6082 + x]);
                uint16_t t153 = MEDIAN_MAX(buf[3520 + x], buf[6082 + x]);
                uint16_t t154 = MEDIAN_MIN(t152, t150);
                buf[11200 + x] = t154;
                uint16_t t155 = MEDIAN_MAX(t152, t150);
                buf[11520 + x] = t155;
                uint16_t t156 = MEDIAN_MIN(t153, t151);
                buf[11840 + x] = t156;
                uint16_t t157 = MEDIAN_MAX(t153, t151);
                buf[12160 + x] = t157;
                uint16_t t174 = MEDIAN_MIN(buf[3840 + x], buf[6722 + x]);
                buf[12480 + x] = t174;
                uint16_t t175 = MEDIAN_MAX(buf[3840 + x], buf[6722 + x]);
                uint16_t t176 = MEDIAN_MIN(buf[7362 + x], t175);
                uint16_t t177 = MEDIAN_MAX(buf[7362 + x], t175);
                uint16_t t178 = MEDIAN_MIN(buf[4160 + x], buf[7042 + x]);
                uint16_t t179 = MEDIAN_MAX(buf[4160 + x], buf[7042 + x]);
                uint16_t t180 = MEDIAN_MIN(t178, t176);
                buf[12800 + x] = t180;
                uint16_t t181 = MEDIAN_MAX(t178, t176);
                buf[13120 + x] = t181;
                uint16_t t182 = MEDIAN_MIN(t179, t177);
                buf[13440 + x] = t182;
                uint16_t t183 = MEDIAN_MAX(t179, t177);
                buf[13760 + x] = t183;
            }
            for (index_t x = 0; x < 256; x++) {
                uint16_t t69 = MEDIAN_MAX(buf[1280 + x], buf[1602 + x]);
                uint16_t t70 = MEDIAN_MIN(buf[9922 + x], t69);
                uint16_t t71 = MEDIAN_MAX(buf[9922 + x], t69);
                uint16_t t72 = MEDIAN_MIN(buf[4800 + x], buf[8642 + x]);
                uint16_t t73 = MEDIAN_MAX(buf[4800 + x], buf[8642 + x]);
                uint16_t t75 = MEDIAN_MAX(t72, t70);
                uint16_t t76 = MEDIAN_MIN(t73, t71);
                uint16_t t79 = MEDIAN_MAX(buf[320 + x], buf[8002 + x]);
                uint16_t t80 = MEDIAN_MIN(buf[10562 + x], t79);
                uint16_t t82 = MEDIAN_MIN(buf[5440 + x], buf[9282 + x]);
                uint16_t t84 = MEDIAN_MIN(t82, t80);
                uint16_t t85 = MEDIAN_MAX(t82, t80);
                uint16_t t91 = MEDIAN_MAX(t84, t75);
                uint16_t t92 = MEDIAN_MIN(t85, t76);
                uint16_t t93 = MEDIAN_MAX(t85, t76);
                uint16_t t97 = MEDIAN_MAX(buf[640 + x], buf[7682 + x]);
                uint16_t t98 = MEDIAN_MIN(buf[10242 + x], t97);
                uint16_t t99 = MEDIAN_MAX(buf[10242 + x], t97);
                uint16_t t100 = MEDIAN_MIN(buf[5120 + x], buf[8962 + x]);
                uint16_t t101 = MEDIAN_MAX(buf[5120 + x], buf[8962 + x]);
                uint16_t t103 = MEDIAN_MAX(t100, t98);
                uint16_t t104 = MEDIAN_MIN(t101, t99);
                uint16_t t107 = MEDIAN_MAX(buf[4480 + x], buf[8322 + x]);
                uint16_t t108 = MEDIAN_MIN(buf[2 + x], t107);
                uint16_t t110 = MEDIAN_MIN(buf[960 + x], buf[9602 + x]);
                uint16_t t112 = MEDIAN_MIN(t110, t108);
                uint16_t t113 = MEDIAN_MAX(t110, t108);
                uint16_t t118 = MEDIAN_MIN(t112, t103);
                uint16_t t119 = MEDIAN_MAX(t112, t103);
                uint16_t t120 = MEDIAN_MIN(t113, t104);
                uint16_t t130 = MEDIAN_MIN(t118, t91);
                uint16_t t131 = MEDIAN_MAX(t118, t91);
                uint16_t t132 = MEDIAN_MIN(t119, t92);
                uint16_t t133 = MEDIAN_MAX(t119, t92);
                uint16_t t134 = MEDIAN_MIN(t120, t93);
                uint16_t t135 = MEDIAN_MAX(t120, t93);
                uint16_t t158 = MEDIAN_MAX(t130, buf[12160 + x]);
                uint16_t t159 = MEDIAN_MAX(t131, buf[11840 + x]);
                uint16_t t160 = MEDIAN_MAX(t132, buf[11520 + x]);
                uint16_t t161 = MEDIAN_MAX(t133, buf[11200 + x]);
                uint16_t t162 = MEDIAN_MAX(t134, buf[10880 + x]);
                uint16_t t163 = MEDIAN_MIN(t158, t159);
                uint16_t t164 = MEDIAN_MIN(t163, t160);
                uint16_t t165 = MEDIAN_MIN(t164, t161);
                uint16_t t166 = MEDIAN_MIN(t165, t162);
                uint16_t t167 = MEDIAN_MIN(t166, t135);
                buf[7360 + x] = t167;
                uint16_t t184 = MEDIAN_MAX(t130, buf[13760 + x]);
                uint16_t t185 = MEDIAN_MAX(t131, buf[13440 + x]);
                uint16_t t186 = MEDIAN_MAX(t132, buf[13120 + x]);
                uint16_t t187 = MEDIAN_MAX(t133, buf[12800 + x]);
                uint16_t t188 = MEDIAN_MAX(t134, buf[12480 + x]);
                uint16_t t189 = MEDIAN_MIN(t184, t185);
                uint16_t t190 = MEDIAN_MIN(t189, t186);
                uint16_t t191 = MEDIAN_MIN(t190, t187);
                uint16_t t192 = MEDIAN_MIN(t191, t188);
                uint16_t t193 = MEDIAN_MIN(t192, t135);
                buf[7040 + x] = t193;
            }
            memcpy(oflat + y * lanes + c0, buf + 7360, (size_t)m * sizeof(uint16_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 7040, (size_t)m * sizeof(uint16_t));
        }
    }
}

static void median5_c3_uint8(const uint8_t *restrict flat, uint8_t *restrict oflat, index_t rows, index_t lanes,
                             index_t y0, index_t y1, uint8_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 12;
            index_t lo = max_i(0, 6 - c0), hi = min_i(n_in, 6 + lanes - c0);
            for (index_t r = 0; r < 6; r++) {
                const uint8_t *src = flat + min_i(max_i(y + r - 2, 0), rows - 1) * lanes;
                uint8_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 6, (size_t)(hi - lo) * sizeof(uint8_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 3];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 3 + (c0 + j) % 3];
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t6 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                uint8_t t7 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                uint8_t t8 = MEDIAN_MIN(buf[960 + x], buf[1280 + x]);
                uint8_t t9 = MEDIAN_MAX(buf[960 + x], buf[1280 + x]);
                uint8_t t10 = MEDIAN_MIN(t6, t8);
                buf[1920 + x] = t10;
                uint8_t t11 = MEDIAN_MAX(t6, t8);
                uint8_t t12 = MEDIAN_MIN(t7, t9);
                uint8_t t13 = MEDIAN_MAX(t7, t9);
                buf[2240 + x] = t13;
                uint8_t t14 = MEDIAN_MIN(t12, t11);
                buf[2560 + x] = t14;
                uint8_t t15 = MEDIAN_MAX(t12, t11);
                buf[2880 + x] = t15;
                uint8_t t142 = MEDIAN_MIN(buf[0 + x], buf[3 + x]);
                buf[3200 + x] = t142;
                uint8_t t143 = MEDIAN_MAX(buf[0 + x], buf[3 + x]);
                buf[3520 + x] = t143;
                uint8_t t168 = MEDIAN_MIN(buf[1600 + x], buf[1603 + x]);
                buf[3840 + x] = t168;
                uint8_t t169 = MEDIAN_MAX(buf[1600 + x], buf[1603 + x]);
                buf[4160 + x] = t169;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t16 = MEDIAN_MIN(buf[1920 + x], buf[1923 + x]);
                buf[1280 + x] = t16;
                uint8_t t17 = MEDIAN_MAX(buf[1920 + x], buf[1923 + x]);
                uint8_t t18 = MEDIAN_MIN(buf[2880 + x], buf[2883 + x]);
                uint8_t t19 = MEDIAN_MAX(buf[2880 + x], buf[2883 + x]);
                uint8_t t20 = MEDIAN_MIN(t18, t17);
                uint8_t t21 = MEDIAN_MAX(t18, t17);
                uint8_t t22 = MEDIAN_MIN(buf[2560 + x], buf[2563 + x]);
                uint8_t t23 = MEDIAN_MAX(buf[2560 + x], buf[2563 + x]);
                uint8_t t24 = MEDIAN_MIN(buf[2240 + x], buf[2243 + x]);
                uint8_t t25 = MEDIAN_MAX(buf[2240 + x], buf[2243 + x]);
                buf[960 + x] = t25;
                uint8_t t26 = MEDIAN_MIN(t24, t23);
                uint8_t t27 = MEDIAN_MAX(t24, t23);
                uint8_t t28 = MEDIAN_MIN(t22, t20);
                buf[640 + x] = t28;
                uint8_t t29 = MEDIAN_MAX(t22, t20);
                buf[320 + x] = t29;
                uint8_t t30 = MEDIAN_MIN(t26, t21);
                buf[4480 + x] = t30;
                uint8_t t31 = MEDIAN_MAX(t26, t21);
                buf[4800 + x] = t31;
                uint8_t t32 = MEDIAN_MIN(t27, t19);
                buf[5120 + x] = t32;
                uint8_t t33 = MEDIAN_MAX(t27, t19);
                buf[5440 + x] = t33;
                uint8_t t144 = MEDIAN_MIN(buf[0 + x], buf[3203 + x]);
                buf[5760 + x] = t144;
                uint8_t t145 = MEDIAN_MAX(buf[0 + x], buf[3203 + x]);
                uint8_t t146 = MEDIAN_MIN(buf[3523 + x], t145);
                buf[6080 + x] = t146;
                uint8_t t147 = MEDIAN_MAX(buf[3523 + x], t145);
                buf[6400 + x] = t147;
                uint8_t t170 = MEDIAN_MIN(buf[1600 + x], buf[3843 + x]);
                buf[6720 + x] = t170;
                uint8_t t171 = MEDIAN_MAX(buf[1600 + x], buf[3843 + x]);
                uint8_t t172 = MEDIAN_MIN(buf[4163 + x], t171);
                buf[7040 + x] = t172;
                uint8_t t173 = MEDIAN_MAX(buf[4163 + x], t171);
                buf[7360 + x] = t173;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t34 = MEDIAN_MIN(buf[1920 + x], buf[1283 + x]);
                buf[1600 + x] = t34;
                uint8_t t35 = MEDIAN_MAX(buf[1920 + x], buf[1283 + x]);
                uint8_t t36 = MEDIAN_MIN(buf[4803 + x], t35);
                uint8_t t37 = MEDIAN_MAX(buf[4803 + x], t35);
                uint8_t t38 = MEDIAN_MIN(buf[2880 + x], buf[323 + x]);
                uint8_t t39 = MEDIAN_MAX(buf[2880 + x], buf[323 + x]);
                uint8_t t40 = MEDIAN_MIN(buf[5443 + x], t39);
                uint8_t t41 = MEDIAN_MAX(buf[5443 + x], t39);
                uint8_t t42 = MEDIAN_MIN(t38, t36);
                uint8_t t43 = MEDIAN_MAX(t38, t36);
                uint8_t t44 = MEDIAN_MIN(t40, t37);
                uint8_t t45 = MEDIAN_MAX(t40, t37);
                uint8_t t46 = MEDIAN_MIN(buf[2560 + x], buf[643 + x]);
                uint8_t t47 = MEDIAN_MAX(buf[2560 + x], buf[643 + x]);
                uint8_t t48 = MEDIAN_MIN(buf[5123 + x], t47);
                uint8_t t49 = MEDIAN_MAX(buf[5123 + x], t47);
                uint8_t t50 = MEDIAN_MIN(buf[2240 + x], buf[4483 + x]);
                uint8_t t51 = MEDIAN_MAX(buf[2240 + x], buf[4483 + x]);
                uint8_t t52 = MEDIAN_MIN(buf[963 + x], t51);
                uint8_t t53 = MEDIAN_MAX(buf[963 + x], t51);
                buf[0 + x] = t53;
                uint8_t t54 = MEDIAN_MIN(t50, t48);
                uint8_t t55 = MEDIAN_MAX(t50, t48);
                uint8_t t56 = MEDIAN_MIN(t52, t49);
                uint8_t t57 = MEDIAN_MAX(t52, t49);
                uint8_t t58 = MEDIAN_MIN(t46, t42);
                buf[7680 + x] = t58;
                uint8_t t59 = MEDIAN_MAX(t46, t42);
                buf[8000 + x] = t59;
                uint8_t t60 = MEDIAN_MIN(t54, t43);
                buf[8320 + x] = t60;
                uint8_t t61 = MEDIAN_MAX(t54, t43);
                buf[8640 + x] = t61;
                uint8_t t62 = MEDIAN_MIN(t55, t44);
                buf[8960 + x] = t62;
                uint8_t t63 = MEDIAN_MAX(t55, t44);
                buf[9280 + x] = t63;
                uint8_t t64 = MEDIAN_MIN(t56, t45);
                buf[9600 + x] = t64;
                uint8_t t65 = MEDIAN_MAX(t56, t45);
                buf[9920 + x] = t65;
                uint8_t t66 = MEDIAN_MIN(t57, t41);
                buf[10240 + x] = t66;
                uint8_t t67 = MEDIAN_MAX(t57, t41);
                buf[10560 + x] = t67;
                uint8_t t148 = MEDIAN_MIN(buf[3200 + x], buf[5766 + x]);
                buf[10880 + x] = t148;
                uint8_t t149 = MEDIAN_MAX(buf[3200 + x], buf[5766 + x]);
                uint8_t t150 = MEDIAN_MIN(buf[6406 + x], t149);
                uint8_t t151 = MEDIAN_MAX(buf[6406 + x], t149);
                uint8_t t152 = MEDIAN_MIN(buf[3520 + x], buf[6086 + x]);
                uint8_t t153 = MEDIAN_MAX(buf[3520 + x], buf[6086 + x]);
                uint8_t t154 = MEDIAN_MIN(t152, t150);
                buf[11200 + x] = t154;
                uint8_t t155 = MEDIAN_MAX(t152, t150);
                buf[11520 + x] = t155;
                uint8_t t156 = MEDIAN_MIN(t153, t151);
                buf[11840 + x] = t156;
                uint8_t t157 = MEDIAN_MAX(t153, t151);
                buf[12160 + x] = t157;
                uint8_t t174 = MEDIAN_MIN(buf[3840 + x], buf[6726 + x]);
                buf[12480 + x] = t174;
                uint8_t t175 = MEDIAN_MAX(buf[3840 + x], buf[6726 + x]);
                uint8_t t176 = MEDIAN_MIN(buf[7366 + x], t175);
                uint8_t t177 = MEDIAN_MAX(buf[7366 + x], t175);
                uint8_t t178 = MEDIAN_MIN(buf[4160 + x], buf[7046 + x]);
                uint8_t t179 = MEDIAN_MAX(buf[4160 + x], buf[7046 + x]);
                uint8_t t180 = MEDIAN_MIN(t178, t176);
                buf[12800 + x] = t180;
                uint8_t t181 = MEDIAN_MAX(t178, t176);
                buf[13120 + x] = t181;
                uint8_t t182 = MEDIAN_MIN(t179, t177);
                buf[13440 + x] = t182;
                uint8_t t183 = MEDIAN_MAX(t179, t177);
                buf[13760 + x] = t183;
            }
            for (index_t x = 0; x < 256; x++) {
                uint8_t t69 = MEDIAN_MAX(buf[1280 + x], buf[1606 + x]);
                uint8_t t70 = MEDIAN_MIN(buf[9926 + x], t69);
                uint8_t t71 = MEDIAN_MAX(buf[9926 + x], t69);
                uint8_t t72 = MEDIAN_MIN(buf[4800 + x], buf[8646 + x]);
                uint8_t t73 = MEDIAN_MAX(buf[4800 + x], buf[8646 + x]);
                uint8_t t75 = MEDIAN_MAX(t72, t70);
                uint8_t t76 = MEDIAN_MIN(t73, t71);
                uint8_t t79 = MEDIAN_MAX(buf[320 + x], buf[8006 + x]);
                uint8_t t80 = MEDIAN_MIN(buf[10566 + x], t79);
                uint8_t t82 = MEDIAN_MIN(buf[5440 + x], buf[9286 + x]);
                uint8_t t84 = MEDIAN_MIN(t82, t80);
                uint8_t t85 = MEDIAN_MAX(t82, t80);
                uint8_t t91 = MEDIAN_MAX(t84, t75);
                uint8_t t92 = MEDIAN_MIN(t85, t76);
                uint8_t t93 = MEDIAN_MAX(t85, t76);
                uint8_t t97 = MEDIAN_MAX(buf[640 + x], buf[7686 + x]);
                uint8_t t98 = MEDIAN_MIN(buf[10246 + x], t97);
                uint8_t t99 = MEDIAN_MAX(buf[10246 + x], t97);
                uint8_t t100 = MEDIAN_MIN(buf[5120 + x], buf[8966 + x]);
                uint8_t t101 = MEDIAN_MAX(buf[5120 + x], buf[8966 + x]);
                uint8_t t103 = MEDIAN_MAX(t100, t98);
                uint8_t t104 = MEDIAN_MIN(t101, t99);
                uint8_t t107 = MEDIAN_MAX(buf[4480 + x], buf[8326 + x]);
                uint8_t t108 = MEDIAN_MIN(buf[6 + x], t107);
                uint8_t t110 = MEDIAN_MIN(buf[960 + x], buf[9606 + x]);
                uint8_t t112 = MEDIAN_MIN(t110, t108);
                uint8_t t113 = MEDIAN_MAX(t110, t108);
                uint8_t t118 = MEDIAN_MIN(t112, t103);
                uint8_t t119 = MEDIAN_MAX(t112, t103);
                uint8_t t120 = MEDIAN_MIN(t113, t104);
                uint8_t t130 = MEDIAN_MIN(t118, t91);
                uint8_t t131 = MEDIAN_MAX(t118, t91);
                uint8_t t132 = MEDIAN_MIN(t119, t92);
                uint8_t t133 = MEDIAN_MAX(t119, t92);
                uint8_t t134 = MEDIAN_MIN(t120, t93);
                uint8_t t135 = MEDIAN_MAX(t120, t93);
                uint8_t t158 = MEDIAN_MAX(t130, buf[12160 + x]);
                uint8_t t159 = MEDIAN_MAX(t131, buf[11840 + x]);
                uint8_t t160 = MEDIAN_MAX(t132, buf[11520 + x]);
                uint8_t t161 = MEDIAN_MAX(t133, buf[11200 + x]);
                uint8_t t162 = MEDIAN_MAX(t134, buf[10880 + x]);
                uint8_t t163 = MEDIAN_MIN(t158, t159);
                uint8_t t164 = MEDIAN_MIN(t163, t160);
                uint8_t t165 = MEDIAN_MIN(t164, t161);
                uint8_t t166 = MEDIAN_MIN(t165, t162);
                uint8_t t167 = MEDIAN_MIN(t166, t135);
                buf[7360 + x] = t167;
                uint8_t t184 = MEDIAN_MAX(t130, buf[13760 + x]);
                uint8_t t185 = MEDIAN_MAX(t131, buf[13440 + x]);
                uint8_t t186 = MEDIAN_MAX(t132, buf[13120 + x]);
                uint8_t t187 = MEDIAN_MAX(t133, buf[12800 + x]);
                uint8_t t188 = MEDIAN_MAX(t134, buf[12480 + x]);
                uint8_t t189 = MEDIAN_MIN(t184, t185);
                uint8_t t190 = MEDIAN_MIN(t189, t186);
                uint8_t t191 = MEDIAN_MIN(t190, t187);
                uint8_t t192 = MEDIAN_MIN(t191, t188);
                uint8_t t193 = MEDIAN_MIN(t192, t135);
                buf[7040 + x] = t193;
            }
            memcpy(oflat + y * lanes + c0, buf + 7360, (size_t)m * sizeof(uint8_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 7040, (size_t)m * sizeof(uint8_t));
        }
    }
}

static void median5_c3_uint16(const uint16_t *restrict flat, uint16_t *restrict oflat, index_t rows, index_t lanes,
                              index_t y0, index_t y1, uint16_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 12;
            index_t lo = max_i(0, 6 - c0), hi = min_i(n_in, 6 + lanes - c0);
            for (index_t r = 0; r < 6; r++) {
                const uint16_t *src = flat + min_i(max_i(y + r - 2, 0), rows - 1) * lanes;
                uint16_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 6, (size_t)(hi - lo) * sizeof(uint16_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 3];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 3 + (c0 + j) % 3];
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t6 = MEDIAN_MIN(buf[320 + x], buf[640 + x]);
                uint16_t t7 = MEDIAN_MAX(buf[320 + x], buf[640 + x]);
                uint16_t t8 = MEDIAN_MIN(buf[960 + x], buf[1280 + x]);
                uint16_t t9 = MEDIAN_MAX(buf[960 + x], buf[1280 + x]);
                uint16_t t10 = MEDIAN_MIN(t6, t8);
                buf[1920 + x] = t10;
                uint16_t t11 = MEDIAN_MAX(t6, t8);
                uint16_t t12 = MEDIAN_MIN(t7, t9);
                uint16_t t13 = MEDIAN_MAX(t7, t9);
                buf[2240 + x] = t13;
                uint16_t t14 = MEDIAN_MIN(t12, t11);
                buf[2560 + x] = t14;
                uint16_t t15 = MEDIAN_MAX(t12, t11);
                buf[2880 + x] = t15;
                uint16_t t142 = MEDIAN_MIN(buf[0 + x], buf[3 + x]);
                buf[3200 + x] = t142;
                uint16_t t143 = MEDIAN_MAX(buf[0 + x], buf[3 + x]);
                buf[3520 + x] = t143;
                uint16_t t168 = MEDIAN_MIN(buf[1600 + x], buf[1603 + x]);
                buf[3840 + x] = t168;
                uint16_t t169 = MEDIAN_MAX(buf[1600 + x], buf[1603 + x]);
                buf[4160 + x] = t169;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t16 = MEDIAN_MIN(buf[1920 + x], buf[1923 + x]);
                buf[1280 + x] = t16;
                uint16_t t17 = MEDIAN_MAX(buf[1920 + x], buf[1923 + x]);
                uint16_t t18 = MEDIAN_MIN(buf[2880 + x], buf[2883 + x]);
                uint16_t t19 = MEDIAN_MAX(buf[2880 + x], buf[2883 + x]);
                uint16_t t20 = MEDIAN_MIN(t18, t17);
                uint16_t t21 = MEDIAN_MAX(t18, t17);
                uint16_t t22 = MEDIAN_MIN(buf[2560 + x], buf[2563 + x]);
                uint16_t t23 = MEDIAN_MAX(buf[2560 + x], buf[2563 + x]);
                uint16_t t24 = MEDIAN_MIN(buf[2240 + x], buf[2243 + x]);
                uint16_t t25 = MEDIAN_MAX(buf[2240 + x], buf[2243 + x]);
                buf[960 + x] = t25;
                uint16_t t26 = MEDIAN_MIN(t24, t23);
                uint16_t t27 = MEDIAN_MAX(t24, t23);
                uint16_t t28 = MEDIAN_MIN(t22, t20);
                buf[640 + x] = t28;
                uint16_t t29 = MEDIAN_MAX(t22, t20);
                buf[320 + x] = t29;
                uint16_t t30 = MEDIAN_MIN(t26, t21);
                buf[4480 + x] = t30;
                uint16_t t31 = MEDIAN_MAX(t26, t21);
                buf[4800 + x] = t31;
                uint16_t t32 = MEDIAN_MIN(t27, t19);
                buf[5120 + x] = t32;
                uint16_t t33 = MEDIAN_MAX(t27, t19);
                buf[5440 + x] = t33;
                uint16_t t144 = MEDIAN_MIN(buf[0 + x], buf[3203 + x]);
                buf[5760 + x] = t144;
                uint16_t t145 = MEDIAN_MAX(buf[0 + x], buf[3203 + x]);
                uint16_t t146 = MEDIAN_MIN(buf[3523 + x], t145);
                buf[6080 + x] = t146;
                uint16_t t147 = MEDIAN_MAX(buf[3523 + x], t145);
                buf[6400 + x] = t147;
                uint16_t t170 = MEDIAN_MIN(buf[1600 + x], buf[3843 + x]);
                buf[6720 + x] = t170;
                uint16_t t171 = MEDIAN_MAX(buf[1600 + x], buf[3843 + x]);
                uint16_t t172 = MEDIAN_MIN(buf[4163 + x], t171);
                buf[7040 + x] = t172;
                uint16_t t173 = MEDIAN_MAX(buf[4163 + x], t171);
                buf[7360 + x] = t173;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t34 = MEDIAN_MIN(buf[1920 + x], buf[1283 + x]);
                buf[1600 + x] = t34;
                uint16_t t35 = MEDIAN_MAX(buf[1920 + x], buf[1283 + x]);
                uint16_t t36 = MEDIAN_MIN(buf[4803 + x], t35);
                uint16_t t37 = MEDIAN_MAX(buf[4803 + x], t35);
                uint16_t t38 = MEDIAN_MIN(buf[2880 + x], buf[323 + x]);
                uint16_t t39 = MEDIAN_MAX(buf[2880 + x], buf[323 + x]);
                uint16_t t40 = MEDIAN_MIN(buf[5443 + x], t39);
                uint16_t t41 = MEDIAN_MAX(buf[5443 + x], t39);
                uint16_t t42 = MEDIAN_MIN(t38, t36);
                uint16_t t43 = MEDIAN_MAX(t38, t36);
                uint16_t t44 = MEDIAN_MIN(t40, t37);
                uint16_t t45 = MEDIAN_MAX(t40, t37);
                uint16_t t46 = MEDIAN_MIN(buf[2560 + x], buf[643 + x]);
                uint16_t t47 = MEDIAN_MAX(buf[2560 + x], buf[643 + x]);
                uint16_t t48 = MEDIAN_MIN(buf[5123 + x], t47);
                uint16_t t49 = MEDIAN_MAX(buf[5123 + x], t47);
                uint16_t t50 = MEDIAN_MIN(buf[2240 + x], buf[4483 + x]);
                uint16_t t51 = MEDIAN_MAX(buf[2240 + x], buf[4483 + x]);
                uint16_t t52 = MEDIAN_MIN(buf[963 + x], t51);
                uint16_t t53 = MEDIAN_MAX(buf[963 + x], t51);
                buf[0 + x] = t53;
                uint16_t t54 = MEDIAN_MIN(t50, t48);
                uint16_t t55 = MEDIAN_MAX(t50, t48);
                uint16_t t56 = MEDIAN_MIN(t52, t49);
                uint16_t t57 = MEDIAN_MAX(t52, t49);
                uint16_t t58 = MEDIAN_MIN(t46, t42);
                buf[7680 + x] = t58;
                uint16_t t59 = MEDIAN_MAX(t46, t42);
                buf[8000 + x] = t59;
                uint16_t t60 = MEDIAN_MIN(t54, t43);
                buf[8320 + x] = t60;
                uint16_t t61 = MEDIAN_MAX(t54, t43);
                buf[8640 + x] = t61;
                uint16_t t62 = MEDIAN_MIN(t55, t44);
                buf[8960 + x] = t62;
                uint16_t t63 = MEDIAN_MAX(t55, t44);
                buf[9280 + x] = t63;
                uint16_t t64 = MEDIAN_MIN(t56, t45);
                buf[9600 + x] = t64;
                uint16_t t65 = MEDIAN_MAX(t56, t45);
                buf[9920 + x] = t65;
                uint16_t t66 = MEDIAN_MIN(t57, t41);
                buf[10240 + x] = t66;
                uint16_t t67 = MEDIAN_MAX(t57, t41);
                buf[10560 + x] = t67;
                uint16_t t148 = MEDIAN_MIN(buf[3200 + x], buf[5766 + x]);
                buf[10880 + x] = t148;
                uint16_t t149 = MEDIAN_MAX(buf[3200 + x], buf[5766 + x]);
                uint16_t t150 = MEDIAN_MIN(buf[6406 + x], t149);
                uint16_t t151 = MEDIAN_MAX(buf[6406 + x], t149);
                uint16_t t152 = MEDIAN_MIN(buf[3520 + x], buf[6086 + x]);
                uint16_t t153 = MEDIAN_MAX(buf[3520 + x], buf[6086 + x]);
                uint16_t t154 = MEDIAN_MIN(t152, t150);
                buf[11200 + x] = t154;
                uint16_t t155 = MEDIAN_MAX(t152, t150);
                buf[11520 + x] = t155;
                uint16_t t156 = MEDIAN_MIN(t153, t151);
                buf[11840 + x] = t156;
                uint16_t t157 = MEDIAN_MAX(t153, t151);
                buf[12160 + x] = t157;
                uint16_t t174 = MEDIAN_MIN(buf[3840 + x], buf[6726 + x]);
                buf[12480 + x] = t174;
                uint16_t t175 = MEDIAN_MAX(buf[3840 + x], buf[6726 + x]);
                uint16_t t176 = MEDIAN_MIN(buf[7366 + x], t175);
                uint16_t t177 = MEDIAN_MAX(buf[7366 + x], t175);
                uint16_t t178 = MEDIAN_MIN(buf[4160 + x], buf[7046 + x]);
                uint16_t t179 = MEDIAN_MAX(buf[4160 + x], buf[7046 + x]);
                uint16_t t180 = MEDIAN_MIN(t178, t176);
                buf[12800 + x] = t180;
                uint16_t t181 = MEDIAN_MAX(t178, t176);
                buf[13120 + x] = t181;
                uint16_t t182 = MEDIAN_MIN(t179, t177);
                buf[13440 + x] = t182;
                uint16_t t183 = MEDIAN_MAX(t179, t177);
                buf[13760 + x] = t183;
            }
            for (index_t x = 0; x < 256; x++) {
                uint16_t t69 = MEDIAN_MAX(buf[1280 + x], buf[1606 + x]);
                uint16_t t70 = MEDIAN_MIN(buf[9926 + x], t69);
                uint16_t t71 = MEDIAN_MAX(buf[9926 + x], t69);
                uint16_t t72 = MEDIAN_MIN(buf[4800 + x], buf[8646 + x]);
                uint16_t t73 = MEDIAN_MAX(buf[4800 + x], buf[8646 + x]);
                uint16_t t75 = MEDIAN_MAX(t72, t70);
                uint16_t t76 = MEDIAN_MIN(t73, t71);
                uint16_t t79 = MEDIAN_MAX(buf[320 + x], buf[8006 + x]);
                uint16_t t80 = MEDIAN_MIN(buf[10566 + x], t79);
                uint16_t t82 = MEDIAN_MIN(buf[5440 + x], buf[9286 + x]);
                uint16_t t84 = MEDIAN_MIN(t82, t80);
                uint16_t t85 = MEDIAN_MAX(t82, t80);
                uint16_t t91 = MEDIAN_MAX(t84, t75);
                uint16_t t92 = MEDIAN_MIN(t85, t76);
                uint16_t t93 = MEDIAN_MAX(t85, t76);
                uint16_t t97 = MEDIAN_MAX(buf[640 + x], buf[7686 + x]);
                uint16_t t98 = MEDIAN_MIN(buf[10246 + x], t97);
                uint16_t t99 = MEDIAN_MAX(buf[10246 + x], t97);
                uint16_t t100 = MEDIAN_MIN(buf[5120 + x], buf[8966 + x]);
                uint16_t t101 = MEDIAN_MAX(buf[5120 + x], buf[8966 + x]);
                uint16_t t103 = MEDIAN_MAX(t100, t98);
                uint16_t t104 = MEDIAN_MIN(t101, t99);
                uint16_t t107 = MEDIAN_MAX(buf[4480 + x], buf[8326 + x]);
                uint16_t t108 = MEDIAN_MIN(buf[6 + x], t107);
                uint16_t t110 = MEDIAN_MIN(buf[960 + x], buf[9606 + x]);
                uint16_t t112 = MEDIAN_MIN(t110, t108);
                uint16_t t113 = MEDIAN_MAX(t110, t108);
                uint16_t t118 = MEDIAN_MIN(t112, t103);
                uint16_t t119 = MEDIAN_MAX(t112, t103);
                uint16_t t120 = MEDIAN_MIN(t113, t104);
                uint16_t t130 = MEDIAN_MIN(t118, t91);
                uint16_t t131 = MEDIAN_MAX(t118, t91);
                uint16_t t132 = MEDIAN_MIN(t119, t92);
                uint16_t t133 = MEDIAN_MAX(t119, t92);
                uint16_t t134 = MEDIAN_MIN(t120, t93);
                uint16_t t135 = MEDIAN_MAX(t120, t93);
                uint16_t t158 = MEDIAN_MAX(t130, buf[12160 + x]);
                uint16_t t159 = MEDIAN_MAX(t131, buf[11840 + x]);
                uint16_t t160 = MEDIAN_MAX(t132, buf[11520 + x]);
                uint16_t t161 = MEDIAN_MAX(t133, buf[11200 + x]);
                uint16_t t162 = MEDIAN_MAX(t134, buf[10880 + x]);
                uint16_t t163 = MEDIAN_MIN(t158, t159);
                uint16_t t164 = MEDIAN_MIN(t163, t160);
                uint16_t t165 = MEDIAN_MIN(t164, t161);
                uint16_t t166 = MEDIAN_MIN(t165, t162);
                uint16_t t167 = MEDIAN_MIN(t166, t135);
                buf[7360 + x] = t167;
                uint16_t t184 = MEDIAN_MAX(t130, buf[13760 + x]);
                uint16_t t185 = MEDIAN_MAX(t131, buf[13440 + x]);
                uint16_t t186 = MEDIAN_MAX(t132, buf[13120 + x]);
                uint16_t t187 = MEDIAN_MAX(t133, buf[12800 + x]);
                uint16_t t188 = MEDIAN_MAX(t134, buf[12480 + x]);
                uint16_t t189 = MEDIAN_MIN(t184, t185);
                uint16_t t190 = MEDIAN_MIN(t189, t186);
                uint16_t t191 = MEDIAN_MIN(t190, t187);
                uint16_t t192 = MEDIAN_MIN(t191, t188);
                uint16_t t193 = MEDIAN_MIN(t192, t135);
                buf[7040 + x] = t193;
            }
            memcpy(oflat + y * lanes + c0, buf + 7360, (size_t)m * sizeof(uint16_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 7040, (size_t)m * sizeof(uint16_t));
        }
    }
}

static void median7_c1_uint8(const uint8_t *restrict flat, uint8_t *restrict oflat, index_t rows, index_t lanes,
                             index_t y0, index_t y1, uint8_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 6;
            index_t lo = max_i(0, 3 - c0), hi = min_i(n_in, 3 + lanes - c0);
            for (index_t r = 0; r < 8; r++) {
                const uint8_t *src = flat + min_i(max_i(y + r - 3, 0), rows - 1) * lanes;
                uint8_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 3, (size_t)(hi - lo) * sizeof(uint8_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 1];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 1 + (c0 + j) % 1];
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t8 = MEDIAN_MIN(buf[640 + x], buf[960 + x]);
                uint8_t t9 = MEDIAN_MAX(buf[640 + x], buf[960 + x]);
                uint8_t t10 = MEDIAN_MIN(buf[320 + x], t8);
                uint8_t t11 = MEDIAN_MAX(buf[320 + x], t8);
                uint8_t t12 = MEDIAN_MIN(t9, t11);
                uint8_t t13 = MEDIAN_MAX(t9, t11);
                uint8_t t14 = MEDIAN_MIN(buf[1600 + x], buf[1920 + x]);
                uint8_t t15 = MEDIAN_MAX(buf[1600 + x], buf[1920 + x]);
                uint8_t t16 = MEDIAN_MIN(buf[1280 + x], t14);
                uint8_t t17 = MEDIAN_MAX(buf[1280 + x], t14);
                uint8_t t18 = MEDIAN_MIN(t15, t17);
                uint8_t t19 = MEDIAN_MAX(t15, t17);
                uint8_t t20 = MEDIAN_MIN(t10, t16);
                buf[2560 + x] = t20;
                uint8_t t21 = MEDIAN_MAX(t10, t16);
                uint8_t t22 = MEDIAN_MIN(t13, t19);
                uint8_t t23 = MEDIAN_MAX(t13, t19);
                buf[2880 + x] = t23;
                uint8_t t24 = MEDIAN_MIN(t22, t21);
                uint8_t t25 = MEDIAN_MAX(t22, t21);
                uint8_t t26 = MEDIAN_MIN(t12, t18);
                uint8_t t27 = MEDIAN_MAX(t12, t18);
                uint8_t t28 = MEDIAN_MIN(t26, t24);
                buf[3200 + x] = t28;
                uint8_t t29 = MEDIAN_MAX(t26, t24);
                buf[3520 + x] = t29;
                uint8_t t30 = MEDIAN_MIN(t27, t25);
                buf[3840 + x] = t30;
                uint8_t t31 = MEDIAN_MAX(t27, t25);
                buf[4160 + x] = t31;
                uint8_t t420 = MEDIAN_MIN(buf[0 + x], buf[1 + x]);
                buf[4480 + x] = t420;
                uint8_t t421 = MEDIAN_MAX(buf[0 + x], buf[1 + x]);
                buf[4800 + x] = t421;
                uint8_t t462 = MEDIAN_MIN(buf[2240 + x], buf[2241 + x]);
                buf[5120 + x] = t462;
                uint8_t t463 = MEDIAN_MAX(buf[2240 + x], buf[2241 + x]);
                buf[5440 + x] = t463;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t32 = MEDIAN_MIN(buf[2560 + x], buf[2561 + x]);
                buf[1920 + x] = t32;
                uint8_t t33 = MEDIAN_MAX(buf[2560 + x], buf[2561 + x]);
                uint8_t t34 = MEDIAN_MIN(buf[4160 + x], buf[4161 + x]);
                uint8_t t35 = MEDIAN_MAX(buf[4160 + x], buf[4161 + x]);
                uint8_t t36 = MEDIAN_MIN(t34, t33);
                uint8_t t37 = MEDIAN_MAX(t34, t33);
                uint8_t t38 = MEDIAN_MIN(buf[3520 + x], buf[3521 + x]);
                uint8_t t39 = MEDIAN_MAX(buf[3520 + x], buf[3521 + x]);
                uint8_t t40 = MEDIAN_MIN(t38, t36);
                uint8_t t41 = MEDIAN_MAX(t38, t36);
                uint8_t t42 = MEDIAN_MIN(t39, t37);
                uint8_t t43 = MEDIAN_MAX(t39, t37);
                uint8_t t44 = MEDIAN_MIN(buf[3200 + x], buf[3201 + x]);
                uint8_t t45 = MEDIAN_MAX(buf[3200 + x], buf[3201 + x]);
                uint8_t t46 = MEDIAN_MIN(buf[2880 + x], buf[2881 + x]);
                uint8_t t47 = MEDIAN_MAX(buf[2880 + x], buf[2881 + x]);
                buf[1600 + x] = t47;
                uint8_t t48 = MEDIAN_MIN(t46, t45);
                uint8_t t49 = MEDIAN_MAX(t46, t45);
                uint8_t t50 = MEDIAN_MIN(buf[3840 + x], buf[3841 + x]);
                uint8_t t51 = MEDIAN_MAX(buf[3840 + x], buf[3841 + x]);
                uint8_t t52 = MEDIAN_MIN(t50, t48);
                uint8_t t53 = MEDIAN_MAX(t50, t48);
                uint8_t t54 = MEDIAN_MIN(t51, t49);
                uint8_t t55 = MEDIAN_MAX(t51, t49);
                uint8_t t56 = MEDIAN_MIN(t44, t40);
                buf[1280 + x] = t56;
                uint8_t t57 = MEDIAN_MAX(t44, t40);
                buf[960 + x] = t57;
                uint8_t t58 = MEDIAN_MIN(t52, t41);
                buf[640 + x] = t58;
                uint8_t t59 = MEDIAN_MAX(t52, t41);
                buf[320 + x] = t59;
                uint8_t t60 = MEDIAN_MIN(t53, t42);
                buf[5760 + x] = t60;
                uint8_t t61 = MEDIAN_MAX(t53, t42);
                buf[6080 + x] = t61;
                uint8_t t62 = MEDIAN_MIN(t54, t43);
                buf[6400 + x] = t62;
                uint8_t t63 = MEDIAN_MAX(t54, t43);
                buf[6720 + x] = t63;
                uint8_t t64 = MEDIAN_MIN(t55, t35);
                buf[7040 + x] = t64;
                uint8_t t65 = MEDIAN_MAX(t55, t35);
                buf[7360 + x] = t65;
                uint8_t t422 = MEDIAN_MIN(buf[0 + x], buf[4481 + x]);
                buf[7680 + x] = t422;
                uint8_t t423 = MEDIAN_MAX(buf[0 + x], buf[4481 + x]);
                uint8_t t424 = MEDIAN_MIN(buf[4801 + x], t423);
                buf[8000 + x] = t424;
                uint8_t t425 = MEDIAN_MAX(buf[4801 + x], t423);
                buf[8320 + x] = t425;
                uint8_t t426 = MEDIAN_MIN(buf[4480 + x], buf[4482 + x]);
                buf[8640 + x] = t426;
                uint8_t t427 = MEDIAN_MAX(buf[4480 + x], buf[4482 + x]);
                uint8_t t428 = MEDIAN_MIN(buf[4800 + x], buf[4802 + x]);
                uint8_t t429 = MEDIAN_MAX(buf[4800 + x], buf[4802 + x]);
                buf[8960 + x] = t429;
                uint8_t t430 = MEDIAN_MIN(t428, t427);
                buf[9280 + x] = t430;
                uint8_t t431 = MEDIAN_MAX(t428, t427);
                buf[9600 + x] = t431;
                uint8_t t464 = MEDIAN_MIN(buf[2240 + x], buf[5121 + x]);
                buf[9920 + x] = t464;
                uint8_t t465 = MEDIAN_MAX(buf[2240 + x], buf[5121 + x]);
                uint8_t t466 = MEDIAN_MIN(buf[5441 + x], t465);
                buf[10240 + x] = t466;
                uint8_t t467 = MEDIAN_MAX(buf[5441 + x], t465);
                buf[10560 + x] = t467;
                uint8_t t468 = MEDIAN_MIN(buf[5120 + x], buf[5122 + x]);
                buf[10880 + x] = t468;
                uint8_t t469 = MEDIAN_MAX(buf[5120 + x], buf[5122 + x]);
                uint8_t t470 = MEDIAN_MIN(buf[5440 + x], buf[5442 + x]);
                uint8_t t471 = MEDIAN_MAX(buf[5440 + x], buf[5442 + x]);
                buf[11200 + x] = t471;
                uint8_t t472 = MEDIAN_MIN(t470, t469);
                buf[11520 + x] = t472;
                uint8_t t473 = MEDIAN_MAX(t470, t469);
                buf[11840 + x] = t473;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t66 = MEDIAN_MIN(buf[2560 + x], buf[1921 + x]);
                buf[5440 + x] = t66;
                uint8_t t67 = MEDIAN_MAX(buf[2560 + x], buf[1921 + x]);
                uint8_t t68 = MEDIAN_MIN(buf[6721 + x], t67);
                uint8_t t69 = MEDIAN_MAX(buf[6721 + x], t67);
                uint8_t t70 = MEDIAN_MIN(buf[4160 + x], buf[321 + x]);
                uint8_t t71 = MEDIAN_MAX(buf[4160 + x], buf[321 + x]);
                uint8_t t72 = MEDIAN_MIN(t70, t68);
                uint8_t t73 = MEDIAN_MAX(t70, t68);
                uint8_t t74 = MEDIAN_MIN(t71, t69);
                uint8_t t75 = MEDIAN_MAX(t71, t69);
                uint8_t t76 = MEDIAN_MIN(buf[3520 + x], buf[961 + x]);
                uint8_t t77 = MEDIAN_MAX(buf[3520 + x], buf[961 + x]);
                uint8_t t78 = MEDIAN_MIN(buf[7361 + x], t77);
                uint8_t t79 = MEDIAN_MAX(buf[7361 + x], t77);
                uint8_t t80 = MEDIAN_MIN(buf[6081 + x], t78);
                uint8_t t81 = MEDIAN_MAX(buf[6081 + x], t78);
                uint8_t t82 = MEDIAN_MIN(t76, t72);
                uint8_t t83 = MEDIAN_MAX(t76, t72);
                uint8_t t84 = MEDIAN_MIN(t80, t73);
                uint8_t t85 = MEDIAN_MAX(t80, t73);
                uint8_t t86 = MEDIAN_MIN(t81, t74);
                uint8_t t87 = MEDIAN_MAX(t81, t74);
                uint8_t t88 = MEDIAN_MIN(t79, t75);
                uint8_t t89 = MEDIAN_MAX(t79, t75);
                uint8_t t90 = MEDIAN_MIN(buf[3200 + x], buf[1281 + x]);
                uint8_t t91 = MEDIAN_MAX(buf[3200 + x], buf[1281 + x]);
                uint8_t t92 = MEDIAN_MIN(buf[7041 + x], t91);
                uint8_t t93 = MEDIAN_MAX(buf[7041 + x], t91);
                uint8_t t94 = MEDIAN_MIN(buf[2880 + x], buf[5761 + x]);
                uint8_t t95 = MEDIAN_MAX(buf[2880 + x], buf[5761 + x]);
                uint8_t t96 = MEDIAN_MIN(t94, t92);
                uint8_t t97 = MEDIAN_MAX(t94, t92);
                uint8_t t98 = MEDIAN_MIN(t95, t93);
                uint8_t t99 = MEDIAN_MAX(t95, t93);
                uint8_t t100 = MEDIAN_MIN(buf[3840 + x], buf[641 + x]);
                uint8_t t101 = MEDIAN_MAX(buf[3840 + x], buf[641 + x]);
                uint8_t t102 = MEDIAN_MIN(buf[1601 + x], t101);
                uint8_t t103 = MEDIAN_MAX(buf[1601 + x], t101);
                uint8_t t104 = MEDIAN_MIN(buf[6401 + x], t102);
                uint8_t t105 = MEDIAN_MAX(buf[6401 + x], t102);
                uint8_t t106 = MEDIAN_MIN(t100, t96);
                uint8_t t107 = MEDIAN_MAX(t100, t96);
                uint8_t t108 = MEDIAN_MIN(t104, t97);
                uint8_t t109 = MEDIAN_MAX(t104, t97);
                uint8_t t110 = MEDIAN_MIN(t105, t98);
                uint8_t t111 = MEDIAN_MAX(t105, t98);
                uint8_t t112 = MEDIAN_MIN(t103, t99);
                uint8_t t113 = MEDIAN_MAX(t103, t99);
                buf[5120 + x] = t113;
                uint8_t t114 = MEDIAN_MIN(t90, t82);
                buf[4800 + x] = t114;
                uint8_t t115 = MEDIAN_MAX(t90, t82);
                buf[4480 + x] = t115;
                uint8_t t116 = MEDIAN_MIN(t106, t83);
                buf[2240 + x] = t116;
                uint8_t t117 = MEDIAN_MAX(t106, t83);
                buf[0 + x] = t117;
                uint8_t t118 = MEDIAN_MIN(t107, t84);
                buf[12160 + x] = t118;
                uint8_t t119 = MEDIAN_MAX(t107, t84);
                buf[12480 + x] = t119;
                uint8_t t120 = MEDIAN_MIN(t108, t85);
                buf[12800 + x] = t120;
                uint8_t t121 = MEDIAN_MAX(t108, t85);
                buf[13120 + x] = t121;
                uint8_t t122 = MEDIAN_MIN(t109, t86);
                buf[13440 + x] = t122;
                uint8_t t123 = MEDIAN_MAX(t109, t86);
                buf[13760 + x] = t123;
                uint8_t t124 = MEDIAN_MIN(t110, t87);
                buf[14080 + x] = t124;
                uint8_t t125 = MEDIAN_MAX(t110, t87);
                buf[14400 + x] = t125;
                uint8_t t126 = MEDIAN_MIN(t111, t88);
                buf[14720 + x] = t126;
                uint8_t t127 = MEDIAN_MAX(t111, t88);
                buf[15040 + x] = t127;
                uint8_t t128 = MEDIAN_MIN(t112, t89);
                buf[15360 + x] = t128;
                uint8_t t129 = MEDIAN_MAX(t112, t89);
                buf[15680 + x] = t129;
                uint8_t t130 = MEDIAN_MIN(buf[1920 + x], buf[1922 + x]);
                buf[16000 + x] = t130;
                uint8_t t131 = MEDIAN_MAX(buf[1920 + x], buf[1922 + x]);
                uint8_t t132 = MEDIAN_MIN(buf[6720 + x], buf[6722 + x]);
                uint8_t t133 = MEDIAN_MAX(buf[6720 + x], buf[6722 + x]);
                uint8_t t134 = MEDIAN_MIN(t132, t131);
                uint8_t t135 = MEDIAN_MAX(t132, t131);
                uint8_t t136 = MEDIAN_MIN(buf[320 + x], buf[322 + x]);
                uint8_t t137 = MEDIAN_MAX(buf[320 + x], buf[322 + x]);
                uint8_t t138 = MEDIAN_MIN(t136, t134);
                uint8_t t139 = MEDIAN_MAX(t136, t134);
                uint8_t t140 = MEDIAN_MIN(t137, t135);
                uint8_t t141 = MEDIAN_MAX(t137, t135);
                uint8_t t142 = MEDIAN_MIN(buf[960 + x], buf[962 + x]);
                uint8_t t143 = MEDIAN_MAX(buf[960 + x], buf[962 + x]);
                uint8_t t144 = MEDIAN_MIN(buf[7360 + x], buf[7362 + x]);
                uint8_t t145 = MEDIAN_MAX(buf[7360 + x], buf[7362 + x]);
                uint8_t t146 = MEDIAN_MIN(t144, t143);
                uint8_t t147 = MEDIAN_MAX(t144, t143);
                uint8_t t148 = MEDIAN_MIN(buf[6080 + x], buf[6082 + x]);
                uint8_t t149 = MEDIAN_MAX(buf[6080 + x], buf[6082 + x]);
                uint8_t t150 = MEDIAN_MIN(t148, t146);
                uint8_t t151 = MEDIAN_MAX(t148, t146);
                uint8_t t152 = MEDIAN_MIN(t149, t147);
                uint8_t t153 = MEDIAN_MAX(t149, t147);
                uint8_t t154 = MEDIAN_MIN(t142, t138);
                uint8_t t155 = MEDIAN_MAX(t142, t138);
                uint8_t t156 = MEDIAN_MIN(t150, t139);
                uint8_t t157 = MEDIAN_MAX(t150, t139);
                uint8_t t158 = MEDIAN_MIN(t151, t140);
                uint8_t t159 = MEDIAN_MAX(t151, t140);
                uint8_t t160 = MEDIAN_MIN(t152, t141);
                uint8_t t161 = MEDIAN_MAX(t152, t141);
                uint8_t t162 = MEDIAN_MIN(t153, t133);
                uint8_t t163 = MEDIAN_MAX(t153, t133);
                uint8_t t164 = MEDIAN_MIN(buf[1280 + x], buf[1282 + x]);
                uint8_t t165 = MEDIAN_MAX(buf[1280 + x], buf[1282 + x]);
                uint8_t t166 = MEDIAN_MIN(buf[7040 + x], buf[7042 + x]);
                uint8_t t167 = MEDIAN_MAX(buf[7040 + x], buf[7042 + x]);
                uint8_t t168 = MEDIAN_MIN(t166, t165);
                uint8_t t169 = MEDIAN_MAX(t166, t165);
                uint8_t t170 = MEDIAN_MIN(buf[5760 + x], buf[5762 + x]);
                uint8_t t171 = MEDIAN_MAX(buf[5760 + x], buf[5762 + x]);
                uint8_t t172 = MEDIAN_MIN(t170, t168);
                uint8_t t173 = MEDIAN_MAX(t170, t168);
                uint8_t t174 = MEDIAN_MIN(t171, t169);
                uint8_t t175 = MEDIAN_MAX(t171, t169);
                uint8_t t176 = MEDIAN_MIN(buf[640 + x], buf[642 + x]);
                uint8_t t177 = MEDIAN_MAX(buf[640 + x], buf[642 + x]);
                uint8_t t178 = MEDIAN_MIN(buf[1600 + x], buf[1602 + x]);
                uint8_t t179 = MEDIAN_MAX(buf[1600 + x], buf[1602 + x]);
                buf[16320 + x] = t179;
                uint8_t t180 = MEDIAN_MIN(t178, t177);
                uint8_t t181 = MEDIAN_MAX(t178, t177);
                uint8_t t182 = MEDIAN_MIN(buf[6400 + x], buf[6402 + x]);
                uint8_t t183 = MEDIAN_MAX(buf[6400 + x], buf[6402 + x]);
                uint8_t t184 = MEDIAN_MIN(t182, t180);
                uint8_t t185 = MEDIAN_MAX(t182, t180);
                uint8_t t186 = MEDIAN_MIN(t183, t181);
                uint8_t t187 = MEDIAN_MAX(t183, t181);
                uint8_t t188 = MEDIAN_MIN(t176, t172);
                uint8_t t189 = MEDIAN_MAX(t176, t172);
                uint8_t t190 = MEDIAN_MIN(t184, t173);
                uint8_t t191 = MEDIAN_MAX(t184, t173);
                uint8_t t192 = MEDIAN_MIN(t185, t174);
                uint8_t t193 = MEDIAN_MAX(t185, t174);
                uint8_t t194 = MEDIAN_MIN(t186, t175);
                uint8_t t195 = MEDIAN_MAX(t186, t175);
                uint8_t t196 = MEDIAN_MIN(t187, t167);
                uint8_t t197 = MEDIAN_MAX(t187, t167);
                uint8_t t198 = MEDIAN_MIN(t164, t154);
                buf[16640 + x] = t198;
                uint8_t t199 = MEDIAN_MAX(t164, t154);
                buf[16960 + x] = t199;
                uint8_t t200 = MEDIAN_MIN(t188, t155);
                buf[17280 + x] = t200;
                uint8_t t201 = MEDIAN_MAX(t188, t155);
                buf[17600 + x] = t201;
                uint8_t t202 = MEDIAN_MIN(t189, t156);
                buf[17920 + x] = t202;
                uint8_t t203 = MEDIAN_MAX(t189, t156);
                buf[18240 + x] = t203;
                uint8_t t204 = MEDIAN_MIN(t190, t157);
                buf[18560 + x] = t204;
                uint8_t t205 = MEDIAN_MAX(t190, t157);
                buf[18880 + x] = t205;
                uint8_t t206 = MEDIAN_MIN(t191, t158);
                buf[19200 + x] = t206;
                uint8_t t207 = MEDIAN_MAX(t191, t158);
                buf[19520 + x] = t207;
                uint8_t t208 = MEDIAN_MIN(t192, t159);
                buf[19840 + x] = t208;
                uint8_t t209 = MEDIAN_MAX(t192, t159);
                buf[20160 + x] = t209;
                uint8_t t210 = MEDIAN_MIN(t193, t160);
                buf[20480 + x] = t210;
                uint8_t t211 = MEDIAN_MAX(t193, t160);
                buf[20800 + x] = t211;
                uint8_t t212 = MEDIAN_MIN(t194, t161);
                buf[21120 + x] = t212;
                uint8_t t213 = MEDIAN_MAX(t194, t161);
                buf[21440 + x] = t213;
                uint8_t t214 = MEDIAN_MIN(t195, t162);
                buf[21760 + x] = t214;
                uint8_t t215 = MEDIAN_MAX(t195, t162);
                buf[22080 + x] = t215;
                uint8_t t216 = MEDIAN_MIN(t196, t163);
                buf[22400 + x] = t216;
                uint8_t t217 = MEDIAN_MAX(t196, t163);
                buf[22720 + x] = t217;
                uint8_t t218 = MEDIAN_MIN(t197, t145);
                buf[23040 + x] = t218;
                uint8_t t219 = MEDIAN_MAX(t197, t145);
                buf[23360 + x] = t219;
                uint8_t t432 = MEDIAN_MIN(buf[7680 + x], buf[8643 + x]);
                buf[23680 + x] = t432;
                uint8_t t433 = MEDIAN_MAX(buf[7680 + x], buf[8643 + x]);
                uint8_t t434 = MEDIAN_MIN(buf[8320 + x], buf[9603 + x]);
                uint8_t t435 = MEDIAN_MAX(buf[8320 + x], buf[9603 + x]);
                uint8_t t436 = MEDIAN_MIN(t434, t433);
                uint8_t t437 = MEDIAN_MAX(t434, t433);
                uint8_t t438 = MEDIAN_MIN(buf[8000 + x], buf[9283 + x]);
                uint8_t t439 = MEDIAN_MAX(buf[8000 + x], buf[9283 + x]);
                uint8_t t440 = MEDIAN_MIN(buf[8963 + x], t439);
                uint8_t t441 = MEDIAN_MAX(buf[8963 + x], t439);
                uint8_t t442 = MEDIAN_MIN(t438, t436);
                buf[24000 + x] = t442;
                uint8_t t443 = MEDIAN_MAX(t438, t436);
                buf[24320 + x] = t443;
                uint8_t t444 = MEDIAN_MIN(t440, t437);
                buf[24640 + x] = t444;
                uint8_t t445 = MEDIAN_MAX(t440, t437);
                buf[24960 + x] = t445;
                uint8_t t446 = MEDIAN_MIN(t441, t435);
                buf[25280 + x] = t446;
                uint8_t t447 = MEDIAN_MAX(t441, t435);
                buf[25600 + x] = t447;
                uint8_t t474 = MEDIAN_MIN(buf[9920 + x], buf[10883 + x]);
                buf[25920 + x] = t474;
                uint8_t t475 = MEDIAN_MAX(buf[9920 + x], buf[10883 + x]);
                uint8_t t476 = MEDIAN_MIN(buf[10560 + x], buf[11843 + x]);
                uint8_t t477 = MEDIAN_MAX(buf[10560 + x], buf[11843 + x]);
                uint8_t t478 = MEDIAN_MIN(t476, t475);
                uint8_t t479 = MEDIAN_MAX(t476, t475);
                uint8_t t480 = MEDIAN_MIN(buf[10240 + x], buf[11523 + x]);
                uint8_t t481 = MEDIAN_MAX(buf[10240 + x], buf[11523 + x]);
                uint8_t t482 = MEDIAN_MIN(buf[11203 + x], t481);
                uint8_t t483 = MEDIAN_MAX(buf[11203 + x], t481);
                uint8_t t484 = MEDIAN_MIN(t480, t478);
                buf[26240 + x] = t484;
                uint8_t t485 = MEDIAN_MAX(t480, t478);
                buf[26560 + x] = t485;
                uint8_t t486 = MEDIAN_MIN(t482, t479);
                buf[26880 + x] = t486;
                uint8_t t487 = MEDIAN_MAX(t482, t479);
                buf[27200 + x] = t487;
                uint8_t t488 = MEDIAN_MIN(t483, t477);
                buf[27520 + x] = t488;
                uint8_t t489 = MEDIAN_MAX(t483, t477);
                buf[27840 + x] = t489;
            }
            for (index_t x = 0; x < 256; x++) {
                uint8_t t221 = MEDIAN_MAX(buf[5440 + x], buf[16003 + x]);
                uint8_t t222 = MEDIAN_MIN(buf[15680 + x], buf[21443 + x]);
                uint8_t t225 = MEDIAN_MAX(t222, t221);
                uint8_t t227 = MEDIAN_MAX(buf[13120 + x], buf[18883 + x]);
                uint8_t t230 = MEDIAN_MIN(t227, t225);
                uint8_t t233 = MEDIAN_MAX(buf[0 + x], buf[17603 + x]);
                uint8_t t234 = MEDIAN_MIN(buf[22723 + x], t233);
                uint8_t t236 = MEDIAN_MIN(buf[14400 + x], buf[20163 + x]);
                uint8_t t239 = MEDIAN_MAX(t236, t234);
                uint8_t t246 = MEDIAN_MIN(t239, t230);
                uint8_t t247 = MEDIAN_MAX(t239, t230);
                uint8_t t253 = MEDIAN_MAX(buf[4480 + x], buf[16963 + x]);
                uint8_t t254 = MEDIAN_MIN(buf[22083 + x], t253);
                uint8_t t255 = MEDIAN_MAX(buf[22083 + x], t253);
                uint8_t t256 = MEDIAN_MIN(buf[13760 + x], buf[19523 + x]);
                uint8_t t257 = MEDIAN_MAX(buf[13760 + x], buf[19523 + x]);
                uint8_t t259 = MEDIAN_MAX(t256, t254);
                uint8_t t260 = MEDIAN_MIN(t257, t255);
                uint8_t t263 = MEDIAN_MAX(buf[12480 + x], buf[18243 + x]);
                uint8_t t264 = MEDIAN_MIN(buf[23363 + x], t263);
                uint8_t t266 = MEDIAN_MIN(buf[15040 + x], buf[20803 + x]);
                uint8_t t268 = MEDIAN_MIN(t266, t264);
                uint8_t t269 = MEDIAN_MAX(t266, t264);
                uint8_t t275 = MEDIAN_MAX(t268, t259);
                uint8_t t276 = MEDIAN_MIN(t269, t260);
                uint8_t t288 = MEDIAN_MIN(t275, t246);
                uint8_t t289 = MEDIAN_MAX(t275, t246);
                uint8_t t290 = MEDIAN_MIN(t276, t247);
                uint8_t t291 = MEDIAN_MAX(t276, t247);
                uint8_t t301 = MEDIAN_MAX(buf[4800 + x], buf[16643 + x]);
                uint8_t t302 = MEDIAN_MIN(buf[5120 + x], buf[21763 + x]);
                uint8_t t304 = MEDIAN_MIN(t302, t301);
                uint8_t t305 = MEDIAN_MAX(t302, t301);
                uint8_t t306 = MEDIAN_MIN(buf[13440 + x], buf[19203 + x]);
                uint8_t t307 = MEDIAN_MAX(buf[13440 + x], buf[19203 + x]);
                uint8_t t309 = MEDIAN_MAX(t306, t304);
                uint8_t t310 = MEDIAN_MIN(t307, t305);
                uint8_t t313 = MEDIAN_MAX(buf[12160 + x], buf[17923 + x]);
                uint8_t t314 = MEDIAN_MIN(buf[23043 + x], t313);
                uint8_t t316 = MEDIAN_MIN(buf[14720 + x], buf[20483 + x]);
                uint8_t t318 = MEDIAN_MIN(t316, t314);
                uint8_t t319 = MEDIAN_MAX(t316, t314);
                uint8_t t325 = MEDIAN_MAX(t318, t309);
                uint8_t t326 = MEDIAN_MIN(t319, t310);
                uint8_t t327 = MEDIAN_MAX(t319, t310);
                uint8_t t333 = MEDIAN_MAX(buf[2240 + x], buf[17283 + x]);
                uint8_t t334 = MEDIAN_MIN(buf[22403 + x], t333);
                uint8_t t335 = MEDIAN_MAX(buf[22403 + x], t333);
                uint8_t t336 = MEDIAN_MIN(buf[14080 + x], buf[19843 + x]);
                uint8_t t337 = MEDIAN_MAX(buf[14080 + x], buf[19843 + x]);
                uint8_t t339 = MEDIAN_MAX(t336, t334);
                uint8_t t340 = MEDIAN_MIN(t337, t335);
                uint8_t t343 = MEDIAN_MAX(buf[12800 + x], buf[18563 + x]);
                uint8_t t344 = MEDIAN_MIN(buf[16323 + x], t343);
                uint8_t t346 = MEDIAN_MIN(buf[15360 + x], buf[21123 + x]);
                uint8_t t348 = MEDIAN_MIN(t346, t344);
                uint8_t t349 = MEDIAN_MAX(t346, t344);
                uint8_t t354 = MEDIAN_MIN(t348, t339);
                uint8_t t355 = MEDIAN_MAX(t348, t339);
                uint8_t t356 = MEDIAN_MIN(t349, t340);
                uint8_t t367 = MEDIAN_MAX(t354, t325);
                uint8_t t368 = MEDIAN_MIN(t355, t326);
                uint8_t t369 = MEDIAN_MAX(t355, t326);
                uint8_t t370 = MEDIAN_MIN(t356, t327);
                uint8_t t396 = MEDIAN_MIN(t367, t288);
                uint8_t t397 = MEDIAN_MAX(t367, t288);
                uint8_t t398 = MEDIAN_MIN(t368, t289);
                uint8_t t399 = MEDIAN_MAX(t368, t289);
                uint8_t t400 = MEDIAN_MIN(t369, t290);
                uint8_t t401 = MEDIAN_MAX(t369, t290);
                uint8_t t402 = MEDIAN_MIN(t370, t291);
                uint8_t t403 = MEDIAN_MAX(t370, t291);
                uint8_t t448 = MEDIAN_MAX(t396, buf[25600 + x]);
                uint8_t t449 = MEDIAN_MAX(t397, buf[25280 + x]);
                uint8_t t450 = MEDIAN_MAX(t398, buf[24960 + x]);
                uint8_t t451 = MEDIAN_MAX(t399, buf[24640 + x]);
                uint8_t t452 = MEDIAN_MAX(t400, buf[24320 + x]);
                uint8_t t453 = MEDIAN_MAX(t401, buf[24000 + x]);
                uint8_t t454 = MEDIAN_MAX(t402, buf[23680 + x]);
                uint8_t t455 = MEDIAN_MIN(t448, t449);
                uint8_t t456 = MEDIAN_MIN(t455, t450);
                uint8_t t457 = MEDIAN_MIN(t456, t451);
                uint8_t t458 = MEDIAN_MIN(t457, t452);
                uint8_t t459 = MEDIAN_MIN(t458, t453);
                uint8_t t460 = MEDIAN_MIN(t459, t454);
                uint8_t t461 = MEDIAN_MIN(t460, t403);
                buf[11840 + x] = t461;
                uint8_t t490 = MEDIAN_MAX(t396, buf[27840 + x]);
                uint8_t t491 = MEDIAN_MAX(t397, buf[27520 + x]);
                uint8_t t492 = MEDIAN_MAX(t398, buf[27200 + x]);
                uint8_t t493 = MEDIAN_MAX(t399, buf[26880 + x]);
                uint8_t t494 = MEDIAN_MAX(t400, buf[26560 + x]);
                uint8_t t495 = MEDIAN_MAX(t401, buf[26240 + x]);
                uint8_t t496 = MEDIAN_MAX(t402, buf[25920 + x]);
                uint8_t t497 = MEDIAN_MIN(t490, t491);
                uint8_t t498 = MEDIAN_MIN(t497, t492);
                uint8_t t499 = MEDIAN_MIN(t498, t493);
                uint8_t t500 = MEDIAN_MIN(t499, t494);
                uint8_t t501 = MEDIAN_MIN(t500, t495);
                uint8_t t502 = MEDIAN_MIN(t501, t496);
                uint8_t t503 = MEDIAN_MIN(t502, t403);
                buf[11520 + x] = t503;
            }
            memcpy(oflat + y * lanes + c0, buf + 11840, (size_t)m * sizeof(uint8_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 11520, (size_t)m * sizeof(uint8_t));
        }
    }
}

static void median7_c1_uint16(const uint16_t *restrict flat, uint16_t *restrict oflat, index_t rows, index_t lanes,
                              index_t y0, index_t y1, uint16_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 6;
            index_t lo = max_i(0, 3 - c0), hi = min_i(n_in, 3 + lanes - c0);
            for (index_t r = 0; r < 8; r++) {
                const uint16_t *src = flat + min_i(max_i(y + r - 3, 0), rows - 1) * lanes;
                uint16_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 3, (size_t)(hi - lo) * sizeof(uint16_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 1];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 1 + (c0 + j) % 1];
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t8 = MEDIAN_MIN(buf[640 + x], buf[960 + x]);
                uint16_t t9 = MEDIAN_MAX(buf[640 + x], buf[960 + x]);
                uint16_t t10 = MEDIAN_MIN(buf[320 + x], t8);
                uint16_t t11 = MEDIAN_MAX(buf[320 + x], t8);
                uint16_t t12 = MEDIAN_MIN(t9, t11);
                uint16_t t13 = MEDIAN_MAX(t9, t11);
                uint16_t t14 = MEDIAN_MIN(buf[1600 + x], buf[1920 + x]);
                uint16_t t15 = MEDIAN_MAX(buf[1600 + x], buf[1920 + x]);
                uint16_t t16 = MEDIAN_MIN(buf[1280 + x], t14);
                uint16_t t17 = MEDIAN_MAX(buf[1280 + x], t14);
                uint16_t t18 = MEDIAN_MIN(t15, t17);
                uint16_t t19 = MEDIAN_MAX(t15, t17);
                uint16_t t20 = MEDIAN_MIN(t10, t16);
                buf[2560 + x] = t20;
                uint16_t t21 = MEDIAN_MAX(t10, t16);
                uint16_t t22 = MEDIAN_MIN(t13, t19);
                uint16_t t23 = MEDIAN_MAX(t13, t19);
                buf[2880 + x] = t23;
                uint16_t t24 = MEDIAN_MIN(t22, t21);
                uint16_t t25 = MEDIAN_MAX(t22, t21);
                uint16_t t26 = MEDIAN_MIN(t12, t18);
                uint16_t t27 = MEDIAN_MAX(t12, t18);
                uint16_t t28 = MEDIAN_MIN(t26, t24);
                buf[3200 + x] = t28;
                uint16_t t29 = MEDIAN_MAX(t26, t24);
                buf[3520 + x] = t29;
                uint16_t t30 = MEDIAN_MIN(t27, t25);
                buf[3840 + x] = t30;
                uint16_t t31 = MEDIAN_MAX(t27, t25);
                buf[4160 + x] = t31;
                uint16_t t420 = MEDIAN_MIN(buf[0 + x], buf[1 + x]);
                buf[4480 + x] = t420;
                uint16_t t421 = MEDIAN_MAX(buf[0 + x], buf[1 + x]);
                buf[4800 + x] = t421;
                uint16_t t462 = MEDIAN_MIN(buf[2240 + x], buf[2241 + x]);
                buf[5120 + x] = t462;
                uint16_t t463 = MEDIAN_MAX(buf[2240 + x], buf[2241 + x]);
                buf[5440 + x] = t463;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t32 = MEDIAN_MIN(buf[2560 + x], buf[2561 + x]);
                buf[1920 + x] = t32;
                uint16_t t33 = MEDIAN_MAX(buf[2560 + x], buf[2561 + x]);
                uint16_t t34 = MEDIAN_MIN(buf[4160 + x], buf[4161 + x]);
                uint16_t t35 = MEDIAN_MAX(buf[4160 + x], buf[4161 + x]);
                uint16_t t36 = MEDIAN_MIN(t34, t33);
                uint16_t t37 = MEDIAN_MAX(t34, t33);
                uint16_t t38 = MEDIAN_MIN(buf[3520 + x], buf[3521 + x]);
                uint16_t t39 = MEDIAN_MAX(buf[3520 + x], buf[3521 + x]);
                uint16_t t40 = MEDIAN_MIN(t38, t36);
                uint16_t t41 = MEDIAN_MAX(t38, t36);
                uint16_t t42 = MEDIAN_MIN(t39, t37);
                uint16_t t43 = MEDIAN_MAX(t39, t37);
                uint16_t t44 = MEDIAN_MIN(buf[3200 + x], buf[3201 + x]);
                uint16_t t45 = MEDIAN_MAX(buf[3200 + x], buf[3201 + x]);
                uint16_t t46 = MEDIAN_MIN(buf[2880 + x], buf[2881 + x]);
                uint16_t t47 = MEDIAN_MAX(buf[2880 + x], buf[2881 + x]);
                buf[1600 + x] = t47;
                uint16_t t48 = MEDIAN_MIN(t46, t45);
                uint16_t t49 = MEDIAN_MAX(t46, t45);
                uint16_t t50 = MEDIAN_MIN(buf[3840 + x], buf[3841 + x]);
                uint16_t t51 = MEDIAN_MAX(buf[3840 + x], buf[3841 + x]);
                uint16_t t52 = MEDIAN_MIN(t50, t48);
                uint16_t t53 = MEDIAN_MAX(t50, t48);
                uint16_t t54 = MEDIAN_MIN(t51, t49);
                uint16_t t55 = MEDIAN_MAX(t51, t49);
                uint16_t t56 = MEDIAN_MIN(t44, t40);
                buf[1280 + x] = t56;
                uint16_t t57 = MEDIAN_MAX(t44, t40);
                buf[960 + x] = t57;
                uint16_t t58 = MEDIAN_MIN(t52, t41);
                buf[640 + x] = t58;
                uint16_t t59 = MEDIAN_MAX(t52, t41);
                buf[320 + x] = t59;
                uint16_t t60 = MEDIAN_MIN(t53, t42);
                buf[5760 + x] = t60;
                uint16_t t61 = MEDIAN_MAX(t53, t42);
                buf[6080 + x] = t61;
                uint16_t t62 = MEDIAN_MIN(t54, t43);
                buf[6400 + x] = t62;
                uint16_t t63 = MEDIAN_MAX(t54, t43);
                buf[6720 + x] = t63;
                uint16_t t64 = MEDIAN_MIN(t55, t35);
                buf[7040 + x] = t64;
                uint16_t t65 = MEDIAN_MAX(t55, t35);
                buf[7360 + x] = t65;
                uint16_t t422 = MEDIAN_MIN(buf[0 + x], buf[4481 + x]);
                buf[7680 + x] = t422;
                uint16_t t423 = MEDIAN_MAX(buf[0 + x], buf[4481 + x]);
                uint16_t t424 = MEDIAN_MIN(buf[4801 + x], t423);
                buf[8000 + x] = t424;
                uint16_t t425 = MEDIAN_MAX(buf[4801 + x], t423);
                buf[8320 + x] = t425;
                uint16_t t426 = MEDIAN_MIN(buf[4480 + x], buf[4482 + x]);
                buf[8640 + x] = t426;
                uint16_t t427 = MEDIAN_MAX(buf[4480 + x], buf[4482 + x]);
                uint16_t t428 = MEDIAN_MIN(buf[4800 + x], buf[4802 + x]);
                uint16_t t429 = MEDIAN_MAX(buf[4800 + x], buf[4802 + x]);
                buf[8960 + x] = t429;
                uint16_t t430 = MEDIAN_MIN(t428, t427);
                buf[9280 + x] = t430;
                uint16_t t431 = MEDIAN_MAX(t428, t427);
                buf[9600 + x] = t431;
                uint16_t t464 = MEDIAN_MIN(buf[2240 + x], buf[5121 + x]);
                buf[9920 + x] = t464;
                uint16_t t465 = MEDIAN_MAX(buf[2240 + x], buf[5121 + x]);
                uint16_t t466 = MEDIAN_MIN(buf[5441 + x], t465);
                buf[10240 + x] = t466;
                uint16_t t467 = MEDIAN_MAX(buf[5441 + x], t465);
                buf[10560 + x] = t467;
                uint16_t t468 = MEDIAN_MIN(buf[5120 + x], buf[5122 + x]);
                buf[10880 + x] = t468;
                uint16_t t469 = MEDIAN_MAX(buf[5120 + x], buf[5122 + x]);
                uint16_t t470 = MEDIAN_MIN(buf[5440 + x], buf[5442 + x]);
                uint16_t t471 = MEDIAN_MAX(buf[5440 + x], buf[5442 + x]);
                buf[11200 + x] = t471;
                uint16_t t472 = MEDIAN_MIN(t470, t469);
                buf[11520 + x] = t472;
                uint16_t t473 = MEDIAN_MAX(t470, t469);
                buf[11840 + x] = t473;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t66 = MEDIAN_MIN(buf[2560 + x], buf[1921 + x]);
                buf[5440 + x] = t66;
                uint16_t t67 = MEDIAN_MAX(buf[2560 + x], buf[1921 + x]);
                uint16_t t68 = MEDIAN_MIN(buf[6721 + x], t67);
                uint16_t t69 = MEDIAN_MAX(buf[6721 + x], t67);
                uint16_t t70 = MEDIAN_MIN(buf[4160 + x], buf[321 + x]);
                uint16_t t71 = MEDIAN_MAX(buf[4160 + x], buf[321 + x]);
                uint16_t t72 = MEDIAN_MIN(t70, t68);
                uint16_t t73 = MEDIAN_MAX(t70, t68);
                uint16_t t74 = MEDIAN_MIN(t71, t69);
                uint16_t t75 = MEDIAN_MAX(t71, t69);
                uint16_t t76 = MEDIAN_MIN(buf[3520 + x], buf[961 + x]);
                uint16_t t77 = MEDIAN_MAX(buf[3520 + x], buf[961 + x]);
                uint16_t t78 = MEDIAN_MIN(buf[7361 + x], t77);
                uint16_t t79 = MEDIAN_MAX(buf[7361 + x], t77);
                uint16_t t80 = MEDIAN_MIN(buf[6081 + x], t78);
                uint16_t t81 = MEDIAN_MAX(buf[6081 + x], t78);
                uint16_t t82 = MEDIAN_MIN(t76, t72);
                uint16_t t83 = MEDIAN_MAX(t76, t72);
                uint16_t t84 = MEDIAN_MIN(t80, t73);
                uint16_t t85 = MEDIAN_MAX(t80, t73);
                uint16_t t86 = MEDIAN_MIN(t81, t74);
                uint16_t t87 = MEDIAN_MAX(t81, t74);
                uint16_t t88 = MEDIAN_MIN(t79, t75);
                uint16_t t89 = MEDIAN_MAX(t79, t75);
                uint16_t t90 = MEDIAN_MIN(buf[3200 + x], buf[1281 + x]);
                uint16_t t91 = MEDIAN_MAX(buf[3200 + x], buf[1281 + x]);
                uint16_t t92 = MEDIAN_MIN(buf[7041 + x], t91);
                uint16_t t93 = MEDIAN_MAX(buf[7041 + x], t91);
                uint16_t t94 = MEDIAN_MIN(buf[2880 + x], buf[5761 + x]);
                uint16_t t95 = MEDIAN_MAX(buf[2880 + x], buf[5761 + x]);
                uint16_t t96 = MEDIAN_MIN(t94, t92);
                uint16_t t97 = MEDIAN_MAX(t94, t92);
                uint16_t t98 = MEDIAN_MIN(t95, t93);
                uint16_t t99 = MEDIAN_MAX(t95, t93);
                uint16_t t100 = MEDIAN_MIN(buf[3840 + x], buf[641 + x]);
                uint16_t t101 = MEDIAN_MAX(buf[3840 + x], buf[641 + x]);
                uint16_t t102 = MEDIAN_MIN(buf[1601 + x], t101);
                uint16_t t103 = MEDIAN_MAX(buf[1601 + x], t101);
                uint16_t t104 = MEDIAN_MIN(buf[6401 + x], t102);
                uint16_t t105 = MEDIAN_MAX(buf[6401 + x], t102);
                uint16_t t106 = MEDIAN_MIN(t100, t96);
                uint16_t t107 = MEDIAN_MAX(t100, t96);
                uint16_t t108 = MEDIAN_MIN(t104, t97);
                uint16_t t109 = MEDIAN_MAX(t104, t97);
                uint16_t t110 = MEDIAN_MIN(t105, t98);
                uint16_t t111 = MEDIAN_MAX(t105, t98);
                uint16_t t112 = MEDIAN_MIN(t103, t99);
                uint16_t t113 = MEDIAN_MAX(t103, t99);
                buf[5120 + x] = t113;
                uint16_t t114 = MEDIAN_MIN(t90, t82);
                buf[4800 + x] = t114;
                uint16_t t115 = MEDIAN_MAX(t90, t82);
                buf[4480 + x] = t115;
                uint16_t t116 = MEDIAN_MIN(t106, t83);
                buf[2240 + x] = t116;
                uint16_t t117 = MEDIAN_MAX(t106, t83);
                buf[0 + x] = t117;
                uint16_t t118 = MEDIAN_MIN(t107, t84);
                buf[12160 + x] = t118;
                uint16_t t119 = MEDIAN_MAX(t107, t84);
                buf[12480 + x] = t119;
                uint16_t t120 = MEDIAN_MIN(t108, t85);
                buf[12800 + x] = t120;
                uint16_t t121 = MEDIAN_MAX(t108, t85);
                buf[13120 + x] = t121;
                uint16_t t122 = MEDIAN_MIN(t109, t86);
                buf[13440 + x] = t122;
                uint16_t t123 = MEDIAN_MAX(t109, t86);
                buf[13760 + x] = t123;
                uint16_t t124 = MEDIAN_MIN(t110, t87);
                buf[14080 + x] = t124;
                uint16_t t125 = MEDIAN_MAX(t110, t87);
                buf[14400 + x] = t125;
                uint16_t t126 = MEDIAN_MIN(t111, t88);
                buf[14720 + x] = t126;
                uint16_t t127 = MEDIAN_MAX(t111, t88);
                buf[15040 + x] = t127;
                uint16_t t128 = MEDIAN_MIN(t112, t89);
                buf[15360 + x] = t128;
                uint16_t t129 = MEDIAN_MAX(t112, t89);
                buf[15680 + x] = t129;
                uint16_t t130 = MEDIAN_MIN(buf[1920 + x], buf[1922 + x]);
                buf[16000 + x] = t130;
                uint16_t t131 = MEDIAN_MAX(buf[1920 + x], buf[1922 + x]);
                uint16_t t132 = MEDIAN_MIN(buf[6720 + x], buf[6722 + x]);
                uint16_t t133 = MEDIAN_MAX(buf[6720 + x], buf[6722 + x]);
                uint16_t t134 = MEDIAN_MIN(t132, t131);
                uint16_t t135 = MEDIAN_MAX(t132, t131);
                uint16_t t136 = MEDIAN_MIN(buf[320 + x], buf[322 + x]);
                uint16_t t137 = MEDIAN_MAX(buf[320 + x], buf[322 + x]);
                uint16_t t138 = MEDIAN_MIN(t136, t134);
                uint16_t t139 = MEDIAN_MAX(t136, t134);
                uint16_t t140 = MEDIAN_MIN(t137, t135);
                uint16_t t141 = MEDIAN_MAX(t137, t135);
                uint16_t t142 = MEDIAN_MIN(buf[960 + x], buf[962 + x]);
                uint16_t t143 = MEDIAN_MAX(buf[960 + x], buf[962 + x]);
                uint16_t t144 = MEDIAN_MIN(buf[7360 + x], buf[7362 + x]);
                uint16_t t145 = MEDIAN_MAX(buf[7360 + x], buf[7362 + x]);
                uint16_t t146 = MEDIAN_MIN(t144, t143);
                uint16_t t147 = MEDIAN_MAX(t144, t143);
                uint16_t t148 = MEDIAN_MIN(buf[6080 + x], buf[6082 + x]);
                uint16_t t149 = MEDIAN_MAX(buf[6080 + x], buf[6082 + x]);
                uint16_t t150 = MEDIAN_MIN(t148, t146);
                uint16_t t151 = MEDIAN_MAX(t148, t146);
                uint16_t t152 = MEDIAN_MIN(t149, t147);
                uint16_t t153 = MEDIAN_MAX(t149, t147);
                uint16_t t154 = MEDIAN_MIN(t142, t138);
                uint16_t t155 = MEDIAN_MAX(t142, t138);
                uint16_t t156 = MEDIAN_MIN(t150, t139);
                uint16_t t157 = MEDIAN_MAX(t150, t139);
                uint16_t t158 = MEDIAN_MIN(t151, t140);
                uint16_t t159 = MEDIAN_MAX(t151, t140);
                uint16_t t160 = MEDIAN_MIN(t152, t141);
                uint16_t t161 = MEDIAN_MAX(t152, t141);
                uint16_t t162 = MEDIAN_MIN(t153, t133);
                uint16_t t163 = MEDIAN_MAX(t153, t133);
                uint16_t t164 = MEDIAN_MIN(buf[1280 + x], buf[1282 + x]);
                uint16_t t165 = MEDIAN_MAX(buf[1280 + x], buf[1282 + x]);
                uint16_t t166 = MEDIAN_MIN(buf[7040 + x], buf[7042 + x]);
                uint16_t t167 = MEDIAN_MAX(buf[7040 + x], buf[7042 + x]);
                uint16_t t168 = MEDIAN_MIN(t166, t165);
                uint16_t t169 = MEDIAN_MAX(t166, t165);
                uint16_t t170 = MEDIAN_MIN(buf[5760 + x], buf[5762 + x]);
                uint16_t t171 = MEDIAN_MAX(buf[5760 + x], buf[5762 + x]);
                uint16_t t172 = MEDIAN_MIN(t170, t168);
                uint16_t t173 = MEDIAN_MAX(t170, t168);
                uint16_t t174 = MEDIAN_MIN(t171, t169);
                uint16_t t175 = MEDIAN_MAX(t171, t169);
                uint16_t t176 = MEDIAN_MIN(buf[640 + x], buf[642 + x]);
                uint16_t t177 = MEDIAN_MAX(buf[640 + x], buf[642 + x]);
                uint16_t t178 = MEDIAN_MIN(buf[1600 + x], buf[1602 + x]);
                uint16_t t179 = MEDIAN_MAX(buf[1600 + x], buf[1602 + x]);
                buf[16320 + x] = t179;
                uint16_t t180 = MEDIAN_MIN(t178, t177);
                uint16_t t181 = MEDIAN_MAX(t178, t177);
                uint16_t t182 = MEDIAN_MIN(buf[6400 + x], buf[6402 + x]);
                uint16_t t183 = MEDIAN_MAX(buf[6400 + x], buf[6402 + x]);
                uint16_t t184 = MEDIAN_MIN(t182, t180);
                uint16_t t185 = MEDIAN_MAX(t182, t180);
                uint16_t t186 = MEDIAN_MIN(t183, t181);
                uint16_t t187 = MEDIAN_MAX(t183, t181);
                uint16_t t188 = MEDIAN_MIN(t176, t172);
                uint16_t t189 = MEDIAN_MAX(t176, t172);
                uint16_t t190 = MEDIAN_MIN(t184, t173);
                uint16_t t191 = MEDIAN_MAX(t184, t173);
                uint16_t t192 = MEDIAN_MIN(t185, t174);
                uint16_t t193 = MEDIAN_MAX(t185, t174);
                uint16_t t194 = MEDIAN_MIN(t186, t175);
                uint16_t t195 = MEDIAN_MAX(t186, t175);
                uint16_t t196 = MEDIAN_MIN(t187, t167);
                uint16_t t197 = MEDIAN_MAX(t187, t167);
                uint16_t t198 = MEDIAN_MIN(t164, t154);
                buf[16640 + x] = t198;
                uint16_t t199 = MEDIAN_MAX(t164, t154);
                buf[16960 + x] = t199;
                uint16_t t200 = MEDIAN_MIN(t188, t155);
                buf[17280 + x] = t200;
                uint16_t t201 = MEDIAN_MAX(t188, t155);
                buf[17600 + x] = t201;
                uint16_t t202 = MEDIAN_MIN(t189, t156);
                buf[17920 + x] = t202;
                uint16_t t203 = MEDIAN_MAX(t189, t156);
                buf[18240 + x] = t203;
                uint16_t t204 = MEDIAN_MIN(t190, t157);
                buf[18560 + x] = t204;
                uint16_t t205 = MEDIAN_MAX(t190, t157);
                buf[18880 + x] = t205;
                uint16_t t206 = MEDIAN_MIN(t191, t158);
                buf[19200 + x] = t206;
                uint16_t t207 = MEDIAN_MAX(t191, t158);
                buf[19520 + x] = t207;
                uint16_t t208 = MEDIAN_MIN(t192, t159);
                buf[19840 + x] = t208;
                uint16_t t209 = MEDIAN_MAX(t192, t159);
                buf[20160 + x] = t209;
                uint16_t t210 = MEDIAN_MIN(t193, t160);
                buf[20480 + x] = t210;
                uint16_t t211 = MEDIAN_MAX(t193, t160);
                buf[20800 + x] = t211;
                uint16_t t212 = MEDIAN_MIN(t194, t161);
                buf[21120 + x] = t212;
                uint16_t t213 = MEDIAN_MAX(t194, t161);
                buf[21440 + x] = t213;
                uint16_t t214 = MEDIAN_MIN(t195, t162);
                buf[21760 + x] = t214;
                uint16_t t215 = MEDIAN_MAX(t195, t162);
                buf[22080 + x] = t215;
                uint16_t t216 = MEDIAN_MIN(t196, t163);
                buf[22400 + x] = t216;
                uint16_t t217 = MEDIAN_MAX(t196, t163);
                buf[22720 + x] = t217;
                uint16_t t218 = MEDIAN_MIN(t197, t145);
                buf[23040 + x] = t218;
                uint16_t t219 = MEDIAN_MAX(t197, t145);
                buf[23360 + x] = t219;
                uint16_t t432 = MEDIAN_MIN(buf[7680 + x], buf[8643 + x]);
                buf[23680 + x] = t432;
                uint16_t t433 = MEDIAN_MAX(buf[7680 + x], buf[8643 + x]);
                uint16_t t434 = MEDIAN_MIN(buf[8320 + x], buf[9603 + x]);
                uint16_t t435 = MEDIAN_MAX(buf[8320 + x], buf[9603 + x]);
                uint16_t t436 = MEDIAN_MIN(t434, t433);
                uint16_t t437 = MEDIAN_MAX(t434, t433);
                uint16_t t438 = MEDIAN_MIN(buf[8000 + x], buf[9283 + x]);
                uint16_t t439 = MEDIAN_MAX(buf[8000 + x], buf[9283 + x]);
                uint16_t t440 = MEDIAN_MIN(buf[8963 + x], t439);
                uint16_t t441 = MEDIAN_MAX(buf[8963 + x], t439);
                uint16_t t442 = MEDIAN_MIN(t438, t436);
                buf[24000 + x] = t442;
                uint16_t t443 = MEDIAN_MAX(t438, t436);
                buf[24320 + x] = t443;
                uint16_t t444 = MEDIAN_MIN(t440, t437);
                buf[24640 + x] = t444;
                uint16_t t445 = MEDIAN_MAX(t440, t437);
                buf[24960 + x] = t445;
                uint16_t t446 = MEDIAN_MIN(t441, t435);
                buf[25280 + x] = t446;
                uint16_t t447 = MEDIAN_MAX(t441, t435);
                buf[25600 + x] = t447;
                uint16_t t474 = MEDIAN_MIN(buf[9920 + x], buf[10883 + x]);
                buf[25920 + x] = t474;
                uint16_t t475 = MEDIAN_MAX(buf[9920 + x], buf[10883 + x]);
                uint16_t t476 = MEDIAN_MIN(buf[10560 + x], buf[11843 + x]);
                uint16_t t477 = MEDIAN_MAX(buf[10560 + x], buf[11843 + x]);
                uint16_t t478 = MEDIAN_MIN(t476, t475);
                uint16_t t479 = MEDIAN_MAX(t476, t475);
                uint16_t t480 = MEDIAN_MIN(buf[10240 + x], buf[11523 + x]);
                uint16_t t481 = MEDIAN_MAX(buf[10240 + x], buf[11523 + x]);
                uint16_t t482 = MEDIAN_MIN(buf[11203 + x], t481);
                uint16_t t483 = MEDIAN_MAX(buf[11203 + x], t481);
                uint16_t t484 = MEDIAN_MIN(t480, t478);
                buf[26240 + x] = t484;
                uint16_t t485 = MEDIAN_MAX(t480, t478);
                buf[26560 + x] = t485;
                uint16_t t486 = MEDIAN_MIN(t482, t479);
                buf[26880 + x] = t486;
                uint16_t t487 = MEDIAN_MAX(t482, t479);
                buf[27200 + x] = t487;
                uint16_t t488 = MEDIAN_MIN(t483, t477);
                buf[27520 + x] = t488;
                uint16_t t489 = MEDIAN_MAX(t483, t477);
                buf[27840 + x] = t489;
            }
            for (index_t x = 0; x < 256; x++) {
                uint16_t t221 = MEDIAN_MAX(buf[5440 + x], buf[16003 + x]);
                uint16_t t222 = MEDIAN_MIN(buf[15680 + x], buf[21443 + x]);
                uint16_t t225 = MEDIAN_MAX(t222, t221);
                uint16_t t227 = MEDIAN_MAX(buf[13120 + x], buf[18883 + x]);
                uint16_t t230 = MEDIAN_MIN(t227, t225);
                uint16_t t233 = MEDIAN_MAX(buf[0 + x], buf[17603 + x]);
                uint16_t t234 = MEDIAN_MIN(buf[22723 + x], t233);
                uint16_t t236 = MEDIAN_MIN(buf[14400 + x], buf[20163 + x]);
                uint16_t t239 = MEDIAN_MAX(t236, t234);
                uint16_t t246 = MEDIAN_MIN(t239, t230);
                uint16_t t247 = MEDIAN_MAX(t239, t230);
                uint16_t t253 = MEDIAN_MAX(buf[4480 + x], buf[16963 + x]);
                uint16_t t254 = MEDIAN_MIN(buf[22083 + x], t253);
                uint16_t t255 = MEDIAN_MAX(buf[22083 + x], t253);
                uint16_t t256 = MEDIAN_MIN(buf[13760 + x], buf[19523 + x]);
                uint16_t t257 = MEDIAN_MAX(buf[13760 + x], buf[19523 + x]);
                uint16_t t259 = MEDIAN_MAX(t256, t254);
                uint16_t t260 = MEDIAN_MIN(t257, t255);
                uint16_t t263 = MEDIAN_MAX(buf[12480 + x], buf[18243 + x]);
                uint16_t t264 = MEDIAN_MIN(buf[23363 + x], t263);
                uint16_t t266 = MEDIAN_MIN(buf[15040 + x], buf[20803 + x]);
                uint16_t t268 = MEDIAN_MIN(t266, t264);
                uint16_t t269 = MEDIAN_MAX(t266, t264);
                uint16_t t275 = MEDIAN_MAX(t268, t259);
                uint16_t t276 = MEDIAN_MIN(t269, t260);
                uint16_t t288 = MEDIAN_MIN(t275, t246);
                uint16_t t289 = MEDIAN_MAX(t275, t246);
                uint16_t t290 = MEDIAN_MIN(t276, t247);
                uint16_t t291 = MEDIAN_MAX(t276, t247);
                uint16_t t301 = MEDIAN_MAX(buf[4800 + x], buf[16643 + x]);
                uint16_t t302 = MEDIAN_MIN(buf[5120 + x], buf[21763 + x]);
                uint16_t t304 = MEDIAN_MIN(t302, t301);
                uint16_t t305 = MEDIAN_MAX(t302, t301);
                uint16_t t306 = MEDIAN_MIN(buf[13440 + x], buf[19203 + x]);
                uint16_t t307 = MEDIAN_MAX(buf[13440 + x], buf[19203 + x]);
                uint16_t t309 = MEDIAN_MAX(t306, t304);
                uint16_t t310 = MEDIAN_MIN(t307, t305);
                uint16_t t313 = MEDIAN_MAX(buf[12160 + x], buf[17923 + x]);
                uint16_t t314 = MEDIAN_MIN(buf[23043 + x], t313);
                uint16_t t316 = MEDIAN_MIN(buf[14720 + x], buf[20483 + x]);
                uint16_t t318 = MEDIAN_MIN(t316, t314);
                uint16_t t319 = MEDIAN_MAX(t316, t314);
                uint16_t t325 = MEDIAN_MAX(t318, t309);
                uint16_t t326 = MEDIAN_MIN(t319, t310);
                uint16_t t327 = MEDIAN_MAX(t319, t310);
                uint16_t t333 = MEDIAN_MAX(buf[2240 + x], buf[17283 + x]);
                uint16_t t334 = MEDIAN_MIN(buf[22403 + x], t333);
                uint16_t t335 = MEDIAN_MAX(buf[22403 + x], t333);
                uint16_t t336 = MEDIAN_MIN(buf[14080 + x], buf[19843 + x]);
                uint16_t t337 = MEDIAN_MAX(buf[14080 + x], buf[19843 + x]);
                uint16_t t339 = MEDIAN_MAX(t336, t334);
                uint16_t t340 = MEDIAN_MIN(t337, t335);
                uint16_t t343 = MEDIAN_MAX(buf[12800 + x], buf[18563 + x]);
                uint16_t t344 = MEDIAN_MIN(buf[16323 + x], t343);
                uint16_t t346 = MEDIAN_MIN(buf[15360 + x], buf[21123 + x]);
                uint16_t t348 = MEDIAN_MIN(t346, t344);
                uint16_t t349 = MEDIAN_MAX(t346, t344);
                uint16_t t354 = MEDIAN_MIN(t348, t339);
                uint16_t t355 = MEDIAN_MAX(t348, t339);
                uint16_t t356 = MEDIAN_MIN(t349, t340);
                uint16_t t367 = MEDIAN_MAX(t354, t325);
                uint16_t t368 = MEDIAN_MIN(t355, t326);
                uint16_t t369 = MEDIAN_MAX(t355, t326);
                uint16_t t370 = MEDIAN_MIN(t356, t327);
                uint16_t t396 = MEDIAN_MIN(t367, t288);
                uint16_t t397 = MEDIAN_MAX(t367, t288);
                uint16_t t398 = MEDIAN_MIN(t368, t289);
                uint16_t t399 = MEDIAN_MAX(t368, t289);
                uint16_t t400 = MEDIAN_MIN(t369, t290);
                uint16_t t401 = MEDIAN_MAX(t369, t290);
                uint16_t t402 = MEDIAN_MIN(t370, t291);
                uint16_t t403 = MEDIAN_MAX(t370, t291);
                uint16_t t448 = MEDIAN_MAX(t396, buf[25600 + x]);
                uint16_t t449 = MEDIAN_MAX(t397, buf[25280 + x]);
                uint16_t t450 = MEDIAN_MAX(t398, buf[24960 + x]);
                uint16_t t451 = MEDIAN_MAX(t399, buf[24640 + x]);
                uint16_t t452 = MEDIAN_MAX(t400, buf[24320 + x]);
                uint16_t t453 = MEDIAN_MAX(t401, buf[24000 + x]);
                uint16_t t454 = MEDIAN_MAX(t402, buf[23680 + x]);
                uint16_t t455 = MEDIAN_MIN(t448, t449);
                uint16_t t456 = MEDIAN_MIN(t455, t450);
                uint16_t t457 = MEDIAN_MIN(t456, t451);
                uint16_t t458 = MEDIAN_MIN(t457, t452);
                uint16_t t459 = MEDIAN_MIN(t458, t453);
                uint16_t t460 = MEDIAN_MIN(t459, t454);
                uint16_t t461 = MEDIAN_MIN(t460, t403);
                buf[11840 + x] = t461;
                uint16_t t490 = MEDIAN_MAX(t396, buf[27840 + x]);
                uint16_t t491 = MEDIAN_MAX(t397, buf[27520 + x]);
                uint16_t t492 = MEDIAN_MAX(t398, buf[27200 + x]);
                uint16_t t493 = MEDIAN_MAX(t399, buf[26880 + x]);
                uint16_t t494 = MEDIAN_MAX(t400, buf[26560 + x]);
                uint16_t t495 = MEDIAN_MAX(t401, buf[26240 + x]);
                uint16_t t496 = MEDIAN_MAX(t402, buf[25920 + x]);
                uint16_t t497 = MEDIAN_MIN(t490, t491);
                uint16_t t498 = MEDIAN_MIN(t497, t492);
                uint16_t t499 = MEDIAN_MIN(t498, t493);
                uint16_t t500 = MEDIAN_MIN(t499, t494);
                uint16_t t501 = MEDIAN_MIN(t500, t495);
                uint16_t t502 = MEDIAN_MIN(t501, t496);
                uint16_t t503 = MEDIAN_MIN(t502, t403);
                buf[11520 + x] = t503;
            }
            memcpy(oflat + y * lanes + c0, buf + 11840, (size_t)m * sizeof(uint16_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 11520, (size_t)m * sizeof(uint16_t));
        }
    }
}

static void median7_c3_uint8(const uint8_t *restrict flat, uint8_t *restrict oflat, index_t rows, index_t lanes,
                             index_t y0, index_t y1, uint8_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 18;
            index_t lo = max_i(0, 9 - c0), hi = min_i(n_in, 9 + lanes - c0);
            for (index_t r = 0; r < 8; r++) {
                const uint8_t *src = flat + min_i(max_i(y + r - 3, 0), rows - 1) * lanes;
                uint8_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 9, (size_t)(hi - lo) * sizeof(uint8_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 3];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 3 + (c0 + j) % 3];
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t8 = MEDIAN_MIN(buf[640 + x], buf[960 + x]);
                uint8_t t9 = MEDIAN_MAX(buf[640 + x], buf[960 + x]);
                uint8_t t10 = MEDIAN_MIN(buf[320 + x], t8);
                uint8_t t11 = MEDIAN_MAX(buf[320 + x], t8);
                uint8_t t12 = MEDIAN_MIN(t9, t11);
                uint8_t t13 = MEDIAN_MAX(t9, t11);
                uint8_t t14 = MEDIAN_MIN(buf[1600 + x], buf[1920 + x]);
                uint8_t t15 = MEDIAN_MAX(buf[1600 + x], buf[1920 + x]);
                uint8_t t16 = MEDIAN_MIN(buf[1280 + x], t14);
                uint8_t t17 = MEDIAN_MAX(buf[1280 + x], t14);
                uint8_t t18 = MEDIAN_MIN(t15, t17);
                uint8_t t19 = MEDIAN_MAX(t15, t17);
                uint8_t t20 = MEDIAN_MIN(t10, t16);
                buf[2560 + x] = t20;
                uint8_t t21 = MEDIAN_MAX(t10, t16);
                uint8_t t22 = MEDIAN_MIN(t13, t19);
                uint8_t t23 = MEDIAN_MAX(t13, t19);
                buf[2880 + x] = t23;
                uint8_t t24 = MEDIAN_MIN(t22, t21);
                uint8_t t25 = MEDIAN_MAX(t22, t21);
                uint8_t t26 = MEDIAN_MIN(t12, t18);
                uint8_t t27 = MEDIAN_MAX(t12, t18);
                uint8_t t28 = MEDIAN_MIN(t26, t24);
                buf[3200 + x] = t28;
                uint8_t t29 = MEDIAN_MAX(t26, t24);
                buf[3520 + x] = t29;
                uint8_t t30 = MEDIAN_MIN(t27, t25);
                buf[3840 + x] = t30;
                uint8_t t31 = MEDIAN_MAX(t27, t25);
                buf[4160 + x] = t31;
                uint8_t t420 = MEDIAN_MIN(buf[0 + x], buf[3 + x]);
                buf[4480 + x] = t420;
                uint8_t t421 = MEDIAN_MAX(buf[0 + x], buf[3 + x]);
                buf[4800 + x] = t421;
                uint8_t t462 = MEDIAN_MIN(buf[2240 + x], buf[2243 + x]);
                buf[5120 + x] = t462;
                uint8_t t463 = MEDIAN_MAX(buf[2240 + x], buf[2243 + x]);
                buf[5440 + x] = t463;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t32 = MEDIAN_MIN(buf[2560 + x], buf[2563 + x]);
                buf[1920 + x] = t32;
                uint8_t t33 = MEDIAN_MAX(buf[2560 + x], buf[2563 + x]);
                uint8_t t34 = MEDIAN_MIN(buf[4160 + x], buf[4163 + x]);
                uint8_t t35 = MEDIAN_MAX(buf[4160 + x], buf[4163 + x]);
                uint8_t t36 = MEDIAN_MIN(t34, t33);
                uint8_t t37 = MEDIAN_MAX(t34, t33);
                uint8_t t38 = MEDIAN_MIN(buf[3520 + x], buf[3523 + x]);
                uint8_t t39 = MEDIAN_MAX(buf[3520 + x], buf[3523 + x]);
                uint8_t t40 = MEDIAN_MIN(t38, t36);
                uint8_t t41 = MEDIAN_MAX(t38, t36);
                uint8_t t42 = MEDIAN_MIN(t39, t37);
                uint8_t t43 = MEDIAN_MAX(t39, t37);
                uint8_t t44 = MEDIAN_MIN(buf[3200 + x], buf[3203 + x]);
                uint8_t t45 = MEDIAN_MAX(buf[3200 + x], buf[3203 + x]);
                uint8_t t46 = MEDIAN_MIN(buf[2880 + x], buf[2883 + x]);
                uint8_t t47 = MEDIAN_MAX(buf[2880 + x], buf[2883 + x]);
                buf[1600 + x] = t47;
                uint8_t t48 = MEDIAN_MIN(t46, t45);
                uint8_t t49 = MEDIAN_MAX(t46, t45);
                uint8_t t50 = MEDIAN_MIN(buf[3840 + x], buf[3843 + x]);
                uint8_t t51 = MEDIAN_MAX(buf[3840 + x], buf[3843 + x]);
                uint8_t t52 = MEDIAN_MIN(t50, t48);
                uint8_t t53 = MEDIAN_MAX(t50, t48);
                uint8_t t54 = MEDIAN_MIN(t51, t49);
                uint8_t t55 = MEDIAN_MAX(t51, t49);
                uint8_t t56 = MEDIAN_MIN(t44, t40);
                buf[1280 + x] = t56;
                uint8_t t57 = MEDIAN_MAX(t44, t40);
                buf[960 + x] = t57;
                uint8_t t58 = MEDIAN_MIN(t52, t41);
                buf[640 + x] = t58;
                uint8_t t59 = MEDIAN_MAX(t52, t41);
                buf[320 + x] = t59;
                uint8_t t60 = MEDIAN_MIN(t53, t42);
                buf[5760 + x] = t60;
                uint8_t t61 = MEDIAN_MAX(t53, t42);
                buf[6080 + x] = t61;
                uint8_t t62 = MEDIAN_MIN(t54, t43);
                buf[6400 + x] = t62;
                uint8_t t63 = MEDIAN_MAX(t54, t43);
                buf[6720 + x] = t63;
                uint8_t t64 = MEDIAN_MIN(t55, t35);
                buf[7040 + x] = t64;
                uint8_t t65 = MEDIAN_MAX(t55, t35);
                buf[7360 + x] = t65;
                uint8_t t422 = MEDIAN_MIN(buf[0 + x], buf[4483 + x]);
                buf[7680 + x] = t422;
                uint8_t t423 = MEDIAN_MAX(buf[0 + x], buf[4483 + x]);
                uint8_t t424 = MEDIAN_MIN(buf[4803 + x], t423);
                buf[8000 + x] = t424;
                uint8_t t425 = MEDIAN_MAX(buf[4803 + x], t423);
                buf[8320 + x] = t425;
                uint8_t t426 = MEDIAN_MIN(buf[4480 + x], buf[4486 + x]);
                buf[8640 + x] = t426;
                uint8_t t427 = MEDIAN_MAX(buf[4480 + x], buf[4486 + x]);
                uint8_t t428 = MEDIAN_MIN(buf[4800 + x], buf[4806 + x]);
                uint8_t t429 = MEDIAN_MAX(buf[4800 + x], buf[4806 + x]);
                buf[8960 + x] = t429;
                uint8_t t430 = MEDIAN_MIN(t428, t427);
                buf[9280 + x] = t430;
                uint8_t t431 = MEDIAN_MAX(t428, t427);
                buf[9600 + x] = t431;
                uint8_t t464 = MEDIAN_MIN(buf[2240 + x], buf[5123 + x]);
                buf[9920 + x] = t464;
                uint8_t t465 = MEDIAN_MAX(buf[2240 + x], buf[5123 + x]);
                uint8_t t466 = MEDIAN_MIN(buf[5443 + x], t465);
                buf[10240 + x] = t466;
                uint8_t t467 = MEDIAN_MAX(buf[5443 + x], t465);
                buf[10560 + x] = t467;
                uint8_t t468 = MEDIAN_MIN(buf[5120 + x], buf[5126 + x]);
                buf[10880 + x] = t468;
                uint8_t t469 = MEDIAN_MAX(buf[5120 + x], buf[5126 + x]);
                uint8_t t470 = MEDIAN_MIN(buf[5440 + x], buf[5446 + x]);
                uint8_t t471 = MEDIAN_MAX(buf[5440 + x], buf[5446 + x]);
                buf[11200 + x] = t471;
                uint8_t t472 = MEDIAN_MIN(t470, t469);
                buf[11520 + x] = t472;
                uint8_t t473 = MEDIAN_MAX(t470, t469);
                buf[11840 + x] = t473;
            }
            for (index_t x = 0; x < 288; x++) {
                uint8_t t66 = MEDIAN_MIN(buf[2560 + x], buf[1923 + x]);
                buf[5440 + x] = t66;
                uint8_t t67 = MEDIAN_MAX(buf[2560 + x], buf[1923 + x]);
                uint8_t t68 = MEDIAN_MIN(buf[6723 + x], t67);
                uint8_t t69 = MEDIAN_MAX(buf[6723 + x], t67);
                uint8_t t70 = MEDIAN_MIN(buf[4160 + x], buf[323 + x]);
                uint8_t t71 = MEDIAN_MAX(buf[4160 + x], buf[323 + x]);
                uint8_t t72 = MEDIAN_MIN(t70, t68);
                uint8_t t73 = MEDIAN_MAX(t70, t68);
                uint8_t t74 = MEDIAN_MIN(t71, t69);
                uint8_t t75 = MEDIAN_MAX(t71, t69);
                uint8_t t76 = MEDIAN_MIN(buf[3520 + x], buf[963 + x]);
                uint8_t t77 = MEDIAN_MAX(buf[3520 + x], buf[963 + x]);
                uint8_t t78 = MEDIAN_MIN(buf[7363 + x], t77);
                uint8_t t79 = MEDIAN_MAX(buf[7363 + x], t77);
                uint8_t t80 = MEDIAN_MIN(buf[6083 + x], t78);
                uint8_t t81 = MEDIAN_MAX(buf[6083 + x], t78);
                uint8_t t82 = MEDIAN_MIN(t76, t72);
                uint8_t t83 = MEDIAN_MAX(t76, t72);
                uint8_t t84 = MEDIAN_MIN(t80, t73);
                uint8_t t85 = MEDIAN_MAX(t80, t73);
                uint8_t t86 = MEDIAN_MIN(t81, t74);
                uint8_t t87 = MEDIAN_MAX(t81, t74);
                uint8_t t88 = MEDIAN_MIN(t79, t75);
                uint8_t t89 = MEDIAN_MAX(t79, t75);
                uint8_t t90 = MEDIAN_MIN(buf[3200 + x], buf[1283 + x]);
                uint8_t t91 = MEDIAN_MAX(buf[3200 + x], buf[1283 + x]);
                uint8_t t92 = MEDIAN_MIN(buf[7043 + x], t91);
                uint8_t t93 = MEDIAN_MAX(buf[7043 + x], t91);
                uint8_t t94 = MEDIAN_MIN(buf[2880 + x], buf[5763 + x]);
                uint8_t t95 = MEDIAN_MAX(buf[2880 + x], buf[5763 + x]);
                uint8_t t96 = MEDIAN_MIN(t94, t92);
                uint8_t t97 = MEDIAN_MAX(t94, t92);
                uint8_t t98 = MEDIAN_MIN(t95, t93);
                uint8_t t99 = MEDIAN_MAX(t95, t93);
                uint8_t t100 = MEDIAN_MIN(buf[3840 + x], buf[643 + x]);
                uint8_t t101 = MEDIAN_MAX(buf[3840 + x], buf[643 + x]);
                uint8_t t102 = MEDIAN_MIN(buf[1603 + x], t101);
                uint8_t t103 = MEDIAN_MAX(buf[1603 + x], t101);
                uint8_t t104 = MEDIAN_MIN(buf[6403 + x], t102);
                uint8_t t105 = MEDIAN_MAX(buf[6403 + x], t102);
                uint8_t t106 = MEDIAN_MIN(t100, t96);
                uint8_t t107 = MEDIAN_MAX(t100, t96);
                uint8_t t108 = MEDIAN_MIN(t104, t97);
                uint8_t t109 = MEDIAN_MAX(t104, t97);
                uint8_t t110 = MEDIAN_MIN(t105, t98);
                uint8_t t111 = MEDIAN_MAX(t105, t98);
                uint8_t t112 = MEDIAN_MIN(t103, t99);
                uint8_t t113 = MEDIAN_MAX(t103, t99);
                buf[5120 + x] = t113;
                uint8_t t114 = MEDIAN_MIN(t90, t82);
                buf[4800 + x] = t114;
                uint8_t t115 = MEDIAN_MAX(t90, t82);
                buf[4480 + x] = t115;
                uint8_t t116 = MEDIAN_MIN(t106, t83);
                buf[2240 + x] = t116;
                uint8_t t117 = MEDIAN_MAX(t106, t83);
                buf[0 + x] = t117;
                uint8_t t118 = MEDIAN_MIN(t107, t84);
                buf[12160 + x] = t118;
                uint8_t t119 = MEDIAN_MAX(t107, t84);
                buf[12480 + x] = t119;
                uint8_t t120 = MEDIAN_MIN(t108, t85);
                buf[12800 + x] = t120;
                uint8_t t121 = MEDIAN_MAX(t108, t85);
                buf[13120 + x] = t121;
                uint8_t t122 = MEDIAN_MIN(t109, t86);
                buf[13440 + x] = t122;
                uint8_t t123 = MEDIAN_MAX(t109, t86);
                buf[13760 + x] = t123;
                uint8_t t124 = MEDIAN_MIN(t110, t87);
                buf[14080 + x] = t124;
                uint8_t t125 = MEDIAN_MAX(t110, t87);
                buf[14400 + x] = t125;
                uint8_t t126 = MEDIAN_MIN(t111, t88);
                buf[14720 + x] = t126;
                uint8_t t127 = MEDIAN_MAX(t111, t88);
                buf[15040 + x] = t127;
                uint8_t t128 = MEDIAN_MIN(t112, t89);
                buf[15360 + x] = t128;
                uint8_t t129 = MEDIAN_MAX(t112, t89);
                buf[15680 + x] = t129;
                uint8_t t130 = MEDIAN_MIN(buf[1920 + x], buf[1926 + x]);
                buf[16000 + x] = t130;
                uint8_t t131 = MEDIAN_MAX(buf[1920 + x], buf[1926 + x]);
                uint8_t t132 = MEDIAN_MIN(buf[6720 + x], buf[6726 + x]);
                uint8_t t133 = MEDIAN_MAX(buf[6720 + x], buf[6726 + x]);
                uint8_t t134 = MEDIAN_MIN(t132, t131);
                uint8_t t135 = MEDIAN_MAX(t132, t131);
                uint8_t t136 = MEDIAN_MIN(buf[320 + x], buf[326 + x]);
                uint8_t t137 = MEDIAN_MAX(buf[320 + x], buf[326 + x]);
                uint8_t t138 = MEDIAN_MIN(t136, t134);
                uint8_t t139 = MEDIAN_MAX(t136, t134);
                uint8_t t140 = MEDIAN_MIN(t137, t135);
                uint8_t t141 = MEDIAN_MAX(t137, t135);
                uint8_t t142 = MEDIAN_MIN(buf[960 + x], buf[966 + x]);
                uint8_t t143 = MEDIAN_MAX(buf[960 + x], buf[966 + x]);
                uint8_t t144 = MEDIAN_MIN(buf[7360 + x], buf[7366 + x]);
                uint8_t t145 = MEDIAN_MAX(buf[7360 + x], buf[7366 + x]);
                uint8_t t146 = MEDIAN_MIN(t144, t143);
                uint8_t t147 = MEDIAN_MAX(t144, t143);
                uint8_t t148 = MEDIAN_MIN(buf[6080 + x], buf[6086 + x]);
                uint8_t t149 = MEDIAN_MAX(buf[6080 + x], buf[6086 + x]);
                uint8_t t150 = MEDIAN_MIN(t148, t146);
                uint8_t t151 = MEDIAN_MAX(t148, t146);
                uint8_t t152 = MEDIAN_MIN(t149, t147);
                uint8_t t153 = MEDIAN_MAX(t149, t147);
                uint8_t t154 = MEDIAN_MIN(t142, t138);
                uint8_t t155 = MEDIAN_MAX(t142, t138);
                uint8_t t156 = MEDIAN_MIN(t150, t139);
                uint8_t t157 = MEDIAN_MAX(t150, t139);
                uint8_t t158 = MEDIAN_MIN(t151, t140);
                uint8_t t159 = MEDIAN_MAX(t151, t140);
                uint8_t t160 = MEDIAN_MIN(t152, t141);
                uint8_t t161 = MEDIAN_MAX(t152, t141);
                uint8_t t162 = MEDIAN_MIN(t153, t133);
                uint8_t t163 = MEDIAN_MAX(t153, t133);
                uint8_t t164 = MEDIAN_MIN(buf[1280 + x], buf[1286 + x]);
                uint8_t t165 = MEDIAN_MAX(buf[1280 + x], buf[1286 + x]);
                uint8_t t166 = MEDIAN_MIN(buf[7040 + x], buf[7046 + x]);
                uint8_t t167 = MEDIAN_MAX(buf[7040 + x], buf[7046 + x]);
                uint8_t t168 = MEDIAN_MIN(t166, t165);
                uint8_t t169 = MEDIAN_MAX(t166, t165);
                uint8_t t170 = MEDIAN_MIN(buf[5760 + x], buf[5766 + x]);
                uint8_t t171 = MEDIAN_MAX(buf[5760 + x], buf[5766 + x]);
                uint8_t t172 = MEDIAN_MIN(t170, t168);
                uint8_t t173 = MEDIAN_MAX(t170, t168);
                uint8_t t174 = MEDIAN_MIN(t171, t169);
                uint8_t t175 = MEDIAN_MAX(t171, t169);
                uint8_t t176 = MEDIAN_MIN(buf[640 + x], buf[646 + x]);
                uint8_t t177 = MEDIAN_MAX(buf[640 + x], buf[646 + x]);
                uint8_t t178 = MEDIAN_MIN(buf[1600 + x], buf[1606 + x]);
                uint8_t t179 = MEDIAN_MAX(buf[1600 + x], buf[1606 + x]);
                buf[16320 + x] = t179;
                uint8_t t180 = MEDIAN_MIN(t178, t177);
                uint8_t t181 = MEDIAN_MAX(t178, t177);
                uint8_t t182 = MEDIAN_MIN(buf[6400 + x], buf[6406 + x]);
                uint8_t t183 = MEDIAN_MAX(buf[6400 + x], buf[6406 + x]);
                uint8_t t184 = MEDIAN_MIN(t182, t180);
                uint8_t t185 = MEDIAN_MAX(t182, t180);
                uint8_t t186 = MEDIAN_MIN(t183, t181);
                uint8_t t187 = MEDIAN_MAX(t183, t181);
                uint8_t t188 = MEDIAN_MIN(t176, t172);
                uint8_t t189 = MEDIAN_MAX(t176, t172);
                uint8_t t190 = MEDIAN_MIN(t184, t173);
                uint8_t t191 = MEDIAN_MAX(t184, t173);
                uint8_t t192 = MEDIAN_MIN(t185, t174);
                uint8_t t193 = MEDIAN_MAX(t185, t174);
                uint8_t t194 = MEDIAN_MIN(t186, t175);
                uint8_t t195 = MEDIAN_MAX(t186, t175);
                uint8_t t196 = MEDIAN_MIN(t187, t167);
                uint8_t t197 = MEDIAN_MAX(t187, t167);
                uint8_t t198 = MEDIAN_MIN(t164, t154);
                buf[16640 + x] = t198;
                uint8_t t199 = MEDIAN_MAX(t164, t154);
                buf[16960 + x] = t199;
                uint8_t t200 = MEDIAN_MIN(t188, t155);
                buf[17280 + x] = t200;
                uint8_t t201 = MEDIAN_MAX(t188, t155);
                buf[17600 + x] = t201;
                uint8_t t202 = MEDIAN_MIN(t189, t156);
                buf[17920 + x] = t202;
                uint8_t t203 = MEDIAN_MAX(t189, t156);
                buf[18240 + x] = t203;
                uint8_t t204 = MEDIAN_MIN(t190, t157);
                buf[18560 + x] = t204;
                uint8_t t205 = MEDIAN_MAX(t190, t157);
                buf[18880 + x] = t205;
                uint8_t t206 = MEDIAN_MIN(t191, t158);
                buf[19200 + x] = t206;
                uint8_t t207 = MEDIAN_MAX(t191, t158);
                buf[19520 + x] = t207;
                uint8_t t208 = MEDIAN_MIN(t192, t159);
                buf[19840 + x] = t208;
                uint8_t t209 = MEDIAN_MAX(t192, t159);
                buf[20160 + x] = t209;
                uint8_t t210 = MEDIAN_MIN(t193, t160);
                buf[20480 + x] = t210;
                uint8_t t211 = MEDIAN_MAX(t193, t160);
                buf[20800 + x] = t211;
                uint8_t t212 = MEDIAN_MIN(t194, t161);
                buf[21120 + x] = t212;
                uint8_t t213 = MEDIAN_MAX(t194, t161);
                buf[21440 + x] = t213;
                uint8_t t214 = MEDIAN_MIN(t195, t162);
                buf[21760 + x] = t214;
                uint8_t t215 = MEDIAN_MAX(t195, t162);
                buf[22080 + x] = t215;
                uint8_t t216 = MEDIAN_MIN(t196, t163);
                buf[22400 + x] = t216;
                uint8_t t217 = MEDIAN_MAX(t196, t163);
                buf[22720 + x] = t217;
                uint8_t t218 = MEDIAN_MIN(t197, t145);
                buf[23040 + x] = t218;
                uint8_t t219 = MEDIAN_MAX(t197, t145);
                buf[23360 + x] = t219;
                uint8_t t432 = MEDIAN_MIN(buf[7680 + x], buf[8649 + x]);
                buf[23680 + x] = t432;
                uint8_t t433 = MEDIAN_MAX(buf[7680 + x], buf[8649 + x]);
                uint8_t t434 = MEDIAN_MIN(buf[8320 + x], buf[9609 + x]);
                uint8_t t435 = MEDIAN_MAX(buf[8320 + x], buf[9609 + x]);
                uint8_t t436 = MEDIAN_MIN(t434, t433);
                uint8_t t437 = MEDIAN_MAX(t434, t433);
                uint8_t t438 = MEDIAN_MIN(buf[8000 + x], buf[9289 + x]);
                uint8_t t439 = MEDIAN_MAX(buf[8000 + x], buf[9289 + x]);
                uint8_t t440 = MEDIAN_MIN(buf[8969 + x], t439);
                uint8_t t441 = MEDIAN_MAX(buf[8969 + x], t439);
                uint8_t t442 = MEDIAN_MIN(t438, t436);
                buf[24000 + x] = t442;
                uint8_t t443 = MEDIAN_MAX(t438, t436);
                buf[24320 + x] = t443;
                uint8_t t444 = MEDIAN_MIN(t440, t437);
                buf[24640 + x] = t444;
                uint8_t t445 = MEDIAN_MAX(t440, t437);
                buf[24960 + x] = t445;
                uint8_t t446 = MEDIAN_MIN(t441, t435);
                buf[25280 + x] = t446;
                uint8_t t447 = MEDIAN_MAX(t441, t435);
                buf[25600 + x] = t447;
                uint8_t t474 = MEDIAN_MIN(buf[9920 + x], buf[10889 + x]);
                buf[25920 + x] = t474;
                uint8_t t475 = MEDIAN_MAX(buf[9920 + x], buf[10889 + x]);
                uint8_t t476 = MEDIAN_MIN(buf[10560 + x], buf[11849 + x]);
                uint8_t t477 = MEDIAN_MAX(buf[10560 + x], buf[11849 + x]);
                uint8_t t478 = MEDIAN_MIN(t476, t475);
                uint8_t t479 = MEDIAN_MAX(t476, t475);
                uint8_t t480 = MEDIAN_MIN(buf[10240 + x], buf[11529 + x]);
                uint8_t t481 = MEDIAN_MAX(buf[10240 + x], buf[11529 + x]);
                uint8_t t482 = MEDIAN_MIN(buf[11209 + x], t481);
                uint8_t t483 = MEDIAN_MAX(buf[11209 + x], t481);
                uint8_t t484 = MEDIAN_MIN(t480, t478);
                buf[26240 + x] = t484;
                uint8_t t485 = MEDIAN_MAX(t480, t478);
                buf[26560 + x] = t485;
                uint8_t t486 = MEDIAN_MIN(t482, t479);
                buf[26880 + x] = t486;
                uint8_t t487 = MEDIAN_MAX(t482, t479);
                buf[27200 + x] = t487;
                uint8_t t488 = MEDIAN_MIN(t483, t477);
                buf[27520 + x] = t488;
                uint8_t t489 = MEDIAN_MAX(t483, t477);
                buf[27840 + x] = t489;
            }
            for (index_t x = 0; x < 256; x++) {
                uint8_t t221 = MEDIAN_MAX(buf[5440 + x], buf[16009 + x]);
                uint8_t t222 = MEDIAN_MIN(buf[15680 + x], buf[21449 + x]);
                uint8_t t225 = MEDIAN_MAX(t222, t221);
                uint8_t t227 = MEDIAN_MAX(buf[13120 + x], buf[18889 + x]);
                uint8_t t230 = MEDIAN_MIN(t227, t225);
                uint8_t t233 = MEDIAN_MAX(buf[0 + x], buf[17609 + x]);
                uint8_t t234 = MEDIAN_MIN(buf[22729 + x], t233);
                uint8_t t236 = MEDIAN_MIN(buf[14400 + x], buf[20169 + x]);
                uint8_t t239 = MEDIAN_MAX(t236, t234);
                uint8_t t246 = MEDIAN_MIN(t239, t230);
                uint8_t t247 = MEDIAN_MAX(t239, t230);
                uint8_t t253 = MEDIAN_MAX(buf[4480 + x], buf[16969 + x]);
                uint8_t t254 = MEDIAN_MIN(buf[22089 + x], t253);
                uint8_t t255 = MEDIAN_MAX(buf[22089 + x], t253);
                uint8_t t256 = MEDIAN_MIN(buf[13760 + x], buf[19529 + x]);
                uint8_t t257 = MEDIAN_MAX(buf[13760 + x], buf[19529 + x]);
                uint8_t t259 = MEDIAN_MAX(t256, t254);
                uint8_t t260 = MEDIAN_MIN(t257, t255);
                uint8_t t263 = MEDIAN_MAX(buf[12480 + x], buf[18249 + x]);
                uint8_t t264 = MEDIAN_MIN(buf[23369 + x], t263);
                uint8_t t266 = MEDIAN_MIN(buf[15040 + x], buf[20809 + x]);
                uint8_t t268 = MEDIAN_MIN(t266, t264);
                uint8_t t269 = MEDIAN_MAX(t266, t264);
                uint8_t t275 = MEDIAN_MAX(t268, t259);
                uint8_t t276 = MEDIAN_MIN(t269, t260);
                uint8_t t288 = MEDIAN_MIN(t275, t246);
                uint8_t t289 = MEDIAN_MAX(t275, t246);
                uint8_t t290 = MEDIAN_MIN(t276, t247);
                uint8_t t291 = MEDIAN_MAX(t276, t247);
                uint8_t t301 = MEDIAN_MAX(buf[4800 + x], buf[16649 + x]);
                uint8_t t302 = MEDIAN_MIN(buf[5120 + x], buf[21769 + x]);
                uint8_t t304 = MEDIAN_MIN(t302, t301);
                uint8_t t305 = MEDIAN_MAX(t302, t301);
                uint8_t t306 = MEDIAN_MIN(buf[13440 + x], buf[19209 + x]);
                uint8_t t307 = MEDIAN_MAX(buf[13440 + x], buf[19209 + x]);
                uint8_t t309 = MEDIAN_MAX(t306, t304);
                uint8_t t310 = MEDIAN_MIN(t307, t305);
                uint8_t t313 = MEDIAN_MAX(buf[12160 + x], buf[17929 + x]);
                uint8_t t314 = MEDIAN_MIN(buf[23049 + x], t313);
                uint8_t t316 = MEDIAN_MIN(buf[14720 + x], buf[20489 + x]);
                uint8_t t318 = MEDIAN_MIN(t316, t314);
                uint8_t t319 = MEDIAN_MAX(t316, t314);
                uint8_t t325 = MEDIAN_MAX(t318, t309);
                uint8_t t326 = MEDIAN_MIN(t319, t310);
                uint8_t t327 = MEDIAN_MAX(t319, t310);
                uint8_t t333 = MEDIAN_MAX(buf[2240 + x], buf[17289 + x]);
                uint8_t t334 = MEDIAN_MIN(buf[22409 + x], t333);
                uint8_t t335 = MEDIAN_MAX(buf[22409 + x], t333);
                uint8_t t336 = MEDIAN_MIN(buf[14080 + x], buf[19849 + x]);
                uint8_t t337 = MEDIAN_MAX(buf[14080 + x], buf[19849 + x]);
                uint8_t t339 = MEDIAN_MAX(t336, t334);
                uint8_t t340 = MEDIAN_MIN(t337, t335);
                uint8_t t343 = MEDIAN_MAX(buf[12800 + x], buf[18569 + x]);
                uint8_t t344 = MEDIAN_MIN(buf[16329 + x], t343);
                uint8_t t346 = MEDIAN_MIN(buf[15360 + x], buf[21129 + x]);
                uint8_t t348 = MEDIAN_MIN(t346, t344);
                uint8_t t349 = MEDIAN_MAX(t346, t344);
                uint8_t t354 = MEDIAN_MIN(t348, t339);
                uint8_t t355 = MEDIAN_MAX(t348, t339);
                uint8_t t356 = MEDIAN_MIN(t349, t340);
                uint8_t t367 = MEDIAN_MAX(t354, t325);
                uint8_t t368 = MEDIAN_MIN(t355, t326);
                uint8_t t369 = MEDIAN_MAX(t355, t326);
                uint8_t t370 = MEDIAN_MIN(t356, t327);
                uint8_t t396 = MEDIAN_MIN(t367, t288);
                uint8_t t397 = MEDIAN_MAX(t367, t288);
                uint8_t t398 = MEDIAN_MIN(t368, t289);
                uint8_t t399 = MEDIAN_MAX(t368, t289);
                uint8_t t400 = MEDIAN_MIN(t369, t290);
                uint8_t t401 = MEDIAN_MAX(t369, t290);
                uint8_t t402 = MEDIAN_MIN(t370, t291);
                uint8_t t403 = MEDIAN_MAX(t370, t291);
                uint8_t t448 = MEDIAN_MAX(t396, buf[25600 + x]);
                uint8_t t449 = MEDIAN_MAX(t397, buf[25280 + x]);
                uint8_t t450 = MEDIAN_MAX(t398, buf[24960 + x]);
                uint8_t t451 = MEDIAN_MAX(t399, buf[24640 + x]);
                uint8_t t452 = MEDIAN_MAX(t400, buf[24320 + x]);
                uint8_t t453 = MEDIAN_MAX(t401, buf[24000 + x]);
                uint8_t t454 = MEDIAN_MAX(t402, buf[23680 + x]);
                uint8_t t455 = MEDIAN_MIN(t448, t449);
                uint8_t t456 = MEDIAN_MIN(t455, t450);
                uint8_t t457 = MEDIAN_MIN(t456, t451);
                uint8_t t458 = MEDIAN_MIN(t457, t452);
                uint8_t t459 = MEDIAN_MIN(t458, t453);
                uint8_t t460 = MEDIAN_MIN(t459, t454);
                uint8_t t461 = MEDIAN_MIN(t460, t403);
                buf[11840 + x] = t461;
                uint8_t t490 = MEDIAN_MAX(t396, buf[27840 + x]);
                uint8_t t491 = MEDIAN_MAX(t397, buf[27520 + x]);
                uint8_t t492 = MEDIAN_MAX(t398, buf[27200 + x]);
                uint8_t t493 = MEDIAN_MAX(t399, buf[26880 + x]);
                uint8_t t494 = MEDIAN_MAX(t400, buf[26560 + x]);
                uint8_t t495 = MEDIAN_MAX(t401, buf[26240 + x]);
                uint8_t t496 = MEDIAN_MAX(t402, buf[25920 + x]);
                uint8_t t497 = MEDIAN_MIN(t490, t491);
                uint8_t t498 = MEDIAN_MIN(t497, t492);
                uint8_t t499 = MEDIAN_MIN(t498, t493);
                uint8_t t500 = MEDIAN_MIN(t499, t494);
                uint8_t t501 = MEDIAN_MIN(t500, t495);
                uint8_t t502 = MEDIAN_MIN(t501, t496);
                uint8_t t503 = MEDIAN_MIN(t502, t403);
                buf[11520 + x] = t503;
            }
            memcpy(oflat + y * lanes + c0, buf + 11840, (size_t)m * sizeof(uint8_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 11520, (size_t)m * sizeof(uint8_t));
        }
    }
}

static void median7_c3_uint16(const uint16_t *restrict flat, uint16_t *restrict oflat, index_t rows, index_t lanes,
                              index_t y0, index_t y1, uint16_t *restrict buf)
{
    for (index_t y = y0; y < y1; y += 2) {
        for (index_t c0 = 0; c0 < lanes; c0 += 256) {
            index_t m = min_i(256, lanes - c0), n_in = m + 18;
            index_t lo = max_i(0, 9 - c0), hi = min_i(n_in, 9 + lanes - c0);
            for (index_t r = 0; r < 8; r++) {
                const uint16_t *src = flat + min_i(max_i(y + r - 3, 0), rows - 1) * lanes;
                uint16_t *o = buf + r * 320;
                if (hi > lo) memcpy(o + lo, src + c0 + lo - 9, (size_t)(hi - lo) * sizeof(uint16_t));
                for (index_t j = 0; j < lo; j++) o[j] = src[(c0 + j) % 3];
                for (index_t j = hi; j < n_in; j++) o[j] = src[lanes - 3 + (c0 + j) % 3];
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t8 = MEDIAN_MIN(buf[640 + x], buf[960 + x]);
                uint16_t t9 = MEDIAN_MAX(buf[640 + x], buf[960 + x]);
                uint16_t t10 = MEDIAN_MIN(buf[320 + x], t8);
                uint16_t t11 = MEDIAN_MAX(buf[320 + x], t8);
                uint16_t t12 = MEDIAN_MIN(t9, t11);
                uint16_t t13 = MEDIAN_MAX(t9, t11);
                uint16_t t14 = MEDIAN_MIN(buf[1600 + x], buf[1920 + x]);
                uint16_t t15 = MEDIAN_MAX(buf[1600 + x], buf[1920 + x]);
                uint16_t t16 = MEDIAN_MIN(buf[1280 + x], t14);
                uint16_t t17 = MEDIAN_MAX(buf[1280 + x], t14);
                uint16_t t18 = MEDIAN_MIN(t15, t17);
                uint16_t t19 = MEDIAN_MAX(t15, t17);
                uint16_t t20 = MEDIAN_MIN(t10, t16);
                buf[2560 + x] = t20;
                uint16_t t21 = MEDIAN_MAX(t10, t16);
                uint16_t t22 = MEDIAN_MIN(t13, t19);
                uint16_t t23 = MEDIAN_MAX(t13, t19);
                buf[2880 + x] = t23;
                uint16_t t24 = MEDIAN_MIN(t22, t21);
                uint16_t t25 = MEDIAN_MAX(t22, t21);
                uint16_t t26 = MEDIAN_MIN(t12, t18);
                uint16_t t27 = MEDIAN_MAX(t12, t18);
                uint16_t t28 = MEDIAN_MIN(t26, t24);
                buf[3200 + x] = t28;
                uint16_t t29 = MEDIAN_MAX(t26, t24);
                buf[3520 + x] = t29;
                uint16_t t30 = MEDIAN_MIN(t27, t25);
                buf[3840 + x] = t30;
                uint16_t t31 = MEDIAN_MAX(t27, t25);
                buf[4160 + x] = t31;
                uint16_t t420 = MEDIAN_MIN(buf[0 + x], buf[3 + x]);
                buf[4480 + x] = t420;
                uint16_t t421 = MEDIAN_MAX(buf[0 + x], buf[3 + x]);
                buf[4800 + x] = t421;
                uint16_t t462 = MEDIAN_MIN(buf[2240 + x], buf[2243 + x]);
                buf[5120 + x] = t462;
                uint16_t t463 = MEDIAN_MAX(buf[2240 + x], buf[2243 + x]);
                buf[5440 + x] = t463;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t32 = MEDIAN_MIN(buf[2560 + x], buf[2563 + x]);
                buf[1920 + x] = t32;
                uint16_t t33 = MEDIAN_MAX(buf[2560 + x], buf[2563 + x]);
                uint16_t t34 = MEDIAN_MIN(buf[4160 + x], buf[4163 + x]);
                uint16_t t35 = MEDIAN_MAX(buf[4160 + x], buf[4163 + x]);
                uint16_t t36 = MEDIAN_MIN(t34, t33);
                uint16_t t37 = MEDIAN_MAX(t34, t33);
                uint16_t t38 = MEDIAN_MIN(buf[3520 + x], buf[3523 + x]);
                uint16_t t39 = MEDIAN_MAX(buf[3520 + x], buf[3523 + x]);
                uint16_t t40 = MEDIAN_MIN(t38, t36);
                uint16_t t41 = MEDIAN_MAX(t38, t36);
                uint16_t t42 = MEDIAN_MIN(t39, t37);
                uint16_t t43 = MEDIAN_MAX(t39, t37);
                uint16_t t44 = MEDIAN_MIN(buf[3200 + x], buf[3203 + x]);
                uint16_t t45 = MEDIAN_MAX(buf[3200 + x], buf[3203 + x]);
                uint16_t t46 = MEDIAN_MIN(buf[2880 + x], buf[2883 + x]);
                uint16_t t47 = MEDIAN_MAX(buf[2880 + x], buf[2883 + x]);
                buf[1600 + x] = t47;
                uint16_t t48 = MEDIAN_MIN(t46, t45);
                uint16_t t49 = MEDIAN_MAX(t46, t45);
                uint16_t t50 = MEDIAN_MIN(buf[3840 + x], buf[3843 + x]);
                uint16_t t51 = MEDIAN_MAX(buf[3840 + x], buf[3843 + x]);
                uint16_t t52 = MEDIAN_MIN(t50, t48);
                uint16_t t53 = MEDIAN_MAX(t50, t48);
                uint16_t t54 = MEDIAN_MIN(t51, t49);
                uint16_t t55 = MEDIAN_MAX(t51, t49);
                uint16_t t56 = MEDIAN_MIN(t44, t40);
                buf[1280 + x] = t56;
                uint16_t t57 = MEDIAN_MAX(t44, t40);
                buf[960 + x] = t57;
                uint16_t t58 = MEDIAN_MIN(t52, t41);
                buf[640 + x] = t58;
                uint16_t t59 = MEDIAN_MAX(t52, t41);
                buf[320 + x] = t59;
                uint16_t t60 = MEDIAN_MIN(t53, t42);
                buf[5760 + x] = t60;
                uint16_t t61 = MEDIAN_MAX(t53, t42);
                buf[6080 + x] = t61;
                uint16_t t62 = MEDIAN_MIN(t54, t43);
                buf[6400 + x] = t62;
                uint16_t t63 = MEDIAN_MAX(t54, t43);
                buf[6720 + x] = t63;
                uint16_t t64 = MEDIAN_MIN(t55, t35);
                buf[7040 + x] = t64;
                uint16_t t65 = MEDIAN_MAX(t55, t35);
                buf[7360 + x] = t65;
                uint16_t t422 = MEDIAN_MIN(buf[0 + x], buf[4483 + x]);
                buf[7680 + x] = t422;
                uint16_t t423 = MEDIAN_MAX(buf[0 + x], buf[4483 + x]);
                uint16_t t424 = MEDIAN_MIN(buf[4803 + x], t423);
                buf[8000 + x] = t424;
                uint16_t t425 = MEDIAN_MAX(buf[4803 + x], t423);
                buf[8320 + x] = t425;
                uint16_t t426 = MEDIAN_MIN(buf[4480 + x], buf[4486 + x]);
                buf[8640 + x] = t426;
                uint16_t t427 = MEDIAN_MAX(buf[4480 + x], buf[4486 + x]);
                uint16_t t428 = MEDIAN_MIN(buf[4800 + x], buf[4806 + x]);
                uint16_t t429 = MEDIAN_MAX(buf[4800 + x], buf[4806 + x]);
                buf[8960 + x] = t429;
                uint16_t t430 = MEDIAN_MIN(t428, t427);
                buf[9280 + x] = t430;
                uint16_t t431 = MEDIAN_MAX(t428, t427);
                buf[9600 + x] = t431;
                uint16_t t464 = MEDIAN_MIN(buf[2240 + x], buf[5123 + x]);
                buf[9920 + x] = t464;
                uint16_t t465 = MEDIAN_MAX(buf[2240 + x], buf[5123 + x]);
                uint16_t t466 = MEDIAN_MIN(buf[5443 + x], t465);
                buf[10240 + x] = t466;
                uint16_t t467 = MEDIAN_MAX(buf[5443 + x], t465);
                buf[10560 + x] = t467;
                uint16_t t468 = MEDIAN_MIN(buf[5120 + x], buf[5126 + x]);
                buf[10880 + x] = t468;
                uint16_t t469 = MEDIAN_MAX(buf[5120 + x], buf[5126 + x]);
                uint16_t t470 = MEDIAN_MIN(buf[5440 + x], buf[5446 + x]);
                uint16_t t471 = MEDIAN_MAX(buf[5440 + x], buf[5446 + x]);
                buf[11200 + x] = t471;
                uint16_t t472 = MEDIAN_MIN(t470, t469);
                buf[11520 + x] = t472;
                uint16_t t473 = MEDIAN_MAX(t470, t469);
                buf[11840 + x] = t473;
            }
            for (index_t x = 0; x < 288; x++) {
                uint16_t t66 = MEDIAN_MIN(buf[2560 + x], buf[1923 + x]);
                buf[5440 + x] = t66;
                uint16_t t67 = MEDIAN_MAX(buf[2560 + x], buf[1923 + x]);
                uint16_t t68 = MEDIAN_MIN(buf[6723 + x], t67);
                uint16_t t69 = MEDIAN_MAX(buf[6723 + x], t67);
                uint16_t t70 = MEDIAN_MIN(buf[4160 + x], buf[323 + x]);
                uint16_t t71 = MEDIAN_MAX(buf[4160 + x], buf[323 + x]);
                uint16_t t72 = MEDIAN_MIN(t70, t68);
                uint16_t t73 = MEDIAN_MAX(t70, t68);
                uint16_t t74 = MEDIAN_MIN(t71, t69);
                uint16_t t75 = MEDIAN_MAX(t71, t69);
                uint16_t t76 = MEDIAN_MIN(buf[3520 + x], buf[963 + x]);
                uint16_t t77 = MEDIAN_MAX(buf[3520 + x], buf[963 + x]);
                uint16_t t78 = MEDIAN_MIN(buf[7363 + x], t77);
                uint16_t t79 = MEDIAN_MAX(buf[7363 + x], t77);
                uint16_t t80 = MEDIAN_MIN(buf[6083 + x], t78);
                uint16_t t81 = MEDIAN_MAX(buf[6083 + x], t78);
                uint16_t t82 = MEDIAN_MIN(t76, t72);
                uint16_t t83 = MEDIAN_MAX(t76, t72);
                uint16_t t84 = MEDIAN_MIN(t80, t73);
                uint16_t t85 = MEDIAN_MAX(t80, t73);
                uint16_t t86 = MEDIAN_MIN(t81, t74);
                uint16_t t87 = MEDIAN_MAX(t81, t74);
                uint16_t t88 = MEDIAN_MIN(t79, t75);
                uint16_t t89 = MEDIAN_MAX(t79, t75);
                uint16_t t90 = MEDIAN_MIN(buf[3200 + x], buf[1283 + x]);
                uint16_t t91 = MEDIAN_MAX(buf[3200 + x], buf[1283 + x]);
                uint16_t t92 = MEDIAN_MIN(buf[7043 + x], t91);
                uint16_t t93 = MEDIAN_MAX(buf[7043 + x], t91);
                uint16_t t94 = MEDIAN_MIN(buf[2880 + x], buf[5763 + x]);
                uint16_t t95 = MEDIAN_MAX(buf[2880 + x], buf[5763 + x]);
                uint16_t t96 = MEDIAN_MIN(t94, t92);
                uint16_t t97 = MEDIAN_MAX(t94, t92);
                uint16_t t98 = MEDIAN_MIN(t95, t93);
                uint16_t t99 = MEDIAN_MAX(t95, t93);
                uint16_t t100 = MEDIAN_MIN(buf[3840 + x], buf[643 + x]);
                uint16_t t101 = MEDIAN_MAX(buf[3840 + x], buf[643 + x]);
                uint16_t t102 = MEDIAN_MIN(buf[1603 + x], t101);
                uint16_t t103 = MEDIAN_MAX(buf[1603 + x], t101);
                uint16_t t104 = MEDIAN_MIN(buf[6403 + x], t102);
                uint16_t t105 = MEDIAN_MAX(buf[6403 + x], t102);
                uint16_t t106 = MEDIAN_MIN(t100, t96);
                uint16_t t107 = MEDIAN_MAX(t100, t96);
                uint16_t t108 = MEDIAN_MIN(t104, t97);
                uint16_t t109 = MEDIAN_MAX(t104, t97);
                uint16_t t110 = MEDIAN_MIN(t105, t98);
                uint16_t t111 = MEDIAN_MAX(t105, t98);
                uint16_t t112 = MEDIAN_MIN(t103, t99);
                uint16_t t113 = MEDIAN_MAX(t103, t99);
                buf[5120 + x] = t113;
                uint16_t t114 = MEDIAN_MIN(t90, t82);
                buf[4800 + x] = t114;
                uint16_t t115 = MEDIAN_MAX(t90, t82);
                buf[4480 + x] = t115;
                uint16_t t116 = MEDIAN_MIN(t106, t83);
                buf[2240 + x] = t116;
                uint16_t t117 = MEDIAN_MAX(t106, t83);
                buf[0 + x] = t117;
                uint16_t t118 = MEDIAN_MIN(t107, t84);
                buf[12160 + x] = t118;
                uint16_t t119 = MEDIAN_MAX(t107, t84);
                buf[12480 + x] = t119;
                uint16_t t120 = MEDIAN_MIN(t108, t85);
                buf[12800 + x] = t120;
                uint16_t t121 = MEDIAN_MAX(t108, t85);
                buf[13120 + x] = t121;
                uint16_t t122 = MEDIAN_MIN(t109, t86);
                buf[13440 + x] = t122;
                uint16_t t123 = MEDIAN_MAX(t109, t86);
                buf[13760 + x] = t123;
                uint16_t t124 = MEDIAN_MIN(t110, t87);
                buf[14080 + x] = t124;
                uint16_t t125 = MEDIAN_MAX(t110, t87);
                buf[14400 + x] = t125;
                uint16_t t126 = MEDIAN_MIN(t111, t88);
                buf[14720 + x] = t126;
                uint16_t t127 = MEDIAN_MAX(t111, t88);
                buf[15040 + x] = t127;
                uint16_t t128 = MEDIAN_MIN(t112, t89);
                buf[15360 + x] = t128;
                uint16_t t129 = MEDIAN_MAX(t112, t89);
                buf[15680 + x] = t129;
                uint16_t t130 = MEDIAN_MIN(buf[1920 + x], buf[1926 + x]);
                buf[16000 + x] = t130;
                uint16_t t131 = MEDIAN_MAX(buf[1920 + x], buf[1926 + x]);
                uint16_t t132 = MEDIAN_MIN(buf[6720 + x], buf[6726 + x]);
                uint16_t t133 = MEDIAN_MAX(buf[6720 + x], buf[6726 + x]);
                uint16_t t134 = MEDIAN_MIN(t132, t131);
                uint16_t t135 = MEDIAN_MAX(t132, t131);
                uint16_t t136 = MEDIAN_MIN(buf[320 + x], buf[326 + x]);
                uint16_t t137 = MEDIAN_MAX(buf[320 + x], buf[326 + x]);
                uint16_t t138 = MEDIAN_MIN(t136, t134);
                uint16_t t139 = MEDIAN_MAX(t136, t134);
                uint16_t t140 = MEDIAN_MIN(t137, t135);
                uint16_t t141 = MEDIAN_MAX(t137, t135);
                uint16_t t142 = MEDIAN_MIN(buf[960 + x], buf[966 + x]);
                uint16_t t143 = MEDIAN_MAX(buf[960 + x], buf[966 + x]);
                uint16_t t144 = MEDIAN_MIN(buf[7360 + x], buf[7366 + x]);
                uint16_t t145 = MEDIAN_MAX(buf[7360 + x], buf[7366 + x]);
                uint16_t t146 = MEDIAN_MIN(t144, t143);
                uint16_t t147 = MEDIAN_MAX(t144, t143);
                uint16_t t148 = MEDIAN_MIN(buf[6080 + x], buf[6086 + x]);
                uint16_t t149 = MEDIAN_MAX(buf[6080 + x], buf[6086 + x]);
                uint16_t t150 = MEDIAN_MIN(t148, t146);
                uint16_t t151 = MEDIAN_MAX(t148, t146);
                uint16_t t152 = MEDIAN_MIN(t149, t147);
                uint16_t t153 = MEDIAN_MAX(t149, t147);
                uint16_t t154 = MEDIAN_MIN(t142, t138);
                uint16_t t155 = MEDIAN_MAX(t142, t138);
                uint16_t t156 = MEDIAN_MIN(t150, t139);
                uint16_t t157 = MEDIAN_MAX(t150, t139);
                uint16_t t158 = MEDIAN_MIN(t151, t140);
                uint16_t t159 = MEDIAN_MAX(t151, t140);
                uint16_t t160 = MEDIAN_MIN(t152, t141);
                uint16_t t161 = MEDIAN_MAX(t152, t141);
                uint16_t t162 = MEDIAN_MIN(t153, t133);
                uint16_t t163 = MEDIAN_MAX(t153, t133);
                uint16_t t164 = MEDIAN_MIN(buf[1280 + x], buf[1286 + x]);
                uint16_t t165 = MEDIAN_MAX(buf[1280 + x], buf[1286 + x]);
                uint16_t t166 = MEDIAN_MIN(buf[7040 + x], buf[7046 + x]);
                uint16_t t167 = MEDIAN_MAX(buf[7040 + x], buf[7046 + x]);
                uint16_t t168 = MEDIAN_MIN(t166, t165);
                uint16_t t169 = MEDIAN_MAX(t166, t165);
                uint16_t t170 = MEDIAN_MIN(buf[5760 + x], buf[5766 + x]);
                uint16_t t171 = MEDIAN_MAX(buf[5760 + x], buf[5766 + x]);
                uint16_t t172 = MEDIAN_MIN(t170, t168);
                uint16_t t173 = MEDIAN_MAX(t170, t168);
                uint16_t t174 = MEDIAN_MIN(t171, t169);
                uint16_t t175 = MEDIAN_MAX(t171, t169);
                uint16_t t176 = MEDIAN_MIN(buf[640 + x], buf[646 + x]);
                uint16_t t177 = MEDIAN_MAX(buf[640 + x], buf[646 + x]);
                uint16_t t178 = MEDIAN_MIN(buf[1600 + x], buf[1606 + x]);
                uint16_t t179 = MEDIAN_MAX(buf[1600 + x], buf[1606 + x]);
                buf[16320 + x] = t179;
                uint16_t t180 = MEDIAN_MIN(t178, t177);
                uint16_t t181 = MEDIAN_MAX(t178, t177);
                uint16_t t182 = MEDIAN_MIN(buf[6400 + x], buf[6406 + x]);
                uint16_t t183 = MEDIAN_MAX(buf[6400 + x], buf[6406 + x]);
                uint16_t t184 = MEDIAN_MIN(t182, t180);
                uint16_t t185 = MEDIAN_MAX(t182, t180);
                uint16_t t186 = MEDIAN_MIN(t183, t181);
                uint16_t t187 = MEDIAN_MAX(t183, t181);
                uint16_t t188 = MEDIAN_MIN(t176, t172);
                uint16_t t189 = MEDIAN_MAX(t176, t172);
                uint16_t t190 = MEDIAN_MIN(t184, t173);
                uint16_t t191 = MEDIAN_MAX(t184, t173);
                uint16_t t192 = MEDIAN_MIN(t185, t174);
                uint16_t t193 = MEDIAN_MAX(t185, t174);
                uint16_t t194 = MEDIAN_MIN(t186, t175);
                uint16_t t195 = MEDIAN_MAX(t186, t175);
                uint16_t t196 = MEDIAN_MIN(t187, t167);
                uint16_t t197 = MEDIAN_MAX(t187, t167);
                uint16_t t198 = MEDIAN_MIN(t164, t154);
                buf[16640 + x] = t198;
                uint16_t t199 = MEDIAN_MAX(t164, t154);
                buf[16960 + x] = t199;
                uint16_t t200 = MEDIAN_MIN(t188, t155);
                buf[17280 + x] = t200;
                uint16_t t201 = MEDIAN_MAX(t188, t155);
                buf[17600 + x] = t201;
                uint16_t t202 = MEDIAN_MIN(t189, t156);
                buf[17920 + x] = t202;
                uint16_t t203 = MEDIAN_MAX(t189, t156);
                buf[18240 + x] = t203;
                uint16_t t204 = MEDIAN_MIN(t190, t157);
                buf[18560 + x] = t204;
                uint16_t t205 = MEDIAN_MAX(t190, t157);
                buf[18880 + x] = t205;
                uint16_t t206 = MEDIAN_MIN(t191, t158);
                buf[19200 + x] = t206;
                uint16_t t207 = MEDIAN_MAX(t191, t158);
                buf[19520 + x] = t207;
                uint16_t t208 = MEDIAN_MIN(t192, t159);
                buf[19840 + x] = t208;
                uint16_t t209 = MEDIAN_MAX(t192, t159);
                buf[20160 + x] = t209;
                uint16_t t210 = MEDIAN_MIN(t193, t160);
                buf[20480 + x] = t210;
                uint16_t t211 = MEDIAN_MAX(t193, t160);
                buf[20800 + x] = t211;
                uint16_t t212 = MEDIAN_MIN(t194, t161);
                buf[21120 + x] = t212;
                uint16_t t213 = MEDIAN_MAX(t194, t161);
                buf[21440 + x] = t213;
                uint16_t t214 = MEDIAN_MIN(t195, t162);
                buf[21760 + x] = t214;
                uint16_t t215 = MEDIAN_MAX(t195, t162);
                buf[22080 + x] = t215;
                uint16_t t216 = MEDIAN_MIN(t196, t163);
                buf[22400 + x] = t216;
                uint16_t t217 = MEDIAN_MAX(t196, t163);
                buf[22720 + x] = t217;
                uint16_t t218 = MEDIAN_MIN(t197, t145);
                buf[23040 + x] = t218;
                uint16_t t219 = MEDIAN_MAX(t197, t145);
                buf[23360 + x] = t219;
                uint16_t t432 = MEDIAN_MIN(buf[7680 + x], buf[8649 + x]);
                buf[23680 + x] = t432;
                uint16_t t433 = MEDIAN_MAX(buf[7680 + x], buf[8649 + x]);
                uint16_t t434 = MEDIAN_MIN(buf[8320 + x], buf[9609 + x]);
                uint16_t t435 = MEDIAN_MAX(buf[8320 + x], buf[9609 + x]);
                uint16_t t436 = MEDIAN_MIN(t434, t433);
                uint16_t t437 = MEDIAN_MAX(t434, t433);
                uint16_t t438 = MEDIAN_MIN(buf[8000 + x], buf[9289 + x]);
                uint16_t t439 = MEDIAN_MAX(buf[8000 + x], buf[9289 + x]);
                uint16_t t440 = MEDIAN_MIN(buf[8969 + x], t439);
                uint16_t t441 = MEDIAN_MAX(buf[8969 + x], t439);
                uint16_t t442 = MEDIAN_MIN(t438, t436);
                buf[24000 + x] = t442;
                uint16_t t443 = MEDIAN_MAX(t438, t436);
                buf[24320 + x] = t443;
                uint16_t t444 = MEDIAN_MIN(t440, t437);
                buf[24640 + x] = t444;
                uint16_t t445 = MEDIAN_MAX(t440, t437);
                buf[24960 + x] = t445;
                uint16_t t446 = MEDIAN_MIN(t441, t435);
                buf[25280 + x] = t446;
                uint16_t t447 = MEDIAN_MAX(t441, t435);
                buf[25600 + x] = t447;
                uint16_t t474 = MEDIAN_MIN(buf[9920 + x], buf[10889 + x]);
                buf[25920 + x] = t474;
                uint16_t t475 = MEDIAN_MAX(buf[9920 + x], buf[10889 + x]);
                uint16_t t476 = MEDIAN_MIN(buf[10560 + x], buf[11849 + x]);
                uint16_t t477 = MEDIAN_MAX(buf[10560 + x], buf[11849 + x]);
                uint16_t t478 = MEDIAN_MIN(t476, t475);
                uint16_t t479 = MEDIAN_MAX(t476, t475);
                uint16_t t480 = MEDIAN_MIN(buf[10240 + x], buf[11529 + x]);
                uint16_t t481 = MEDIAN_MAX(buf[10240 + x], buf[11529 + x]);
                uint16_t t482 = MEDIAN_MIN(buf[11209 + x], t481);
                uint16_t t483 = MEDIAN_MAX(buf[11209 + x], t481);
                uint16_t t484 = MEDIAN_MIN(t480, t478);
                buf[26240 + x] = t484;
                uint16_t t485 = MEDIAN_MAX(t480, t478);
                buf[26560 + x] = t485;
                uint16_t t486 = MEDIAN_MIN(t482, t479);
                buf[26880 + x] = t486;
                uint16_t t487 = MEDIAN_MAX(t482, t479);
                buf[27200 + x] = t487;
                uint16_t t488 = MEDIAN_MIN(t483, t477);
                buf[27520 + x] = t488;
                uint16_t t489 = MEDIAN_MAX(t483, t477);
                buf[27840 + x] = t489;
            }
            for (index_t x = 0; x < 256; x++) {
                uint16_t t221 = MEDIAN_MAX(buf[5440 + x], buf[16009 + x]);
                uint16_t t222 = MEDIAN_MIN(buf[15680 + x], buf[21449 + x]);
                uint16_t t225 = MEDIAN_MAX(t222, t221);
                uint16_t t227 = MEDIAN_MAX(buf[13120 + x], buf[18889 + x]);
                uint16_t t230 = MEDIAN_MIN(t227, t225);
                uint16_t t233 = MEDIAN_MAX(buf[0 + x], buf[17609 + x]);
                uint16_t t234 = MEDIAN_MIN(buf[22729 + x], t233);
                uint16_t t236 = MEDIAN_MIN(buf[14400 + x], buf[20169 + x]);
                uint16_t t239 = MEDIAN_MAX(t236, t234);
                uint16_t t246 = MEDIAN_MIN(t239, t230);
                uint16_t t247 = MEDIAN_MAX(t239, t230);
                uint16_t t253 = MEDIAN_MAX(buf[4480 + x], buf[16969 + x]);
                uint16_t t254 = MEDIAN_MIN(buf[22089 + x], t253);
                uint16_t t255 = MEDIAN_MAX(buf[22089 + x], t253);
                uint16_t t256 = MEDIAN_MIN(buf[13760 + x], buf[19529 + x]);
                uint16_t t257 = MEDIAN_MAX(buf[13760 + x], buf[19529 + x]);
                uint16_t t259 = MEDIAN_MAX(t256, t254);
                uint16_t t260 = MEDIAN_MIN(t257, t255);
                uint16_t t263 = MEDIAN_MAX(buf[12480 + x], buf[18249 + x]);
                uint16_t t264 = MEDIAN_MIN(buf[23369 + x], t263);
                uint16_t t266 = MEDIAN_MIN(buf[15040 + x], buf[20809 + x]);
                uint16_t t268 = MEDIAN_MIN(t266, t264);
                uint16_t t269 = MEDIAN_MAX(t266, t264);
                uint16_t t275 = MEDIAN_MAX(t268, t259);
                uint16_t t276 = MEDIAN_MIN(t269, t260);
                uint16_t t288 = MEDIAN_MIN(t275, t246);
                uint16_t t289 = MEDIAN_MAX(t275, t246);
                uint16_t t290 = MEDIAN_MIN(t276, t247);
                uint16_t t291 = MEDIAN_MAX(t276, t247);
                uint16_t t301 = MEDIAN_MAX(buf[4800 + x], buf[16649 + x]);
                uint16_t t302 = MEDIAN_MIN(buf[5120 + x], buf[21769 + x]);
                uint16_t t304 = MEDIAN_MIN(t302, t301);
                uint16_t t305 = MEDIAN_MAX(t302, t301);
                uint16_t t306 = MEDIAN_MIN(buf[13440 + x], buf[19209 + x]);
                uint16_t t307 = MEDIAN_MAX(buf[13440 + x], buf[19209 + x]);
                uint16_t t309 = MEDIAN_MAX(t306, t304);
                uint16_t t310 = MEDIAN_MIN(t307, t305);
                uint16_t t313 = MEDIAN_MAX(buf[12160 + x], buf[17929 + x]);
                uint16_t t314 = MEDIAN_MIN(buf[23049 + x], t313);
                uint16_t t316 = MEDIAN_MIN(buf[14720 + x], buf[20489 + x]);
                uint16_t t318 = MEDIAN_MIN(t316, t314);
                uint16_t t319 = MEDIAN_MAX(t316, t314);
                uint16_t t325 = MEDIAN_MAX(t318, t309);
                uint16_t t326 = MEDIAN_MIN(t319, t310);
                uint16_t t327 = MEDIAN_MAX(t319, t310);
                uint16_t t333 = MEDIAN_MAX(buf[2240 + x], buf[17289 + x]);
                uint16_t t334 = MEDIAN_MIN(buf[22409 + x], t333);
                uint16_t t335 = MEDIAN_MAX(buf[22409 + x], t333);
                uint16_t t336 = MEDIAN_MIN(buf[14080 + x], buf[19849 + x]);
                uint16_t t337 = MEDIAN_MAX(buf[14080 + x], buf[19849 + x]);
                uint16_t t339 = MEDIAN_MAX(t336, t334);
                uint16_t t340 = MEDIAN_MIN(t337, t335);
                uint16_t t343 = MEDIAN_MAX(buf[12800 + x], buf[18569 + x]);
                uint16_t t344 = MEDIAN_MIN(buf[16329 + x], t343);
                uint16_t t346 = MEDIAN_MIN(buf[15360 + x], buf[21129 + x]);
                uint16_t t348 = MEDIAN_MIN(t346, t344);
                uint16_t t349 = MEDIAN_MAX(t346, t344);
                uint16_t t354 = MEDIAN_MIN(t348, t339);
                uint16_t t355 = MEDIAN_MAX(t348, t339);
                uint16_t t356 = MEDIAN_MIN(t349, t340);
                uint16_t t367 = MEDIAN_MAX(t354, t325);
                uint16_t t368 = MEDIAN_MIN(t355, t326);
                uint16_t t369 = MEDIAN_MAX(t355, t326);
                uint16_t t370 = MEDIAN_MIN(t356, t327);
                uint16_t t396 = MEDIAN_MIN(t367, t288);
                uint16_t t397 = MEDIAN_MAX(t367, t288);
                uint16_t t398 = MEDIAN_MIN(t368, t289);
                uint16_t t399 = MEDIAN_MAX(t368, t289);
                uint16_t t400 = MEDIAN_MIN(t369, t290);
                uint16_t t401 = MEDIAN_MAX(t369, t290);
                uint16_t t402 = MEDIAN_MIN(t370, t291);
                uint16_t t403 = MEDIAN_MAX(t370, t291);
                uint16_t t448 = MEDIAN_MAX(t396, buf[25600 + x]);
                uint16_t t449 = MEDIAN_MAX(t397, buf[25280 + x]);
                uint16_t t450 = MEDIAN_MAX(t398, buf[24960 + x]);
                uint16_t t451 = MEDIAN_MAX(t399, buf[24640 + x]);
                uint16_t t452 = MEDIAN_MAX(t400, buf[24320 + x]);
                uint16_t t453 = MEDIAN_MAX(t401, buf[24000 + x]);
                uint16_t t454 = MEDIAN_MAX(t402, buf[23680 + x]);
                uint16_t t455 = MEDIAN_MIN(t448, t449);
                uint16_t t456 = MEDIAN_MIN(t455, t450);
                uint16_t t457 = MEDIAN_MIN(t456, t451);
                uint16_t t458 = MEDIAN_MIN(t457, t452);
                uint16_t t459 = MEDIAN_MIN(t458, t453);
                uint16_t t460 = MEDIAN_MIN(t459, t454);
                uint16_t t461 = MEDIAN_MIN(t460, t403);
                buf[11840 + x] = t461;
                uint16_t t490 = MEDIAN_MAX(t396, buf[27840 + x]);
                uint16_t t491 = MEDIAN_MAX(t397, buf[27520 + x]);
                uint16_t t492 = MEDIAN_MAX(t398, buf[27200 + x]);
                uint16_t t493 = MEDIAN_MAX(t399, buf[26880 + x]);
                uint16_t t494 = MEDIAN_MAX(t400, buf[26560 + x]);
                uint16_t t495 = MEDIAN_MAX(t401, buf[26240 + x]);
                uint16_t t496 = MEDIAN_MAX(t402, buf[25920 + x]);
                uint16_t t497 = MEDIAN_MIN(t490, t491);
                uint16_t t498 = MEDIAN_MIN(t497, t492);
                uint16_t t499 = MEDIAN_MIN(t498, t493);
                uint16_t t500 = MEDIAN_MIN(t499, t494);
                uint16_t t501 = MEDIAN_MIN(t500, t495);
                uint16_t t502 = MEDIAN_MIN(t501, t496);
                uint16_t t503 = MEDIAN_MIN(t502, t403);
                buf[11520 + x] = t503;
            }
            memcpy(oflat + y * lanes + c0, buf + 11840, (size_t)m * sizeof(uint16_t));
            if (y + 1 < rows) memcpy(oflat + (y + 1) * lanes + c0, buf + 11520, (size_t)m * sizeof(uint16_t));
        }
    }
}

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
