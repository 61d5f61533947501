/* tests/plugins/volumetric_froxel/froxel_agree.h: the check of the agreement that the test
 * node froxel_agree (testfroxelspec.c) measured between a backend's output and froxel.h's
 * reference, shared by test_froxel_cpu_dir.c and test_froxel_gl_lights.c.
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

static inline void froxel_agree_check(lg_test *t, const lg_image *m, double tol, const char *what)
{
    const float *p = m->pixels;
    double worst = p[0], rmse = p[1], scale = fmax(fmax(p[4], p[5]), p[6]);
    size_t over = (size_t)p[2], bad = (size_t)p[3], n = (size_t)p[7];
    fprintf(stderr,
            "%s: rgb scale %.4g, max error %.3g of its channel's scale, rmse %.3g, %zu of %zu "
            "beyond %g\n",
            what, scale, worst, rmse, over, n, tol);
    LG_TEST_CHECK(t, scale > 0, "%s: the reference is black", what);
    LG_TEST_CHECK(t, bad == 0, "%s: %zu values are not finite", what, bad);
    LG_TEST_CHECK(t, over <= n / 200,
                  "%s: %zu values (of %zu) differ by more than %g of their channel's largest", what,
                  over, n, tol);
    LG_TEST_CHECK(t, rmse <= 5 * tol, "%s: rmse %g of the channels' largest values > %g", what,
                  rmse, 5 * tol);
}

#endif
