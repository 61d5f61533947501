/* tests/plugins/volumetric_froxel/froxel_agree.h: the check of the agreement that the test
 * node froxel_agree (testfroxelspec.c) measured between a backend's output and froxel.h's
 * reference, shared by test_froxel_cpu_dir.c, test_froxel_gl_lights.c and (the verdict on errors it
 * measured itself) test_froxel_gl.c.
 *
 * The measurement is a 2 x 1 rgba image: pixel 0 = {worst error of a value relative to its
 * channel's largest reference value, rmse of those relative errors, values beyond `tol`,
 * values that are not finite}, pixel 1 = {the r, g, b channels' largest reference values,
 * values compared}. Passing: a non-black reference, every value finite, at most 1 in 200
 * values beyond tol and an rmse of at most 5 tol. The measured errors go to stderr. */
#ifndef LG_TEST_FROXEL_AGREE_H
#define LG_TEST_FROXEL_AGREE_H

#include <math.h>
#include <stdio.h>

#include "lightgraph/image.h"
#include "lightgraph/test.h"

/* The verdict on measured agreement: `scale` the largest of the reference's r, g, b maxima,
 * `rmse` of the errors relative to each value's channel maximum, `over` values beyond tol,
 * `bad` not finite, of `n`. */
static inline void froxel_agree_verdict(lg_test *t, double scale, double rmse, size_t over,
                                        size_t bad, size_t n, double tol, const char *what)
{
    LG_TEST_CHECK(t, scale > 0, "%s: the reference is black", what);
    LG_TEST_CHECK(t, bad == 0, "%s: %zu values are not finite", what, bad);
    LG_TEST_CHECK(t, over <= n / 200,
                  "%s: %zu values (of %zu) differ by more than %g of their channel's largest", what,
                  over, n, tol);
    /* 5 tol: a froxel whose sample point lies within float rounding of a stored shadow depth
     * may test lit on one device and shadowed on the other, and the accumulation carries
     * that step down its whole column (0.07 % of the grid's values on the example scene, up
     * to 0.8 % of the scale each); the count bound above is the primary check */
    LG_TEST_CHECK(t, rmse <= 5 * tol, "%s: rmse %g of the channels' largest values > %g", what,
                  rmse, 5 * tol);
}

/* The verdict on the 2 x 1 image froxel_agree made (above), its errors noted on stderr. */
static inline void froxel_agree_check(lg_test *t, const lg_image *m, double tol, const char *what)
{
    const float *p = m->pixels;
    double worst = p[0], rmse = p[1], scale = fmax(fmax(p[4], p[5]), p[6]);
    size_t over = (size_t)p[2], bad = (size_t)p[3], n = (size_t)p[7];
    fprintf(stderr,
            "%s: rgb scale %.4g, max error %.3g of its channel's scale, rmse %.3g, %zu of %zu "
            "beyond %g\n",
            what, scale, worst, rmse, over, n, tol);
    froxel_agree_verdict(t, scale, rmse, over, bad, n, tol, what);
}

#endif
