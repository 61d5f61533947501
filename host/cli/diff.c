/*
 * lightgraph diff A B: compares two images (any format lg_image_read knows) with the
 * metrics sweep and tune share (cli/metric.h: lg_image_compare's, relative RMSE and SSIM),
 * optionally writing a heat map and checking thresholds.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/metric.h"
#include "lightgraph/image.h"
#include "exec/outputs.h"
#include "base/util.h"

static void diff_usage(FILE *f)
{
    fprintf(f,
            "usage: lightgraph diff A B [--heatmap OUT.png|OUT.exr] [--heat-max X] [--json]\n"
            "                         [--max-rmse X] [--max-abs X] [--max-error X [--metric M]]\n"
            "                         [--ignore-nonfinite]\n"
            "\n"
            "Compares two images of the same size (.exr, .hdr, .pic, .png; PNG is decoded to\n"
            "linear) over their RGB channels: RMSE, PSNR (peak 1.0), mean and max absolute\n"
            "error, relative MSE (mean of (a-b)^2 / (b^2 + 1e-4), B being the reference),\n"
            "relative RMSE (RMSE / the RMS of B) and SSIM (Wang et al. 2004, on the luminance,\n"
            "11x11 Gaussian windows, dynamic range B's brightest pixel; n/a for images under\n"
            "11x11) with DSSIM = 1 - SSIM: the metrics sweep and tune report.\n"
            "\n"
            "Pixels with NaN or Inf in R, G or B are counted first, in A and in B, and left out\n"
            "of the metrics: any such pixel fails the comparison (exit 1) unless\n"
            "--ignore-nonfinite is given. With it the metrics cover the pixels finite in both\n"
            "images (the counts are still printed); when no pixel is, nothing is compared and\n"
            "the exit status is 1.\n"
            "\n"
            "  --heatmap OUT   write the per-pixel error (max over RGB) as a colour ramp:\n"
            "                  black, blue, red, yellow, white; non-finite pixels magenta\n"
            "  --heat-max X    error shown as white (default: the largest error found)\n"
            "  --json          print one JSON object instead of text (PSNR null if infinite)\n"
            "  --max-rmse X    fail (exit 1) if RMSE > X\n"
            "  --max-abs X     fail (exit 1) if max abs error > X\n"
            "  --max-error X   fail (exit 1) if the error --metric names is > X (or is n/a)\n"
            "  --metric M      the error --max-error checks (default rmse): one of\n"
            "                  %s\n"
            "  --ignore-nonfinite\n"
            "                  pixels with NaN or Inf do not fail the comparison: the\n"
            "                  metrics are over the pixels finite in both images\n"
            "\n"
            "exit status: 0 ok, 1 a threshold exceeded, a pixel with NaN or Inf (without\n"
            "--ignore-nonfinite), no pixel finite in both, an image that cannot be read or\n"
            "sizes that differ, 2 bad usage\n",
            lg_metric_names());
}

/* A non-negative finite number, or -1 with a message. */
static int diff_number(const char *opt, const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = s ? strtod(s, &end) : 0.0;
    if (!s || !*s || *end || errno || !isfinite(v) || v < 0.0) {
        fprintf(stderr, "lightgraph diff: %s needs a non-negative number, not '%s'\n", opt,
                s ? s : "");
        return -1;
    }
    *out = v;
    return 0;
}

static const char *format_name(lg_file_format f)
{
    switch (f) {
    case LG_FILE_EXR: return "exr";
    case LG_FILE_HDR: return "hdr";
    case LG_FILE_PNG: return "png";
    default: return "?";
    }
}

/* Pixels with NaN or Inf in R, G or B: the pixels lg_image_compare leaves out when either
 * image has one (alpha is not compared, so it does not count). */
static uint64_t count_nonfinite(const lg_image *img)
{
    uint64_t k = 0;
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++) {
        const float *p = img->pixels + i * 4;
        k += !(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]));
    }
    return k;
}

static void json_number(lg_str *b, const char *key, double v)
{
    if (isfinite(v))
        lg_str_addf(b, ", \"%s\": %.9g", key, v);
    else
        lg_str_addf(b, ", \"%s\": null", key);
}

/* What the command line says. */
typedef struct diff_args {
    const char *paths[2], *heatmap;
    double heat_max, max_rmse, max_abs, max_error; /* the thresholds: -1 when not given */
    lg_metric_id metric;                           /* what --max-error checks */
    const char *metric_arg;                        /* --metric as given, NULL if not */
    bool json, ignore_nonfinite;
} diff_args;

/* diff's options, in the order of diff_opt: the valued ones take "--opt VALUE" or
 * "--opt=VALUE"; --heatmap and --metric are the values that are not numbers */
static const lg_option diff_opts[] = {
    { "--heatmap", NULL, LG_OPT_VALUE | LG_OPT_JOINED },
    { "--heat-max", NULL, LG_OPT_VALUE | LG_OPT_JOINED },
    { "--max-rmse", NULL, LG_OPT_VALUE | LG_OPT_JOINED },
    { "--max-abs", NULL, LG_OPT_VALUE | LG_OPT_JOINED },
    { "--max-error", NULL, LG_OPT_VALUE | LG_OPT_JOINED },
    { "--metric", NULL, LG_OPT_VALUE | LG_OPT_JOINED },
    { "--json", NULL, 0 },
    { "--ignore-nonfinite", NULL, 0 },
    { "-h", "--help", 0 },
    { "--", NULL, 0 },
};
enum diff_opt {
    OPT_HEATMAP,
    OPT_HEAT_MAX,
    OPT_MAX_RMSE,
    OPT_MAX_ABS,
    OPT_MAX_ERROR,
    OPT_METRIC,
    OPT_JSON,
    OPT_IGNORE_NONFINITE,
    OPT_HELP,
    OPT_END,
    N_DIFF_OPTS
};
_Static_assert(sizeof diff_opts / sizeof diff_opts[0] == N_DIFF_OPTS, "diff_opts");

/* Parses argv[1 .. argc-1] into *o. Returns -1 to go on, else the exit status (0 after
 * --help; 2 after the message, and the usage where the mistake is the command's shape). */
static int parse_diff_args(int argc, char **argv, diff_args *o)
{
    memset(o, 0, sizeof *o);
    o->max_rmse = o->max_abs = o->max_error = -1.0;
    o->metric = LG_METRIC_RMSE;
    double *const number[] = { NULL, &o->heat_max, &o->max_rmse, &o->max_abs, &o->max_error };
    int npaths = 0;
    bool options_done = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *val;
        if (options_done || a[0] != '-' || !a[1]) {
            if (npaths == 2) {
                fprintf(stderr, "lightgraph diff: unexpected argument '%s' (two images only)\n", a);
                diff_usage(stderr);
                return 2;
            }
            o->paths[npaths++] = a;
            continue;
        }
        int which = lg_option_find(diff_opts, N_DIFF_OPTS, argc, argv, &i, &val);
        switch (which) {
        case LG_OPT_UNKNOWN:
            fprintf(stderr, "lightgraph diff: unknown option '%s'\n", a);
            diff_usage(stderr);
            return 2;
        case LG_OPT_NO_VALUE: fprintf(stderr, "lightgraph diff: %s needs a value\n", a); return 2;
        case OPT_END: options_done = true; break;
        case OPT_HELP: diff_usage(stdout); return 0;
        case OPT_JSON: o->json = true; break;
        case OPT_IGNORE_NONFINITE: o->ignore_nonfinite = true; break;
        case OPT_HEATMAP:
            if (lg_image_format_from_path(val) == LG_FILE_UNKNOWN) {
                fprintf(stderr, "lightgraph diff: --heatmap '%s': use a .png, .exr or .hdr name\n",
                        val);
                return 2;
            }
            o->heatmap = val;
            break;
        case OPT_METRIC:
            if (lg_metric_parse(val, &o->metric)) {
                fprintf(stderr, "lightgraph diff: --metric wants one of %s, got '%s'\n",
                        lg_metric_names(), val);
                return 2;
            }
            o->metric_arg = val;
            break;
        default: /* the thresholds */
            if (diff_number(diff_opts[which].name, val, number[which]))
                return 2;
            break;
        }
    }
    if (npaths != 2) {
        fprintf(stderr, "lightgraph diff: two images are needed\n");
        diff_usage(stderr);
        return 2;
    }
    /* every metric is printed anyway: a --metric alone would check nothing, silently */
    if (o->metric_arg && o->max_error < 0.0) {
        fprintf(stderr,
                "lightgraph diff: --metric %s names the error --max-error checks, and no "
                "--max-error is given\n",
                o->metric_arg);
        return 2;
    }
    return -1;
}

/* Prints "lightgraph diff: [what: ]err" and returns 1, the status of every failure to
 * read, compare or write. */
static int diff_fail(const char *what, const char *err)
{
    fprintf(stderr, "lightgraph diff: %s%s%s\n", what ? what : "", what ? ": " : "", err);
    return 1;
}

/* Reads both images, the same size. Returns 0, or 1 (printed). */
static int read_pair(const diff_args *o, lg_image img[2], lg_image_read_info info[2])
{
    char err[1024];
    for (int k = 0; k < 2; k++)
        if (lg_image_read(o->paths[k], 0, &img[k], &info[k], err, sizeof err) != LG_OK)
            return diff_fail(NULL, err);
    if (img[0].width != img[1].width || img[0].height != img[1].height) {
        fprintf(stderr, "lightgraph diff: images differ in size: '%s' is %ux%u, '%s' is %ux%u\n",
                o->paths[0], img[0].width, img[0].height, o->paths[1], img[1].width, img[1].height);
        return 1;
    }
    return 0;
}

/* Writes the heat map (RGB) into its temporary and commits it. Returns 0, or 1 (printed). */
static int write_heatmap(lg_outputs *outs, const char *path, const lg_image *heat)
{
    char err[1024];
    lg_image_write_opts wo;
    memset(&wo, 0, sizeof wo);
    wo.channels = 3;
    int rc = lg_outputs_write_image(outs, path, heat, &wo, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_commit(outs, err, sizeof err);
    return rc != LG_OK ? diff_fail(NULL, err) : 0;
}

/* What was compared: the metrics, the non-finite pixels of A and B, and why it fails
 * (empty when it passes). */
typedef struct diff_result {
    lg_image_metrics m; /* ms.base */
    lg_metric_set ms;
    uint64_t total, bad[2], compared;
    lg_str why;
} diff_result;

/* Why an SSIM is n/a (NaN): the images are under the window, or every window holds a pixel
 * that is not finite in both. */
static const char *ssim_why_not(const lg_image img[2])
{
    if (img[0].width < LG_SSIM_WINDOW || img[0].height < LG_SSIM_WINDOW)
        return "the images are smaller than SSIM's 11x11 window";
    return "every 11x11 window holds a pixel with NaN or Inf";
}

/* Why the comparison fails, into r->why: non-finite pixels first (metrics over what is left
 * of the images must not read as a clean result: all of B NaN gave "RMSE 0, PSNR inf"),
 * then the thresholds. */
static void judge(const diff_args *o, const lg_image img[2], diff_result *r)
{
    const lg_image_metrics *m = &r->m;
    r->total = (uint64_t)img[0].width * img[0].height;
    r->bad[0] = count_nonfinite(&img[0]);
    r->bad[1] = count_nonfinite(&img[1]);
    r->compared = r->total - m->nonfinite;
    lg_str *why = &r->why;
    if (!r->compared) /* a failure even with --ignore-nonfinite: there is no result */
        lg_str_addf(why,
                    "NaN or Inf in %llu of %llu pixels of A and %llu of B: no pixel is "
                    "finite in both images, nothing was compared",
                    (unsigned long long)r->bad[0], (unsigned long long)r->total,
                    (unsigned long long)r->bad[1]);
    else if (m->nonfinite && !o->ignore_nonfinite)
        lg_str_addf(why,
                    "NaN or Inf in %llu of %llu pixels of A and %llu of B: the metrics cover "
                    "only the %llu pixels finite in both (--ignore-nonfinite accepts that)",
                    (unsigned long long)r->bad[0], (unsigned long long)r->total,
                    (unsigned long long)r->bad[1], (unsigned long long)r->compared);
    if (o->max_rmse >= 0.0 && m->rmse > o->max_rmse)
        lg_str_addf(why, "%sRMSE %.6g exceeds --max-rmse %.6g", why->len ? "; " : "", m->rmse,
                    o->max_rmse);
    if (o->max_abs >= 0.0 && m->max_abs > o->max_abs)
        lg_str_addf(why, "%smax abs error %.6g exceeds --max-abs %.6g", why->len ? "; " : "",
                    m->max_abs, o->max_abs);
    double e = lg_metric_value(&r->ms, o->metric);
    if (o->max_error >= 0.0 && r->compared && isnan(e)) /* dssim without a window */
        lg_str_addf(why, "%s%s is n/a (%s), so --max-error %.6g cannot be checked",
                    why->len ? "; " : "", lg_metric_name(o->metric), ssim_why_not(img),
                    o->max_error);
    else if (o->max_error >= 0.0 && r->compared && e > o->max_error)
        lg_str_addf(why, "%s%s %.6g exceeds --max-error %.6g", why->len ? "; " : "",
                    lg_metric_name(o->metric), e, o->max_error);
}

static void print_json(const diff_args *o, const lg_image img[2], const diff_result *r)
{
    const lg_image_metrics *m = &r->m;
    lg_str b = { 0 };
    lg_str_add(&b, "{\"a\": ");
    lg_str_add_json(&b, o->paths[0]);
    lg_str_add(&b, ", \"b\": ");
    lg_str_add_json(&b, o->paths[1]);
    lg_str_addf(&b, ", \"width\": %u, \"height\": %u", img[0].width, img[0].height);
    lg_str_addf(&b,
                ", \"nonfinite_a\": %llu, \"nonfinite_b\": %llu, \"nonfinite\": %llu, "
                "\"compared\": %llu",
                (unsigned long long)r->bad[0], (unsigned long long)r->bad[1],
                (unsigned long long)m->nonfinite, (unsigned long long)r->compared);
    /* nothing compared: no metric, rather than the zeros of an empty sum */
    double none = r->compared ? 0.0 : NAN;
    json_number(&b, "rmse", m->rmse + none);
    json_number(&b, "psnr", m->psnr + none);
    json_number(&b, "mean_abs", m->mean_abs + none);
    json_number(&b, "max_abs", m->max_abs + none);
    json_number(&b, "rel_mse", m->rel_mse + none);
    json_number(&b, "rel_rmse", r->ms.rel_rmse + none);
    json_number(&b, "ssim", r->ms.ssim + none);
    json_number(&b, "dssim", 1.0 - r->ms.ssim + none);
    if (o->heatmap) {
        lg_str_add(&b, ", \"heatmap\": ");
        lg_str_add_json(&b, o->heatmap);
    }
    lg_str_addf(&b, ", \"pass\": %s", r->why.len ? "false" : "true");
    lg_str_add(&b, "}\n");
    fputs(b.s, stdout);
    lg_str_free(&b);
}

static void print_text(const diff_args *o, const lg_image img[2], const lg_image_read_info info[2],
                       const diff_result *r)
{
    const lg_image_metrics *m = &r->m;
    for (int k = 0; k < 2; k++)
        printf("%s          %s (%ux%u %s, %u channel%s, %u-bit, %s)\n", k ? "B" : "A", o->paths[k],
               img[k].width, img[k].height, format_name(info[k].format), info[k].channels,
               info[k].channels == 1 ? "" : "s", info[k].bits, info[k].compression);
    printf("nonfinite  A %llu, B %llu of %llu pixel%s (NaN or Inf in R, G or B)\n",
           (unsigned long long)r->bad[0], (unsigned long long)r->bad[1],
           (unsigned long long)r->total, r->total == 1 ? "" : "s");
    if (m->nonfinite)
        printf("compared   %llu of %llu pixels (finite in both images)\n",
               (unsigned long long)r->compared, (unsigned long long)r->total);
    if (!r->compared) {
        printf("RMSE       n/a (no pixel is finite in both images)\n");
    } else {
        printf("RMSE       %.6g\n", m->rmse);
        if (isfinite(m->psnr))
            printf("PSNR       %.2f dB\n", m->psnr);
        else
            printf("PSNR       inf (no difference%s)\n",
                   m->nonfinite ? " in the pixels compared" : "");
        printf("mean abs   %.6g\n", m->mean_abs);
        printf("max abs    %.6g\n", m->max_abs);
        printf("rel MSE    %.6g\n", m->rel_mse);
        printf("rel RMSE   %.6g\n", r->ms.rel_rmse);
        if (isnan(r->ms.ssim))
            printf("SSIM       n/a (%s)\n", ssim_why_not(img));
        else if (r->ms.ssim_skipped)
            printf("SSIM       %.6f (DSSIM %.6g; %llu of %llu windows left out for NaN or Inf)\n",
                   r->ms.ssim, 1.0 - r->ms.ssim, (unsigned long long)r->ms.ssim_skipped,
                   (unsigned long long)(r->ms.ssim_skipped + r->ms.ssim_windows));
        else
            printf("SSIM       %.6f (DSSIM %.6g)\n", r->ms.ssim, 1.0 - r->ms.ssim);
    }
    if (o->heatmap)
        printf("heat map   %s (white = %.6g)\n", o->heatmap,
               o->heat_max > 0.0 ? o->heat_max : m->max_abs);
}

/* Reads, compares, writes the heat map and judges; prints the result. Returns the exit
 * status. */
static int run_diff(const diff_args *o, lg_outputs *outs, lg_image img[2])
{
    lg_image_read_info info[2];
    char err[1024];
    if (read_pair(o, img, info))
        return 1;
    lg_image heat;
    memset(&heat, 0, sizeof heat);
    diff_result r;
    memset(&r, 0, sizeof r);
    if (lg_metrics_compute(&img[0], &img[1], &r.ms, o->heatmap ? &heat : NULL, o->heat_max, err,
                           sizeof err) != 0)
        return diff_fail(NULL, err);
    r.m = r.ms.base;
    if (o->heatmap) {
        int rc = write_heatmap(outs, o->heatmap, &heat);
        lg_image_free(&heat);
        if (rc)
            return rc;
    }
    judge(o, img, &r);
    if (o->json)
        print_json(o, img, &r);
    else
        print_text(o, img, info, &r);
    fflush(stdout);
    int status = 0;
    if (r.why.len) {
        diff_fail(NULL, r.why.s);
        status = 1;
    }
    lg_str_free(&r.why);
    return status;
}

int lg_cmd_diff(int argc, char **argv)
{
    diff_args o;
    int status = parse_diff_args(argc, argv, &o);
    if (status >= 0)
        return status;
    lg_image img[2];
    memset(img, 0, sizeof img);
    char err[1024];
    /* the heat map's destination is checked before the images are read, by the rules of
     * every output (outputs.h) */
    lg_outputs *outs = NULL;
    if (o.heatmap) {
        outs = lg_outputs_new();
        if (lg_outputs_add(outs, o.heatmap, LG_OUTPUT_IMAGE, err, sizeof err))
            status = diff_fail("--heatmap", err);
    }
    if (status < 0)
        status = run_diff(&o, outs, img);
    lg_outputs_free(&outs);
    lg_image_free(&img[0]);
    lg_image_free(&img[1]);
    return status;
}
