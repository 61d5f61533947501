/*
 * tests/common/cl_join.h: OpenCL C texts joined one after the other (a shared twin such
 * as rgbe.cl, then a test kernel), for the device tests that build through the host's
 * program cache directly. Plugins use lg_cl_pass_desc.sources, which does the same (and
 * names each file in the build log); the SDK's lg_cl_source_join went with ABI 3.0.
 */
#ifndef LG_TEST_CL_JOIN_H
#define LG_TEST_CL_JOIN_H

#include <stdlib.h>
#include <string.h>

/* The parts with a newline between them, NUL-terminated, malloc'd (free() it); NULL when
 * out of memory or a part is NULL. */
static inline char *test_cl_join(const char *const *parts, size_t n_parts)
{
    size_t total = 1;
    for (size_t i = 0; i < n_parts; i++) {
        if (!parts[i])
            return NULL;
        total += strlen(parts[i]) + 1;
    }
    char *src = malloc(total), *w = src;
    if (!src)
        return NULL;
    for (size_t i = 0; i < n_parts; i++) {
        size_t len = strlen(parts[i]);
        memcpy(w, parts[i], len);
        w += len;
        if (i + 1 < n_parts)
            *w++ = '\n';
    }
    *w = '\0';
    return src;
}

#endif
