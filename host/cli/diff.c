/*
 * lightgraph diff A B: compares two images (any format lg_image_read knows) with the
 * metrics of lg_image_compare, optionally writing a heat map and checking thresholds.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "lightgraph/image.h"
#include "exec/outputs.h"
#include "base/util.h"

static void diff_usage(FILE *f)
{
    fprintf(f,
            "usage: lightgraph diff A B [--heatmap OUT.png|OUT.exr] [--heat-max X] [--json]\n"
            "                         [--max-rmse X] [--max-abs X] [--ignore-nonfinite]\n"
            "\n"
            "Compares two images of the same size (.exr, .hdr, .pic, .png; PNG is decoded to\n"
            "linear) over their RGB channels: RMSE, PSNR (peak 1.0), mean and max absolute\n"
            "error, relative MSE (mean of (a-b)^2 / (b^2 + 1e-4), B being the reference).\n"
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
            "  --ignore-nonfinite\n"
            "                  pixels with NaN or Inf do not fail the comparison: the\n"
            "                  metrics are over the pixels finite in both images\n"
            "\n"
            "exit status: 0 ok, 1 a threshold exceeded, a pixel with NaN or Inf (without\n"
            "--ignore-nonfinite), no pixel finite in both, an image that cannot be read or\n"
            "sizes that differ, 2 bad usage\n");
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

int lg_cmd_diff(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL}, *heatmap = NULL;
    double heat_max = 0.0, max_rmse = -1.0, max_abs = -1.0;
    int json = 0, npaths = 0, options_done = 0, ignore_nonfinite = 0;

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (options_done || a[0] != '-' || !a[1]) {
            if (npaths == 2) {
                fprintf(stderr, "lightgraph diff: unexpected argument '%s' (two images only)\n", a);
                diff_usage(stderr);
                return 2;
            }
            paths[npaths++] = a;
            continue;
        }
        if (!strcmp(a, "--")) {
            options_done = 1;
            continue;
        }
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            diff_usage(stdout);
            return 0;
        }
        if (!strcmp(a, "--json")) {
            json = 1;
            continue;
        }
        if (!strcmp(a, "--ignore-nonfinite")) {
            ignore_nonfinite = 1;
            continue;
        }
        /* options with a value: "--opt VALUE" or "--opt=VALUE" */
        static const char *const valued[] = {"--heatmap", "--heat-max", "--max-rmse", "--max-abs"};
        const char *val = NULL;
        int which = -1;
        for (int k = 0; k < 4; k++) {
            size_t n = strlen(valued[k]);
            if (!strncmp(a, valued[k], n) && (a[n] == 0 || a[n] == '=')) {
                which = k;
                if (a[n] == '=')
                    val = a + n + 1;
                else if (i + 1 < argc)
                    val = argv[++i];
                break;
            }
        }
        if (which < 0) {
            fprintf(stderr, "lightgraph diff: unknown option '%s'\n", a);
            diff_usage(stderr);
            return 2;
        }
        if (!val) {
            fprintf(stderr, "lightgraph diff: %s needs a value\n", valued[which]);
            return 2;
        }
        if (which == 0) {
            if (lg_image_format_from_path(val) == LG_FILE_UNKNOWN) {
                fprintf(stderr, "lightgraph diff: --heatmap '%s': use a .png, .exr or .hdr name\n",
                        val);
                return 2;
            }
            heatmap = val;
        } else if (diff_number(valued[which], val,
                               which == 1 ? &heat_max : which == 2 ? &max_rmse : &max_abs)) {
            return 2;
        }
    }
    if (npaths != 2) {
        fprintf(stderr, "lightgraph diff: two images are needed\n");
        diff_usage(stderr);
        return 2;
    }

    lg_image img[2];
    lg_image_read_info info[2];
    memset(img, 0, sizeof img);
    char err[1024];
    int status = 0;
    /* the heat map's destination is checked before the images are read, by the rules of
     * every output (outputs.h) */
    lg_outputs *outs = NULL;
    if (heatmap) {
        outs = lg_outputs_new();
        if (lg_outputs_add(outs, heatmap, LG_OUTPUT_IMAGE, err, sizeof err)) {
            fprintf(stderr, "lightgraph diff: --heatmap: %s\n", err);
            status = 1;
            goto done;
        }
    }
    for (int k = 0; k < 2; k++) {
        if (lg_image_read(paths[k], 0, &img[k], &info[k], err, sizeof err) != LG_OK) {
            fprintf(stderr, "lightgraph diff: %s\n", err);
            status = 1;
            goto done;
        }
    }
    if (img[0].width != img[1].width || img[0].height != img[1].height) {
        fprintf(stderr, "lightgraph diff: images differ in size: '%s' is %ux%u, '%s' is %ux%u\n",
                paths[0], img[0].width, img[0].height, paths[1], img[1].width, img[1].height);
        status = 1;
        goto done;
    }

    lg_image heat;
    memset(&heat, 0, sizeof heat);
    lg_image_metrics m;
    if (lg_image_compare(&img[0], &img[1], &m, heatmap ? &heat : NULL, heat_max, err,
                         sizeof err) != LG_OK) {
        fprintf(stderr, "lightgraph diff: %s\n", err);
        status = 1;
        goto done;
    }
    if (heatmap) {
        lg_image_write_opts wo;
        memset(&wo, 0, sizeof wo);
        wo.channels = 3;
        int rc = lg_outputs_write_image(outs, heatmap, &heat, &wo, err, sizeof err);
        if (rc == 0)
            rc = lg_outputs_commit(outs, err, sizeof err);
        lg_image_free(&heat);
        if (rc != LG_OK) {
            fprintf(stderr, "lightgraph diff: %s\n", err);
            status = 1;
            goto done;
        }
    }

    /* Non-finite pixels first: metrics over what is left of the images must not read as a
     * clean result (all of B NaN gave "RMSE 0, PSNR inf"). */
    uint64_t total = (uint64_t)img[0].width * img[0].height;
    uint64_t bad[2] = {count_nonfinite(&img[0]), count_nonfinite(&img[1])};
    uint64_t compared = total - m.nonfinite;
    lg_str why = {0};
    if (!compared) /* a failure even with --ignore-nonfinite: there is no result */
        lg_str_addf(&why, "NaN or Inf in %llu of %llu pixels of A and %llu of B: no pixel is "
                          "finite in both images, nothing was compared",
                    (unsigned long long)bad[0], (unsigned long long)total,
                    (unsigned long long)bad[1]);
    else if (m.nonfinite && !ignore_nonfinite)
        lg_str_addf(&why,
                    "NaN or Inf in %llu of %llu pixels of A and %llu of B: the metrics cover "
                    "only the %llu pixels finite in both (--ignore-nonfinite accepts that)",
                    (unsigned long long)bad[0], (unsigned long long)total,
                    (unsigned long long)bad[1], (unsigned long long)compared);

    /* thresholds */
    if (max_rmse >= 0.0 && m.rmse > max_rmse)
        lg_str_addf(&why, "%sRMSE %.6g exceeds --max-rmse %.6g", why.len ? "; " : "", m.rmse,
                    max_rmse);
    if (max_abs >= 0.0 && m.max_abs > max_abs)
        lg_str_addf(&why, "%smax abs error %.6g exceeds --max-abs %.6g", why.len ? "; " : "",
                    m.max_abs, max_abs);
    int failed = why.len > 0;

    if (json) {
        lg_str b = {0};
        lg_str_add(&b, "{\"a\": ");
        lg_str_add_json(&b, paths[0]);
        lg_str_add(&b, ", \"b\": ");
        lg_str_add_json(&b, paths[1]);
        lg_str_addf(&b, ", \"width\": %u, \"height\": %u", img[0].width, img[0].height);
        lg_str_addf(&b, ", \"nonfinite_a\": %llu, \"nonfinite_b\": %llu, \"nonfinite\": %llu, "
                        "\"compared\": %llu",
                    (unsigned long long)bad[0], (unsigned long long)bad[1],
                    (unsigned long long)m.nonfinite, (unsigned long long)compared);
        /* nothing compared: no metric, rather than the zeros of an empty sum */
        double none = compared ? 0.0 : NAN;
        json_number(&b, "rmse", m.rmse + none);
        json_number(&b, "psnr", m.psnr + none);
        json_number(&b, "mean_abs", m.mean_abs + none);
        json_number(&b, "max_abs", m.max_abs + none);
        json_number(&b, "rel_mse", m.rel_mse + none);
        if (heatmap) {
            lg_str_add(&b, ", \"heatmap\": ");
            lg_str_add_json(&b, heatmap);
        }
        lg_str_addf(&b, ", \"pass\": %s", failed ? "false" : "true");
        lg_str_add(&b, "}\n");
        fputs(b.s, stdout);
        lg_str_free(&b);
    } else {
        for (int k = 0; k < 2; k++)
            printf("%s          %s (%ux%u %s, %u channel%s, %u-bit, %s)\n", k ? "B" : "A", paths[k],
                   img[k].width, img[k].height, format_name(info[k].format), info[k].channels,
                   info[k].channels == 1 ? "" : "s", info[k].bits, info[k].compression);
        printf("nonfinite  A %llu, B %llu of %llu pixel%s (NaN or Inf in R, G or B)\n",
               (unsigned long long)bad[0], (unsigned long long)bad[1],
               (unsigned long long)total, total == 1 ? "" : "s");
        if (m.nonfinite)
            printf("compared   %llu of %llu pixels (finite in both images)\n",
                   (unsigned long long)compared, (unsigned long long)total);
        if (!compared) {
            printf("RMSE       n/a (no pixel is finite in both images)\n");
        } else {
            printf("RMSE       %.6g\n", m.rmse);
            if (isfinite(m.psnr))
                printf("PSNR       %.2f dB\n", m.psnr);
            else
                printf("PSNR       inf (no difference%s)\n",
                       m.nonfinite ? " in the pixels compared" : "");
            printf("mean abs   %.6g\n", m.mean_abs);
            printf("max abs    %.6g\n", m.max_abs);
            printf("rel MSE    %.6g\n", m.rel_mse);
        }
        if (heatmap)
            printf("heat map   %s (white = %.6g)\n", heatmap, heat_max > 0.0 ? heat_max : m.max_abs);
    }
    fflush(stdout);
    if (failed) {
        fprintf(stderr, "lightgraph diff: %s\n", why.s);
        status = 1;
    }
    lg_str_free(&why);

done:
    lg_outputs_free(&outs);
    lg_image_free(&img[0]);
    lg_image_free(&img[1]);
    return status;
}
