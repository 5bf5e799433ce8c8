/* Cholesky factorization A = L L^T of a symmetric positive definite band matrix and the solve
 * A x = b, for continuum.py (loaded with ctypes). Storage: lower band, column-major, lda = b + 1:
 * ab[j (b + 1) + (i - j)] = A(i, j) for j <= i <= j + b, b = the half bandwidth.
 * Why not LAPACK's dpbtrf: with the reference BLAS of a plain Debian system it takes 4-6x longer on
 * the continuum's bands (b = 37-119, the README); the right-looking loop below is one contiguous
 * update of length <= b per pair of columns, which the compiler vectorizes. */
#include <math.h>

/* x86-64: a second copy of each routine for AVX2/FMA (x86-64-v3), picked when the library is loaded
 * (1.4x on the continuum's bands); elsewhere the plain build */
#if defined(__GNUC__) && defined(__x86_64__) && defined(__linux__)
#define BAND_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define BAND_CLONES
#endif

/* Factor in place (L overwrites the lower band). Returns 0, or j + 1 when the pivot of column j is
 * not positive (A is not positive definite; ab is then partly overwritten). */
BAND_CLONES int band_cholesky(int n, int b, double *ab)
{
    const long lda = (long)b + 1;
    for (int j = 0; j < n; ++j) {
        double *cj = ab + j * lda;
        if (!(cj[0] > 0.0)) return j + 1;
        const double d = sqrt(cj[0]);
        cj[0] = d;
        const int m = (n - 1 - j < b) ? n - 1 - j : b;
        const double inv = 1.0 / d;
        for (int i = 1; i <= m; ++i) cj[i] *= inv;
        for (int k = 1; k <= m; ++k) {
            const double lk = cj[k];
            if (lk == 0.0) continue;           /* the band's structural zeros: about half of it */
            double *restrict ck = ab + (j + k) * lda;
            const double *restrict lj = cj + k;
            for (int t = 0; t <= m - k; ++t) ck[t] -= lk * lj[t];
        }
    }
    return 0;
}

/* x <- A^-1 x with the factor of band_cholesky: L y = x, then L^T x = y. */
BAND_CLONES void band_solve(int n, int b, const double *ab, double *x)
{
    const long lda = (long)b + 1;
    for (int j = 0; j < n; ++j) {
        const double *cj = ab + j * lda;
        const int m = (n - 1 - j < b) ? n - 1 - j : b;
        const double xj = x[j] / cj[0];
        x[j] = xj;
        for (int i = 1; i <= m; ++i) x[j + i] -= cj[i] * xj;
    }
    for (int j = n - 1; j >= 0; --j) {
        const double *cj = ab + j * lda;
        const int m = (n - 1 - j < b) ? n - 1 - j : b;
        double s = x[j];
        for (int i = 1; i <= m; ++i) s -= cj[i] * x[j + i];
        x[j] = s / cj[0];
    }
}
