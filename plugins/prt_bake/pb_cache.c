/* The payload of prt_bake's cache entries (pb_cache.h): checked before anything of it is
 * used, on bytes that may be anything (the host's checksum catches a torn write, not an
 * entry written by another build or another version of this plugin). */
#include "pb_cache.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *pb_cache_header_check(const void *data, size_t bytes, const pb_cache_header *want,
                                  pb_cache_header *out)
{
    pb_cache_header h;
    if (bytes < sizeof h)
        return "shorter than its header";
    memcpy(&h, data, sizeof h);
    if (memcmp(h.magic, want->magic, 8) != 0)
        return "bad magic";
    if (h.version != want->version)
        return "another format version";
    if (h.bands != want->bands || h.vertices != want->vertices || h.mode != want->mode ||
        h.samples != want->samples)
        return "its bands, vertices, mode or samples differ from the node's";
    /* floats is compared with the node's count first, so the product cannot wrap */
    if (h.floats != want->floats || bytes != sizeof h + h.floats * sizeof(float))
        return "its size does not add up";
    if (h.bounces > PB_CACHE_MAX_BOUNCES)
        return "an impossible bounce count";
    *out = h;
    return NULL;
}

const char *pb_cache_read(const void *data, size_t bytes, const pb_cache_header *want, float *out,
                          uint32_t *bounces)
{
    pb_cache_header h;
    const char *why = pb_cache_header_check(data, bytes, want, &h);
    if (why)
        return why;
    /* read through memcpy: the payload need not be aligned for floats */
    const char *f = (const char *)data + sizeof h;
    for (uint64_t i = 0; i < h.floats; i++) {
        float v;
        memcpy(&v, f + i * sizeof v, sizeof v);
        if (!isfinite(v))
            return "a value that is not finite";
    }
    memcpy(out, f, h.floats * sizeof(float));
    *bounces = h.bounces;
    return NULL;
}

char *pb_cache_encode(const pb_cache_header *h, const float *f, size_t *bytes)
{
    size_t total = sizeof *h + h->floats * sizeof(float);
    char *blob = malloc(total);
    if (!blob)
        return NULL;
    memcpy(blob, h, sizeof *h);
    if (h->floats)
        memcpy(blob + sizeof *h, f, h->floats * sizeof(float));
    *bytes = total;
    return blob;
}
