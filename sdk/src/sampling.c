/* Point sets and sums of lightgraph/sampling.h. */
#include "lightgraph/sampling.h"

#include <math.h>

#include "lightgraph/vecmath.h"

const char *lg_sampler_name(lg_sampler s)
{
    switch (s) {
    case LG_SAMPLER_JITTERED: return "jittered";
    case LG_SAMPLER_HAMMERSLEY: return "hammersley";
    case LG_SAMPLER_SOBOL: return "sobol";
    }
    return NULL;
}

/* SplitMix64's finaliser: a counter-based hash, so point k needs no state. */
static uint64_t mix64(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* 53 random bits as a double in [0, 1). */
static double unit53(uint64_t bits)
{
    return (double)(bits >> 11) * 0x1p-53;
}

/* 32 bits as a double in [0, 1) (exact). */
static double unit32(uint32_t bits)
{
    return (double)bits * 0x1p-32;
}

static uint32_t reverse32(uint32_t v)
{
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
    return (v >> 16) | (v << 16);
}

/* Sobol's second dimension: direction numbers of x + 1, v_1 = 2^31, v_j = v_{j-1} ^
 * (v_{j-1} >> 1); the point is the XOR of v_j over the set bits j of k. */
static uint32_t sobol2(uint32_t k)
{
    uint32_t v = 1u << 31, r = 0;
    for (; k; k >>= 1, v ^= v >> 1)
        if (k & 1u)
            r ^= v;
    return r;
}

void lg_sample_square(lg_sampler s, uint32_t side, uint64_t seed, uint64_t k, double uv[2])
{
    if (side == 0)
        side = 1;
    uint64_t total = (uint64_t)side * side;
    k %= total;
    /* the shift of each dimension: distinct streams of one hash */
    uint64_t h = seed ? mix64(seed ^ 0x5bd1e9955bd1e995ull) : 0;
    switch (s) {
    case LG_SAMPLER_HAMMERSLEY:
        uv[0] = ((double)k + 0.5) / (double)total;
        uv[1] = unit32(reverse32((uint32_t)k) ^ (uint32_t)h);
        return;
    case LG_SAMPLER_SOBOL:
        uv[0] = unit32(reverse32((uint32_t)k) ^ (uint32_t)h);
        uv[1] = unit32(sobol2((uint32_t)k) ^ (uint32_t)(h >> 32));
        return;
    case LG_SAMPLER_JITTERED:
    default: {
        uint64_t a = mix64(seed * 0x9e3779b97f4a7c15ull + 2 * k);
        uint64_t b = mix64(seed * 0x9e3779b97f4a7c15ull + 2 * k + 1);
        uv[0] = ((double)(k % side) + unit53(a)) / side;
        uv[1] = ((double)(k / side) + unit53(b)) / side;
        /* (i + xi) / side can round to 1 for xi just below 1 */
        if (uv[0] >= 1.0)
            uv[0] = nextafter(1.0, 0.0);
        if (uv[1] >= 1.0)
            uv[1] = nextafter(1.0, 0.0);
        return;
    }
    }
}

void lg_sample_sphere(const double uv[2], double dir[3])
{
    double u = uv[0], z = 1.0 - 2.0 * u;
    double r = 2.0 * sqrt(u * (1.0 - u)); /* sin theta, exact near both poles */
    double phi = 2.0 * LG_PI * uv[1];
    dir[0] = r * cos(phi);
    dir[1] = r * sin(phi);
    dir[2] = z;
}

static double sum_rec(const float *x, size_t n)
{
    if (n <= 64) {
        double s = 0;
        for (size_t i = 0; i < n; i++)
            s += x[i];
        return s;
    }
    size_t h = n / 2;
    return sum_rec(x, h) + sum_rec(x + h, n - h);
}

double lg_sum_f(const float *x, size_t n)
{
    return x && n ? sum_rec(x, n) : 0.0;
}
