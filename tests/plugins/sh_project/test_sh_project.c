/*
 * The sh_project node through the host: probes written here as EXR files, read by the
 * probe node, projected, and the coefficients read back from the text output
 * (`output light "light.txt"`). Each case has an oracle: a closed form, the SH basis
 * itself (lightgraph/sh.h, evaluated here), or an independent estimate.
 *
 *   constant     constant probe c: c_0 = 2 sqrt(pi) c, the rest ~0, by quadrature in the
 *                lat-long, angular and cube (strip) layouts and by every sampler
 *   sign         a probe bright around +x gives positive Y_1,1 (+y: Y_1,-1, +z: Y_1,0),
 *                and around -x negative Y_1,1; the other band-1 coefficients ~0; in the
 *                lat-long and cube layouts
 *   orthonormal  a probe painted with 1 + Y_l,m (every function of 4 bands, three per
 *                render in R, G, B) projects by quadrature to 2 sqrt(pi) e_0 + e_lm
 *   sky          L = 1 for y > 0: with 9 coefficients the irradiance sum_lm A_l L_lm Y_lm(n)
 *                is (pi/2)(1 + n_y) at normals all round
 *   converge     the forest: every sampler's error against quadrature (printed for 16^2,
 *                64^2, 256^2) falls as the samples grow
 *   many         10^8 Hammersley samples of a constant probe (bands 1): c_0 exact to 1e-6
 *                relative (the accumulation)
 *   threads      LIGHTGRAPH_THREADS = 1, 2, 3 give byte-identical text, quadrature and
 *                sobol
 *   rotation     a probe with rotate_deg = [90, 30, 0] projects like the same pattern
 *                drawn rotated (and unlike the unrotated one)
 *   window       window = hanning | lanczos | gaussian scales band l by lg_sh_window_factor;
 *                the header says "windowed"
 *   text         the text format: header, one line per coefficient, i = l (l+1) + m, every
 *                number the shortest text of a float that reads back to it
 *   bad          absurd parameters and mismatched output files are refused before anything
 *                runs, naming the node, the value or the file
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/probe.h"
#include "lightgraph/sh.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#define MAXC (3 * 64 * 64)

/* ---- probes ---------------------------------------------------------------------------------- */

typedef void (*paint_fn)(const void *ctx, lg_vec3 d, float rgb[3]);

/* Writes `name`: a lat-long (W x H), angular (W x W) or cube strip (6W x W) probe whose
 * texel centres hold fn(direction). */
static void write_probe(lg_test *t, const char *name, lg_probe_layout layout, uint32_t w,
                        uint32_t h, paint_fn fn, const void *ctx)
{
    uint32_t faces = layout == LG_PROBE_CUBE ? 6 : 1;
    if (layout != LG_PROBE_LATLONG)
        h = w;
    lg_image img = { 0 };
    if (lg_image_alloc(&img, w * faces, h)) {
        LG_TEST_FAILF(t, "out of memory");
        return;
    }
    for (uint32_t f = 0; f < faces; f++)
        for (uint32_t j = 0; j < h; j++)
            for (uint32_t i = 0; i < w; i++) {
                float *p = img.pixels + 4 * ((size_t)j * w * faces + f * w + i);
                lg_vec3 d = lg_probe_texel_dir(layout, w, h, f, i, j);
                fn(ctx, d, p);
                p[3] = 1.0f;
            }
    lg_test_write_exr(t, name, &img);
    lg_image_free(&img);
}

static void paint_constant(const void *ctx, lg_vec3 d, float rgb[3])
{
    (void)d;
    memcpy(rgb, ctx, 3 * sizeof(float));
}

/* ---- running and reading back ---------------------------------------------------------------- */

typedef struct coeffs {
    uint32_t bands, nc;
    bool windowed;
    double c[MAXC]; /* R plane, G plane, B plane */
} coeffs;

/* Reads the text output; false after a failed check. */
static bool read_coeffs(lg_test *t, const char *rel, coeffs *out)
{
    memset(out, 0, sizeof *out);
    FILE *f = fopen(lg_test_path(t, rel), "r");
    if (!f) {
        LG_TEST_FAILF(t, "%s was not written", rel);
        return false;
    }
    char line[512];
    uint32_t perch = 0, got = 0;
    bool ok = true;
    if (!fgets(line, sizeof line, f) ||
        sscanf(line, "# lightgraph SH coefficients: %u band", &out->bands) != 1 ||
        !strstr(line, out->bands == 1 ? " band, " : " bands, ") ||
        sscanf(strstr(line, ", ") + 2, "%u per channel", &perch) != 1 || out->bands < 1 ||
        out->bands > 64 || perch != out->bands * out->bands) {
        LG_TEST_FAILF(t, "%s: bad first line: %s", rel, line);
        fclose(f);
        return false;
    }
    out->nc = perch;
    out->windowed = strstr(line, ", windowed") != NULL;
    if (!fgets(line, sizeof line, f) || strcmp(line, "# index l m R G B\n") != 0) {
        LG_TEST_FAILF(t, "%s: bad second line: %s", rel, line);
        ok = false;
    }
    while (ok && fgets(line, sizeof line, f)) {
        unsigned i, l;
        int m;
        double v[3];
        if (sscanf(line, "%u %u %d %lf %lf %lf", &i, &l, &m, &v[0], &v[1], &v[2]) != 6 ||
            i != got || l >= out->bands || m < -(int)l || m > (int)l ||
            i != lg_sh_index((int)l, m)) {
            LG_TEST_FAILF(t, "%s: bad line %u: %s", rel, got + 3, line);
            ok = false;
            break;
        }
        for (int ch = 0; ch < 3; ch++)
            out->c[ch * out->nc + i] = v[ch];
        got++;
    }
    fclose(f);
    if (ok && got != out->nc) {
        LG_TEST_FAILF(t, "%s: %u coefficient lines, want %u", rel, got, out->nc);
        ok = false;
    }
    return ok;
}

/* Renders `sky = probe {...}` + `light = sh_project {...}` to light.txt and reads it. */
static bool project(lg_test *t, const char *probe_params, const char *sh_params, coeffs *out)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\nsky = probe { %s }\nlight = sh_project { probe = sky, "
             "%s }\noutput light \"light.txt\"\n",
             probe_params, sh_params);
    lg_test_write_text(t, "g.lgraph", g);
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", NULL, &text);
    LG_TEST_CHECK(t, rc == 0, "render of\n%s\nexit %d:\n%s", g, rc, text ? text : "");
    free(text);
    return rc == 0 && read_coeffs(t, "light.txt", out);
}

static const char *const SAMPLERS[] = { "jittered", "hammersley", "sobol" };

/* ---- cases ----------------------------------------------------------------------------------- */

static void case_constant(lg_test *t)
{
    const float c[3] = { 0.7f, 1.3f, 2.5f };
    write_probe(t, "ll.exr", LG_PROBE_LATLONG, 32, 16, paint_constant, c);
    write_probe(t, "ang.exr", LG_PROBE_ANGULAR, 32, 32, paint_constant, c);
    write_probe(t, "cube.exr", LG_PROBE_CUBE, 8, 8, paint_constant, c);
    struct {
        const char *probe, *sh;
        double tol_rest;
    } runs[] = {
        /* quadrature at texel centres: the within-texel variation of Y_2,0 (lat-long rows,
         * angular rings) is the error left; the cube's symmetry cancels bands 1 to 3 */
        { "file = \"ll.exr\"", "bands = 3", 5e-3 },
        { "file = \"ang.exr\", layout = angular", "bands = 3", 5e-3 },
        { "file = \"cube.exr\", layout = strip", "bands = 3", 1e-5 },
        { "file = \"cube.exr\", layout = strip", "bands = 6", 0.02 }, /* l = 4: texel centres */
        { "file = \"ll.exr\"", "bands = 3, sampler = jittered, samples = 64", 0.01 },
        { "file = \"ll.exr\"", "bands = 3, sampler = hammersley, samples = 64", 0.01 },
        { "file = \"cube.exr\", layout = strip", "bands = 3, sampler = sobol, samples = 64", 0.01 },
    };
    for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
        coeffs k;
        if (!project(t, runs[r].probe, runs[r].sh, &k))
            continue;
        double worst = 0;
        for (uint32_t i = 1; i < k.nc; i++)
            worst = fmax(worst, fabs(k.c[i]) / (2.0 * sqrt(LG_PI) * c[0]));
        printf("%-38s %-46s c_0 %.9g, largest other / c_0 %.2e\n", runs[r].probe, runs[r].sh,
               k.c[0], worst);
        for (int ch = 0; ch < 3; ch++) {
            double want = 2.0 * sqrt(LG_PI) * c[ch], got = k.c[ch * k.nc];
            LG_TEST_CHECK(t, fabs(got - want) <= 2e-6 * want,
                          "%s / %s: c_0 channel %d = %.9g, want %.9g", runs[r].probe, runs[r].sh,
                          ch, got, want);
            for (uint32_t i = 1; i < k.nc; i++)
                LG_TEST_CHECK(t, fabs(k.c[ch * k.nc + i]) <= runs[r].tol_rest * want,
                              "%s / %s: c_%u channel %d = %.3g, want ~0", runs[r].probe, runs[r].sh,
                              i, ch, k.c[ch * k.nc + i]);
        }
    }
}

/* 1 inside a cone of cos > 0.8 around axis a, 0 outside (all channels) */
static void paint_cap(const void *ctx, lg_vec3 d, float rgb[3])
{
    const float *a = ctx;
    float v = d.x * a[0] + d.y * a[1] + d.z * a[2] > 0.8f ? 1.0f : 0.0f;
    rgb[0] = rgb[1] = rgb[2] = v;
}

static void case_sign(lg_test *t)
{
    static const float axes[][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { -1, 0, 0 } };
    static const int idx[] = { 3, 1, 2, 3 }; /* Y_1,1 ~ x, Y_1,-1 ~ y, Y_1,0 ~ z */
    static const double sgn[] = { 1, 1, 1, -1 };
    for (int a = 0; a < 8; a++) {
        /* lat-long, then a cube strip (the faces' order and orientation) */
        bool cube = a >= 4;
        write_probe(t, "cap.exr", cube ? LG_PROBE_CUBE : LG_PROBE_LATLONG, cube ? 32 : 128, 64,
                    paint_cap, axes[a % 4]);
        coeffs k;
        if (!project(t, cube ? "file = \"cap.exr\", layout = strip" : "file = \"cap.exr\"",
                     "bands = 2", &k))
            continue;
        int ax = a % 4;
        /* the cap's band-1 coefficient along its axis: 0.488603 * 2 pi (1 - 0.8^2) / 2 */
        double along = sgn[ax] * k.c[idx[ax]], want = 0.488603 * LG_PI * (1 - 0.64);
        LG_TEST_CHECK(t, fabs(along - want) < 0.05 * want,
                      "%s cap around axis %d: Y_1 coefficient %d = %g, want %g",
                      cube ? "cube" : "lat-long", ax, idx[ax], k.c[idx[ax]], sgn[ax] * want);
        for (int i = 1; i < 4; i++)
            if (i != idx[ax])
                LG_TEST_CHECK(t, fabs(k.c[i]) < 0.02 * want,
                              "%s cap around axis %d: coefficient %d = %g, want ~0",
                              cube ? "cube" : "lat-long", ax, i, k.c[i]);
    }
}

typedef struct ylm3 {
    int idx[3]; /* the function painted in R, G, B (-1: none) */
} ylm3;

static void paint_ylm(const void *ctx, lg_vec3 d, float rgb[3])
{
    const ylm3 *p = ctx;
    double y[16], dir[3] = { d.x, d.y, d.z };
    lg_sh_eval_d(4, dir, y);
    for (int ch = 0; ch < 3; ch++)
        rgb[ch] = (float)(1.0 + (p->idx[ch] >= 0 ? y[p->idx[ch]] : 0.0));
}

static void case_orthonormal(lg_test *t)
{
    double worst = 0;
    for (int first = 0; first < 16; first += 3) {
        ylm3 p;
        for (int ch = 0; ch < 3; ch++)
            p.idx[ch] = first + ch < 16 ? first + ch : -1;
        write_probe(t, "y.exr", LG_PROBE_LATLONG, 256, 128, paint_ylm, &p);
        coeffs k;
        if (!project(t, "file = \"y.exr\"", "bands = 4", &k))
            continue;
        for (int ch = 0; ch < 3; ch++)
            for (int i = 0; i < 16; i++) {
                double want = (i == 0 ? 2.0 * sqrt(LG_PI) : 0.0) + (i == p.idx[ch] ? 1.0 : 0.0);
                double e = fabs(k.c[ch * 16 + i] - want);
                if (e > worst)
                    worst = e;
                LG_TEST_CHECK(t, e < 2e-3, "1 + Y_%d painted: coefficient %d = %.6f, want %g",
                              p.idx[ch], i, k.c[ch * 16 + i], want);
            }
    }
    printf("orthonormality through the node (lat-long 256x128, 4 bands): worst error %.2e\n",
           worst);
}

static void paint_sky(const void *ctx, lg_vec3 d, float rgb[3])
{
    (void)ctx;
    rgb[0] = rgb[1] = rgb[2] = d.y > 0 ? 1.0f : 0.0f;
}

static void case_sky(lg_test *t)
{
    write_probe(t, "sky.exr", LG_PROBE_LATLONG, 256, 128, paint_sky, NULL);
    coeffs k;
    if (!project(t, "file = \"sky.exr\"", "bands = 3", &k))
        return;
    double worst = 0;
    for (int s = 0; s < 26; s++) {
        /* normals: the axes, the 12 edge midpoints and 8 corners of the cube, normalised */
        int a = s < 13 ? s : s + 1; /* skip (0,0,0) of the 27 */
        double nrm[3] = { a % 3 - 1.0, (a / 3) % 3 - 1.0, a / 9 - 1.0 };
        double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        for (int i = 0; i < 3; i++)
            nrm[i] /= len;
        double y[9], e = 0;
        lg_sh_eval_d(3, nrm, y);
        for (int l = 0; l < 3; l++)
            for (int m = -l; m <= l; m++)
                e += lg_sh_clamped_cosine((uint32_t)l) * k.c[lg_sh_index(l, m)] *
                     y[lg_sh_index(l, m)];
        double want = LG_PI / 2 * (1 + nrm[1]);
        worst = fmax(worst, fabs(e - want));
        LG_TEST_CHECK(t, fabs(e - want) < 2e-3 * LG_PI,
                      "upper-hemisphere sky, normal (%.3f, %.3f, %.3f): E = %.6f, want %.6f",
                      nrm[0], nrm[1], nrm[2], e, want);
    }
    printf("upper-hemisphere sky, 9 coefficients: irradiance within %.2e of (pi/2)(1 + n_y)\n",
           worst);
}

/* RMS over every coefficient and channel of a - b, relative to |c_0| (luminance-ish). */
static double rel_rms(const coeffs *a, const coeffs *b)
{
    double s = 0, n0 = 0;
    for (uint32_t i = 0; i < 3 * a->nc; i++)
        s += (a->c[i] - b->c[i]) * (a->c[i] - b->c[i]);
    for (int ch = 0; ch < 3; ch++)
        n0 += b->c[ch * b->nc] * b->c[ch * b->nc];
    return sqrt(s / (3.0 * a->nc)) / sqrt(n0 / 3.0);
}

static void case_converge(lg_test *t)
{
    char probe[1024];
    snprintf(probe, sizeof probe, "file = \"%s\"",
             lg_test_asset("probes/forest_256x128_half_none.exr"));
    coeffs ref, k;
    if (!project(t, probe, "bands = 3", &ref))
        return;
    static const int sides[] = { 16, 64, 256 };
    printf("forest 256x128, 3 bands: relative RMS error against quadrature\n");
    printf("%-11s %10s %10s %10s\n", "sampler", "16^2", "64^2", "256^2");
    for (int s = 0; s < 3; s++) {
        double err[3] = { 0, 0, 0 };
        for (int n = 0; n < 3; n++) {
            char sh[128];
            snprintf(sh, sizeof sh, "bands = 3, sampler = %s, samples = %d, seed = 7", SAMPLERS[s],
                     sides[n]);
            if (project(t, probe, sh, &k))
                err[n] = rel_rms(&k, &ref);
        }
        printf("%-11s %10.2e %10.2e %10.2e\n", SAMPLERS[s], err[0], err[1], err[2]);
        LG_TEST_CHECK(t, err[2] < 0.5 * err[0] && err[1] < 1.5 * err[0] && err[2] < 0.02,
                      "%s: errors %.3g, %.3g, %.3g do not fall", SAMPLERS[s], err[0], err[1],
                      err[2]);
    }
}

static void case_many(lg_test *t)
{
    /* a 1x1 lat-long probe reads its one texel everywhere; 0.3 is not a binary fraction */
    const float c[3] = { 0.3f, 0.3f, 0.3f };
    write_probe(t, "one.exr", LG_PROBE_LATLONG, 1, 1, paint_constant, c);
    coeffs k;
    if (!project(t, "file = \"one.exr\"", "bands = 1, sampler = hammersley, samples = 10000", &k))
        return;
    double want = 2.0 * sqrt(LG_PI) * (double)c[0];
    for (int ch = 0; ch < 3; ch++)
        LG_TEST_CHECK(t, fabs(k.c[ch] - want) <= 1e-6 * want,
                      "10^8 samples: c_0 channel %d = %.9g, want %.9g (relative %.2e)", ch, k.c[ch],
                      want, (k.c[ch] - want) / want);
    printf("10^8 Hammersley samples of a constant 0.3: c_0 = %.9g, exact %.9g (relative "
           "%.2e)\n",
           k.c[0], want, (k.c[0] - want) / want);
}

static char *slurp(lg_test *t, const char *rel)
{
    FILE *f = fopen(lg_test_path(t, rel), "rb");
    if (!f)
        return NULL;
    char *b = calloc(1, 1 << 20);
    if (b)
        (void)fread(b, 1, (1 << 20) - 1, f);
    fclose(f);
    return b;
}

static void case_threads(lg_test *t)
{
    char probe[1024];
    snprintf(probe, sizeof probe, "file = \"%s\"",
             lg_test_asset("probes/forest_256x128_half_none.exr"));
    static const char *const sh[] = { "bands = 4", "bands = 4, sampler = sobol, samples = 300" };
    for (int s = 0; s < 2; s++) {
        char *text[3] = { NULL, NULL, NULL };
        for (int th = 0; th < 3; th++) {
            char n[8];
            snprintf(n, sizeof n, "%d", th + 1);
            setenv("LIGHTGRAPH_THREADS", n, 1);
            coeffs k;
            if (project(t, probe, sh[s], &k))
                text[th] = slurp(t, "light.txt");
        }
        unsetenv("LIGHTGRAPH_THREADS");
        for (int th = 1; th < 3; th++)
            LG_TEST_CHECK(t, text[0] && text[th] && strcmp(text[0], text[th]) == 0,
                          "%s: LIGHTGRAPH_THREADS=1 and %d differ", sh[s], th + 1);
        for (int th = 0; th < 3; th++)
            free(text[th]);
    }
}

/* A smooth, asymmetric pattern in probe directions, or (rot != NULL) the same pattern
 * seen in world directions after the probe -> world rotation rot: P(rot^T d). */
static void paint_pattern(const void *ctx, lg_vec3 d, float rgb[3])
{
    const float *rot = ctx;
    if (rot)
        d = lg_probe_from_world(rot, d);
    float lobe = d.x > 0 ? d.x * d.x * d.x : 0.0f;
    rgb[0] = 1.0f + 2.0f * lobe + 0.5f * d.y;
    rgb[1] = 1.0f + 0.5f * d.z * d.z;
    rgb[2] = 1.0f + 0.8f * d.x * d.y;
}

static void case_rotation(lg_test *t)
{
    float rot[9];
    lg_probe_rotation_from_euler(90, 30, 0, rot);
    write_probe(t, "p.exr", LG_PROBE_LATLONG, 256, 128, paint_pattern, NULL);
    write_probe(t, "pr.exr", LG_PROBE_LATLONG, 256, 128, paint_pattern, rot);
    coeffs a, b, c;
    if (!project(t, "file = \"p.exr\", rotate_deg = [90, 30, 0]", "bands = 4", &a) ||
        !project(t, "file = \"pr.exr\"", "bands = 4", &b) ||
        !project(t, "file = \"p.exr\"", "bands = 4", &c))
        return;
    double e = rel_rms(&a, &b), d = rel_rms(&c, &b);
    printf("rotation [90, 30, 0]: against the pattern drawn rotated %.2e, unrotated %.2e\n", e, d);
    LG_TEST_CHECK(t, e < 1e-3, "rotated probe vs the pattern drawn rotated: %.3g", e);
    LG_TEST_CHECK(t, d > 0.05, "the rotation changed nothing: %.3g", d);
}

static void case_window(lg_test *t)
{
    write_probe(t, "p.exr", LG_PROBE_LATLONG, 64, 32, paint_pattern, NULL);
    coeffs plain;
    if (!project(t, "file = \"p.exr\"", "bands = 5", &plain))
        return;
    LG_TEST_CHECK(t, !plain.windowed, "no window, yet the header says windowed");
    static const char *const names[] = { "hanning", "lanczos", "gaussian" };
    static const lg_sh_window_kind kinds[] = { LG_SH_WINDOW_HANNING, LG_SH_WINDOW_LANCZOS,
                                               LG_SH_WINDOW_GAUSSIAN };
    for (int w = 0; w < 3; w++) {
        char sh[128];
        snprintf(sh, sizeof sh, "bands = 5, window = %s, window_width = 3.5", names[w]);
        coeffs k;
        if (!project(t, "file = \"p.exr\"", sh, &k))
            continue;
        LG_TEST_CHECK(t, k.windowed, "%s: the header does not say windowed", names[w]);
        for (int ch = 0; ch < 3; ch++)
            for (int l = 0; l < 5; l++)
                for (int m = -l; m <= l; m++) {
                    uint32_t i = ch * 25 + lg_sh_index(l, m);
                    double f = lg_sh_window_factor(kinds[w], 3.5, (uint32_t)l);
                    double want = plain.c[i] * f;
                    LG_TEST_CHECK(t, fabs(k.c[i] - want) <= 1e-6 * fabs(plain.c[i]) + 1e-30,
                                  "%s: band %d coefficient %u = %.9g, want %.9g x %.6f", names[w],
                                  l, i, k.c[i], plain.c[i], f);
                }
        /* the window does something: band 4 shrinks */
        LG_TEST_CHECK(t, lg_sh_window_factor(kinds[w], 3.5, 4) < 0.5,
                      "%s: factor of band 4 is not small", names[w]);
    }
}

static void case_text(lg_test *t)
{
    write_probe(t, "p.exr", LG_PROBE_LATLONG, 32, 16, paint_pattern, NULL);
    coeffs k;
    if (!project(t, "file = \"p.exr\"", "bands = 6, sampler = sobol, samples = 50", &k))
        return;
    LG_TEST_CHECK(t, k.bands == 6 && k.nc == 36, "bands %u, %u per channel", k.bands, k.nc);
    /* every number as written is the shortest text that reads back to its float: reading
     * it as a float and writing it again with %.9g gives the same text */
    char *text = slurp(t, "light.txt");
    int numbers = 0;
    for (char *line = text ? strtok(text, "\n") : NULL; line; line = strtok(NULL, "\n")) {
        if (line[0] == '#')
            continue;
        char tok[3][64];
        if (sscanf(line, "%*u %*u %*d %63s %63s %63s", tok[0], tok[1], tok[2]) != 3) {
            LG_TEST_FAILF(t, "line '%s'", line);
            continue;
        }
        for (int c = 0; c < 3; c++) {
            float f = strtof(tok[c], NULL);
            char again[64];
            snprintf(again, sizeof again, "%.9g", (double)f);
            float g = strtof(again, NULL);
            LG_TEST_CHECK(t, strcmp(again, tok[c]) == 0 && memcmp(&f, &g, sizeof f) == 0,
                          "'%s' is not a float's %%.9g text ('%s')", tok[c], again);
            numbers++;
        }
    }
    free(text);
    LG_TEST_CHECK(t, numbers == 108, "%d numbers, want 108", numbers);
    /* render -o x.txt on a graph whose one output is SH */
    lg_test_write_text(t, "o.lgraph",
                       "lightgraph 1\nsky = probe { file = \"p.exr\" }\n"
                       "light = sh_project { probe = sky, bands = 2 }\n"
                       "output light \"light.txt\"\n");
    static const char *const args[] = { "-o", "other.txt", NULL };
    int rc = lg_test_render(t, "o.lgraph", args, NULL);
    coeffs o;
    LG_TEST_CHECK(t, rc == 0 && read_coeffs(t, "other.txt", &o) && o.bands == 2,
                  "render -o other.txt: exit %d", rc);
}

/* A render that must be refused (exit 2) with `want` in its message. */
static void refused(lg_test *t, const char *graph, const char *const *args, const char *want)
{
    lg_test_write_text(t, "bad.lgraph", graph);
    char *text = NULL;
    int rc = lg_test_render(t, "bad.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 2 && text && strstr(text, want),
                  "graph\n%s\nexit %d (want 2), message:\n%s\nwant: %s", graph, rc,
                  text ? text : "", want);
    free(text);
}

static void case_bad(lg_test *t)
{
    const float c[3] = { 1, 1, 1 };
    write_probe(t, "p.exr", LG_PROBE_LATLONG, 8, 4, paint_constant, c);
    static const struct {
        const char *set, *want;
    } bad[] = {
        { "bands = 0", "bands = 0 is out of range [1, 64]" },
        { "bands = 65", "bands = 65 is out of range [1, 64]" },
        { "samples = 0", "samples = 0 is out of range [1, 16384]" },
        { "samples = 100000", "samples = 100000 is out of range [1, 16384]" },
        { "seed = -1", "seed = -1 is out of range" },
        { "window_width = 0", "window_width = 0 is out of range" },
        { "window_width = nan", "only finite numbers are allowed" },
        { "sampler = montecarlo", "'montecarlo' is not one of quadrature, jittered, hammersley, "
                                  "sobol (parameter 'sampler' of node 'light')" },
        { "window = hannig", "did you mean 'hanning'?" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char g[512];
        snprintf(g, sizeof g,
                 "lightgraph 1\nsky = probe { file = \"p.exr\" }\n"
                 "light = sh_project { probe = sky, %s }\n"
                 "output light \"light.txt\"\n",
                 bad[i].set);
        refused(t, g, NULL, bad[i].want);
    }
    /* SH as an image, an image as text */
    refused(t,
            "lightgraph 1\nsky = probe { file = \"p.exr\" }\n"
            "light = sh_project { probe = sky }\noutput light \"light.exr\"\n",
            NULL,
            "'light' gives SH coefficients, which are written as text: name the file "
            ".txt, not 'light.exr'");
    refused(t, "lightgraph 1\nsky = probe { file = \"p.exr\" }\noutput sky \"sky.txt\"\n", NULL,
            "'sky' gives a light probe, which cannot be written as text ('sky.txt'): only SH "
            "coefficients are");
    static const char *const png[] = { "-o", "x.png", NULL };
    refused(t,
            "lightgraph 1\nsky = probe { file = \"p.exr\" }\n"
            "light = sh_project { probe = sky }\noutput light \"light.txt\"\n",
            png, "-o x.png: the graph's output 'light' gives SH coefficients");
    static const char *const txt[] = { "-o", "x.txt", NULL };
    refused(t, "lightgraph 1\nsky = probe { file = \"p.exr\" }\noutput sky \"sky.exr\"\n", txt,
            "-o x.txt: only SH coefficients are written as .txt");
    /* nothing half-written */
    FILE *f = fopen(lg_test_path(t, "light.txt"), "r");
    LG_TEST_CHECK(t, f == NULL, "a refused graph left light.txt behind");
    if (f)
        fclose(f);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "constant", case_constant },
        { "sign", case_sign },
        { "orthonormal", case_orthonormal },
        { "sky", case_sky },
        { "converge", case_converge },
        { "many", case_many },
        { "threads", case_threads },
        { "rotation", case_rotation },
        { "window", case_window },
        { "text", case_text },
        { "bad", case_bad },
    };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], NULL);
}
