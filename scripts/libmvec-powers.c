/* What powers in SIMD lanes would cost here: glibc's vector powers (libmvec, AVX2: 8 `powf`
 * or 4 `pow` a call) against the scalar `powf` and `pow`, on the bases and exponents of
 * `bench contact`'s mixed class, and the vector `powf`'s worst error against `pow` in f32 ulps.
 * A measurement for docs/performance.md (stop 39), not part of the build:
 *
 *   gcc -O2 -mavx2 -mfma -fno-builtin scripts/libmvec-powers.c -o /tmp/libmvec-powers \
 *       -lmvec -lm && /tmp/libmvec-powers
 */
#include <immintrin.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <time.h>

__m256 _ZGVdN8vv_powf(__m256, __m256);
__m256d _ZGVdN4vv_pow(__m256d, __m256d);

/* A fixed, spread sample in [0, 1) (a multiplicative hash), as the criterion group `powers`. */
static double unit(uint64_t k, uint64_t salt) {
    uint64_t h = ((k ^ salt) * 0x9e3779b97f4a7c15ULL) >> 11;
    return (double)h / (double)(1ULL << 53);
}

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

#define N 1024
#define REPS 20000
static float xs[N], es[N];
static double xd[N], ed[N];
static volatile float sink_f;
static volatile double sink_d;

int main(void) {
    for (int k = 0; k < N; k++) {
        xd[k] = 1e-6 + unit(k, 1);
        ed[k] = 0.5 + 3.5 * unit(k, 2);
        xs[k] = (float)xd[k];
        es[k] = (float)ed[k];
    }
    /* Accuracy over bases in [1e-8, 1e8] and exponents in [-16, 16] (the single-precision
     * bounds' range), results in [1e-8, 1e8]. */
    double worst = 0.0;
    for (uint64_t k = 0; k < 4000000; k++) {
        float x = (float)(1e-8 * pow(1e16, unit(k, 7)));
        float e = (float)(-16.0 + 32.0 * unit(k, 9));
        double r = pow((double)x, (double)e);
        if (!(r >= 1e-8 && r <= 1e8)) continue;
        float f = _mm256_cvtss_f32(_ZGVdN8vv_powf(_mm256_set1_ps(x), _mm256_set1_ps(e)));
        double ulp = fabs((double)(float)r) * 1.1920928955078125e-07;
        double err = fabs(f - r) / ulp;
        if (err > worst) worst = err;
    }
    printf("vector powf: worst error %.3f f32 ulps\n", worst);
    for (int rep = 0; rep < 3; rep++) {
        double t = now();
        for (int it = 0; it < REPS; it++)
            for (int i = 0; i < N; i++) sink_f = powf(xs[i], es[i]);
        double a = (now() - t) / ((double)REPS * N) * 1e9;
        t = now();
        for (int it = 0; it < REPS; it++)
            for (int i = 0; i < N; i += 8)
                sink_f = _mm256_cvtss_f32(
                    _ZGVdN8vv_powf(_mm256_loadu_ps(xs + i), _mm256_loadu_ps(es + i)));
        double b = (now() - t) / ((double)REPS * N) * 1e9;
        t = now();
        for (int it = 0; it < REPS; it++)
            for (int i = 0; i < N; i++) sink_d = pow(xd[i], ed[i]);
        double c = (now() - t) / ((double)REPS * N) * 1e9;
        t = now();
        for (int it = 0; it < REPS; it++)
            for (int i = 0; i < N; i += 4)
                sink_d = _mm256_cvtsd_f64(
                    _ZGVdN4vv_pow(_mm256_loadu_pd(xd + i), _mm256_loadu_pd(ed + i)));
        double d = (now() - t) / ((double)REPS * N) * 1e9;
        printf("ns a power: powf %.2f, 8 lanes %.2f | pow %.2f, 4 lanes %.2f\n", a, b, c, d);
    }
    return 0;
}
