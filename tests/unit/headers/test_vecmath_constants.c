/*
 * The constants of lightgraph/vecmath.h: each the double nearest its exact value, checked two
 * ways that do not share a source with the header:
 *
 *   - against the double written bit for bit as a hexadecimal literal (the nearest double to
 *     pi is 0x1.921fb54442d18p+1, to 1/pi 0x1.45f306dc9c883p-2);
 *   - against the value computed in long double (acosl(-1), 64-bit significand on x86-64),
 *     which must lie within half an ulp of the double.
 *
 * Then what the header promises about them: LG_TWO_PI and LG_HALF_PI are 2 and 0.5 times
 * LG_PI to the bit, LG_PIF is the float nearest pi, and the macros are constant expressions
 * (a static initialiser uses them).
 */
#include <float.h>
#include <math.h>
#include <stdio.h>

#include "common/check.h"
#include "lightgraph/vecmath.h"

/* constant expressions: these would not compile otherwise */
static const double deg = LG_PI / 180.0;
static const float quarter = LG_PIF / 4.0f;

/* |x - exact| <= half the gap between x and its neighbour on exact's side (long double) */
static int nearest(double x, long double exact)
{
    double next = nextafter(x, exact > (long double)x ? INFINITY : -INFINITY);
    long double half_ulp = fabsl((long double)next - (long double)x) / 2.0L;
    return fabsl((long double)x - exact) <= half_ulp;
}

int main(void)
{
    const long double pi = acosl(-1.0L);

    CHECKF(LG_PI == 0x1.921fb54442d18p+1, "LG_PI = %a", LG_PI);
    CHECKF(LG_TWO_PI == 0x1.921fb54442d18p+2, "LG_TWO_PI = %a", LG_TWO_PI);
    CHECKF(LG_HALF_PI == 0x1.921fb54442d18p+0, "LG_HALF_PI = %a", LG_HALF_PI);
    CHECKF(LG_INV_PI == 0x1.45f306dc9c883p-2, "LG_INV_PI = %a", LG_INV_PI);
    CHECKF(LG_INV_TWO_PI == 0x1.45f306dc9c883p-3, "LG_INV_TWO_PI = %a", LG_INV_TWO_PI);
    CHECKF(LG_INV_FOUR_PI == 0x1.45f306dc9c883p-4, "LG_INV_FOUR_PI = %a", LG_INV_FOUR_PI);
    CHECKF(LG_PIF == 0x1.921fb6p+1f, "LG_PIF = %a", (double)LG_PIF);

    if (LDBL_MANT_DIG > DBL_MANT_DIG) {
        CHECKF(nearest(LG_PI, pi), "LG_PI %.17g vs %.21Lg", LG_PI, pi);
        CHECKF(nearest(LG_TWO_PI, 2.0L * pi), "LG_TWO_PI %.17g", LG_TWO_PI);
        CHECKF(nearest(LG_HALF_PI, pi / 2.0L), "LG_HALF_PI %.17g", LG_HALF_PI);
        CHECKF(nearest(LG_INV_PI, 1.0L / pi), "LG_INV_PI %.17g", LG_INV_PI);
        CHECKF(nearest(LG_INV_TWO_PI, 1.0L / (2.0L * pi)), "LG_INV_TWO_PI %.17g", LG_INV_TWO_PI);
        CHECKF(nearest(LG_INV_FOUR_PI, 1.0L / (4.0L * pi)), "LG_INV_FOUR_PI %.17g", LG_INV_FOUR_PI);
        CHECKF(fabsl((long double)LG_PIF - pi) <=
                   fabsl((long double)nextafterf(LG_PIF, 0.0f) - (long double)LG_PIF) / 2.0L,
               "LG_PIF %.9g", (double)LG_PIF);
    } else {
        printf("long double is no wider than double here: the hexadecimal checks only\n");
    }

    /* what the header says of them */
    CHECK(LG_TWO_PI == 2.0 * LG_PI);
    CHECK(LG_HALF_PI == 0.5 * LG_PI);
    CHECK(LG_PIF == (float)LG_PI);
    CHECKF(fabs(deg * 180.0 - LG_PI) <= 4.0 * DBL_EPSILON, "%.17g", deg * 180.0);
    CHECK(quarter == (float)(LG_PI / 4.0));
    return check_report("sdk_vecmath_constants");
}
