/* The ibl node's cache entry (ibl_cache.h): the chain is checked before the node uses it,
 * on bytes that may be anything the host's checksum lets through (an entry written by
 * another build or version of this plugin). */
#include "ibl_cache.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *ibl_chain_read_raw(const void *data, size_t bytes, uint32_t size, uint32_t levels,
                               uint32_t samples, size_t floats, float **chain)
{
    *chain = NULL;
    ibl_chain_header h;
    if (floats > (SIZE_MAX - sizeof h) / sizeof(float) ||
        bytes != sizeof h + floats * sizeof(float))
        return "its size does not add up";
    memcpy(&h, data, sizeof h);
    if (memcmp(h.magic, "lgibl01", 8) != 0 || h.size != size || h.levels != levels ||
        h.samples != samples || h.floats != floats)
        return "its magic, cube size, levels, samples or float count differ from the node's";
    float *c = malloc(floats ? floats * sizeof(float) : 1);
    if (!c)
        return "out of memory";
    memcpy(c, (const char *)data + sizeof h, floats * sizeof(float));
    *chain = c;
    return NULL;
}

const char *ibl_chain_read(const void *data, size_t bytes, uint32_t size, uint32_t levels,
                           uint32_t samples, size_t floats, float **chain)
{
    *chain = NULL;
    float *c;
    const char *why = ibl_chain_read_raw(data, bytes, size, levels, samples, floats, &c);
    if (why)
        return why;
    /* a NaN or an infinity would be looked up by every glossy pixel that reaches it and
     * spread through the tone mapper's average: the prefilter never makes one from a
     * probe (the probe node zeroes them), so such an entry is not this node's */
    for (size_t i = 0; i < floats; i++)
        if (!isfinite(c[i])) {
            free(c);
            return "a value that is not finite";
        }
    *chain = c;
    return NULL;
}

char *ibl_chain_encode(uint32_t size, uint32_t levels, uint32_t samples, size_t floats,
                       const float *chain, size_t *bytes)
{
    size_t total = sizeof(ibl_chain_header) + floats * sizeof(float);
    char *blob = malloc(total);
    if (!blob)
        return NULL;
    ibl_chain_header h = { .magic = "lgibl01",
                           .size = size,
                           .levels = levels,
                           .samples = samples,
                           .floats = (uint32_t)floats };
    memcpy(blob, &h, sizeof h);
    if (floats)
        memcpy(blob + sizeof h, chain, floats * sizeof(float));
    *bytes = total;
    return blob;
}
