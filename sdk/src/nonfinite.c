/* lightgraph/image.h, "non-finite pixels": the one count and the one warning every node
 * gives for NaN and Inf pixels, so that `image` and the nodes that pass images on say it
 * alike (a copy per node drifts in wording and in what it counts). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>

#include "lightgraph/host.h"
#include "lightgraph/image.h"

uint64_t lg_pixels_nonfinite(const float *rgba, uint32_t width, uint32_t height, size_t row_pixels)
{
    if (!rgba)
        return 0;
    uint64_t bad = 0;
    for (uint32_t y = 0; y < height; y++) {
        const float *p = rgba + 4 * (size_t)y * row_pixels;
        for (uint32_t x = 0; x < width; x++, p += 4)
            /* a sum is non-finite iff a term is, unless finite terms overflow: test each */
            bad += !isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || !isfinite(p[3]);
    }
    return bad;
}

void lg_warn_nonfinite(lg_node *n, const char *what, uint64_t count, const char *fate)
{
    if (count)
        lg_log(n, LG_LOG_WARN, "%s: %" PRIu64 " pixel%s with a NaN or Inf channel, %s", what, count,
               count == 1 ? "" : "s", fate);
}

int lg_check_input_finite(lg_node *n, const lg_frame *frame, uint32_t port, const char *port_name,
                          const char *fate, bool *reported)
{
    if (*reported)
        return 0;
    const lg_resource *r = lg_input(n, port);
    lg_resource_info info;
    if (!r || lg_describe(r, &info, n) != 0 || info.neutral || info.kind != LG_KIND_IMAGE ||
        info.image.format != LG_FORMAT_RGBA32F)
        return 0;
    lg_cpu_view v;
    int rc = lg_map_cpu(n, r, LG_READ, &v);
    if (rc)
        return rc;
    uint32_t faces = info.image.flags & LG_IMAGE_CUBE ? 6u : 1u;
    uint64_t bad = lg_pixels_nonfinite(v.pixels, info.image.width, info.image.height * faces,
                                       v.row_pixels ? v.row_pixels : info.image.width);
    if (bad) {
        char what[160], how[200];
        snprintf(what, sizeof what, "input '%s' (frame %u)", port_name, frame ? frame->index : 0u);
        snprintf(how, sizeof how, "%s (reported once)", fate ? fate : "passed on as found");
        lg_warn_nonfinite(n, what, bad, how);
        *reported = true;
    }
    return 0;
}
