/*
 * `lightgraph diff` (host/cli/diff.c), called in-process with stdout and stderr captured:
 * text and JSON output, thresholds, heat maps, and the exit statuses (0, 1, 2); pixels
 * with NaN or Inf counted per image and failing unless --ignore-nonfinite (an all-NaN B
 * once read "RMSE 0, PSNR inf (no difference)" with exit 0).
 */
#include <fcntl.h>
#include <stdarg.h>
#include <math.h>
#include <string.h>
#include <unistd.h>

#include "codectest.h"
#include "cli/commands.h"
#include "lightgraph/image.h"

static char scratch[4096];
static char out_buf[16384], err_buf[16384];

static void slurp_into(const char *path, char *buf, size_t n)
{
    FILE *f = fopen(path, "rb");
    size_t k = f ? fread(buf, 1, n - 1, f) : 0;
    buf[k] = 0;
    if (f)
        fclose(f);
}

/* Runs lg_cmd_diff with the NULL-terminated arguments after "diff". */
static int run(const char *first, ...)
{
    char *argv[32];
    int argc = 0;
    argv[argc++] = "diff";
    va_list ap;
    va_start(ap, first);
    for (const char *a = first; a && argc < 31; a = va_arg(ap, const char *))
        argv[argc++] = (char *)a;
    va_end(ap);
    argv[argc] = NULL;

    char outp[4200], errp[4200];
    snprintf(outp, sizeof outp, "%s/stdout", scratch);
    snprintf(errp, sizeof errp, "%s/stderr", scratch);
    fflush(stdout);
    fflush(stderr);
    int so = dup(1), se = dup(2);
    int fo = open(outp, O_WRONLY | O_CREAT | O_TRUNC, 0644),
        fe = open(errp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fo, 1);
    dup2(fe, 2);
    int rc = lg_cmd_diff(argc, argv);
    fflush(stdout);
    fflush(stderr);
    dup2(so, 1);
    dup2(se, 2);
    close(so);
    close(se);
    close(fo);
    close(fe);
    slurp_into(outp, out_buf, sizeof out_buf);
    slurp_into(errp, err_buf, sizeof err_buf);
    return rc;
}

/* w x h pixels of v (alpha 1), the first `nbump` pixels' red channel plus `bump`. */
static void write_img_n(const char *name, uint32_t w, uint32_t h, float v, float bump, size_t nbump,
                        char *path)
{
    lg_image img;
    char err[512];
    lg_image_alloc(&img, w, h);
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        img.pixels[i] = (i % 4 == 3) ? 1.0f : v;
    for (size_t i = 0; i < nbump; i++)
        img.pixels[4 * i] += bump;
    sprintf(path, "%s/%s", scratch, name);
    lg_image_write_opts o = { .exr_pixel = LG_EXR_FLOAT };
    if (lg_image_write(path, &img, &o, err, sizeof err))
        fprintf(stderr, "setup: %s\n", err);
    lg_image_free(&img);
}

static void write_img(const char *name, uint32_t w, uint32_t h, float v, float bump, char *path)
{
    write_img_n(name, w, h, v, bump, 1, path);
}

int main(void)
{
    snprintf(scratch, sizeof scratch, "%s", make_scratch("codecs-diff"));
    char a[4300], b[4300], c[4300], small[4300], nan[4300], heat[4300], missing[4300], bad[4300];
    char allnan[4300], someinf[4300];
    write_img("a.exr", 16, 8, 0.5f, 0.0f, a);
    write_img("b.exr", 16, 8, 0.5f, 0.25f, b); /* one channel of one pixel off by 0.25 */
    write_img("c.hdr", 16, 8, 0.5f, 0.0f, c);  /* 0.5 is exact in RGBE */
    write_img("small.exr", 4, 8, 0.5f, 0.0f, small);
    write_img("nan.exr", 16, 8, 0.5f, NAN, nan);
    write_img_n("allnan.exr", 16, 8, 0.5f, NAN, 16 * 8, allnan);   /* every pixel NaN */
    write_img_n("someinf.exr", 16, 8, 0.5f, INFINITY, 3, someinf); /* 3 pixels +Inf */
    snprintf(heat, sizeof heat, "%s/heat.png", scratch);
    snprintf(missing, sizeof missing, "%s/missing.exr", scratch);
    snprintf(bad, sizeof bad, "%s/bad.exr", scratch);
    FILE *f = fopen(bad, "wb");
    fputs("not an exr", f);
    fclose(f);

    /* identical, text output */
    int rc = run(a, c, NULL);
    CHECKF(rc == 0, "rc %d: %s", rc, err_buf);
    CHECKF(strstr(out_buf, "RMSE       0\n") &&
               strstr(out_buf, "PSNR       inf (no difference)\n") &&
               strstr(out_buf, "nonfinite  A 0, B 0 of 128 pixels") && !strstr(out_buf, "compared"),
           "%s", out_buf);

    /* a difference, JSON output */
    rc = run("--json", a, b, NULL);
    CHECKF(rc == 0, "rc %d: %s", rc, err_buf);
    double rmse = sqrt(0.0625 / (16 * 8 * 3));
    char want[128];
    snprintf(want, sizeof want, "\"rmse\": %.9g", rmse);
    CHECKF(strstr(out_buf, want) && strstr(out_buf, "\"max_abs\": 0.25") &&
               strstr(out_buf, "\"width\": 16, \"height\": 8") &&
               strstr(out_buf, "\"nonfinite\": 0") &&
               strstr(out_buf, "\"nonfinite_a\": 0, \"nonfinite_b\": 0") &&
               strstr(out_buf, "\"compared\": 128") && out_buf[0] == '{' &&
               strstr(out_buf, "\"pass\": true"),
           "%s", out_buf);

    /* thresholds */
    CHECK(run(a, b, "--max-abs", "0.3", NULL) == 0);
    CHECK(run(a, b, "--max-abs=0.2", NULL) == 1 && strstr(err_buf, "exceeds --max-abs"));
    CHECK(run(a, b, "--max-rmse", "0.001", "--json", NULL) == 1 &&
          strstr(out_buf, "\"pass\": false") && strstr(err_buf, "RMSE"));
    CHECK(run(a, b, "--max-rmse", "0.1", "--json", NULL) == 0 && strstr(out_buf, "\"pass\": true"));

    /* NaN and Inf: counted per image, said before the metrics, and failing unless
     * --ignore-nonfinite */
    rc = run(a, nan, NULL);
    CHECKF(rc == 1 && strstr(out_buf, "nonfinite  A 0, B 1 of 128 pixels") &&
               strstr(out_buf, "compared   127 of 128 pixels") &&
               strstr(err_buf, "NaN or Inf in 0 of 128 pixels of A and 1 of B") &&
               strstr(err_buf, "--ignore-nonfinite"),
           "%d %s %s", rc, out_buf, err_buf);
    CHECK(run(a, nan, "--max-rmse", "1", NULL) == 1 && strstr(err_buf, "NaN or Inf"));
    rc = run(a, nan, "--ignore-nonfinite", NULL);
    CHECKF(rc == 0 && strstr(out_buf, "nonfinite  A 0, B 1 of 128 pixels") &&
               strstr(out_buf, "PSNR       inf (no difference in the pixels compared)") &&
               !err_buf[0],
           "%d %s %s", rc, out_buf, err_buf);
    CHECK(run(a, nan, "--ignore-nonfinite", "--max-rmse", "1", NULL) == 0);
    /* every pixel of B NaN: said first, no metric, exit 1 even when ignoring non-finite */
    rc = run(a, allnan, NULL);
    const char *said = strstr(out_buf, "nonfinite  A 0, B 128 of 128 pixels");
    const char *metric = strstr(out_buf, "RMSE");
    CHECKF(rc == 1 && said && metric && said < metric &&
               strstr(out_buf, "RMSE       n/a (no pixel is finite in both images)") &&
               !strstr(out_buf, "PSNR") && !strstr(out_buf, "no difference") &&
               strstr(err_buf, "NaN or Inf in 0 of 128 pixels of A and 128 of B") &&
               strstr(err_buf, "nothing was compared") && !strstr(err_buf, "accepts"),
           "%d %s %s", rc, out_buf, err_buf);
    rc = run(allnan, a, "--ignore-nonfinite", NULL);
    CHECKF(rc == 1 && strstr(out_buf, "nonfinite  A 128, B 0 of 128 pixels") &&
               strstr(err_buf, "no pixel is finite in both images") &&
               strstr(err_buf, "nothing was compared"),
           "%d %s %s", rc, out_buf, err_buf);
    rc = run("--json", a, allnan, NULL);
    CHECKF(rc == 1 &&
               strstr(out_buf, "\"nonfinite_a\": 0, \"nonfinite_b\": 128, \"nonfinite\": 128") &&
               strstr(out_buf, "\"compared\": 0") && strstr(out_buf, "\"rmse\": null") &&
               strstr(out_buf, "\"psnr\": null") && strstr(out_buf, "\"pass\": false"),
           "%d %s", rc, out_buf);
    /* both images have some: each counted on its own, the union left out */
    rc = run("--json", nan, someinf, "--ignore-nonfinite", NULL);
    CHECKF(rc == 0 && strstr(out_buf, "\"nonfinite_a\": 1, \"nonfinite_b\": 3, \"nonfinite\": 3") &&
               strstr(out_buf, "\"compared\": 125") && strstr(out_buf, "\"pass\": true"),
           "%d %s", rc, out_buf);
    CHECK(run(someinf, a, "--ignore-nonfinite", "--json", NULL) == 0 &&
          strstr(out_buf, "\"nonfinite_a\": 3, \"nonfinite_b\": 0"));
    CHECK(run(someinf, a, NULL) == 1 && strstr(err_buf, "3 of 128 pixels of A and 0 of B"));

    /* heat map */
    rc = run(a, b, "--heatmap", heat, NULL);
    CHECKF(rc == 0, "%s", err_buf);
    lg_image h;
    char err[512];
    CHECKF(lg_image_read(heat, 0, &h, NULL, err, sizeof err) == 0, "%s", err);
    CHECK(h.width == 16 && h.height == 8 && h.pixels[0] == 1.0f && h.pixels[4] == 0.0f);
    lg_image_free(&h);

    /* failures: sizes, unreadable files */
    rc = run(a, small, NULL);
    CHECKF(rc == 1 && strstr(err_buf, "16x8") && strstr(err_buf, "4x8"), "%d %s", rc, err_buf);
    rc = run(a, missing, NULL);
    CHECKF(rc == 1 && strstr(err_buf, "missing.exr") && strstr(err_buf, "No such file"), "%d %s",
           rc, err_buf);
    rc = run(bad, a, NULL);
    CHECKF(rc == 1 && strstr(err_buf, "bad.exr") && strstr(err_buf, "not an OpenEXR"), "%d %s", rc,
           err_buf);

    /* usage */
    CHECK(run(a, NULL) == 2);
    CHECK(run(a, b, c, NULL) == 2);
    CHECK(run(a, b, "--frobnicate", NULL) == 2 && strstr(err_buf, "--frobnicate"));
    CHECK(run(a, b, "--max-rmse", NULL) == 2);
    CHECK(run(a, b, "--max-rmse", "abc", NULL) == 2 && strstr(err_buf, "abc"));
    CHECK(run(a, b, "--heat-max", "-1", NULL) == 2);
    CHECK(run(a, b, "--heatmap", "x.jpg", NULL) == 2);
    CHECK(run("--help", NULL) == 0 && strstr(out_buf, "usage: lightgraph diff"));

    return check_report_scratch("diff", scratch);
}
