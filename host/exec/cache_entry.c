/* The bytes of one cache entry (exec.h, "cache"): written by lg_exec_cache_put, checked by
 * lg_exec_cache_get. Apart from cache.c so that the check runs on a buffer, with nothing else of
 * the host: tests/fuzz/fuzz_cache.c feeds it arbitrary bytes.
 *
 *   "LGCACHE\1" | u32 format version | 16 bytes identity | u32 key length | key
 *   | u64 payload size | u64 payload checksum | payload
 *
 * Integers are in the host's byte order (an entry is only read by the machine that wrote
 * it; another order fails the version check).
 */
#include "exec/exec.h"

#include <string.h>

#define CACHE_MAGIC "LGCACHE\1"
#define CACHE_VERSION 1u

void lg_cache_entry_encode(lg_str *b, const lg_digest *identity, const char *key, const void *data,
                           size_t size)
{
    uint32_t ver = CACHE_VERSION, kl = (uint32_t)strlen(key);
    uint64_t psize = size, sum = lg_hash64(data, size, 0);
    lg_str_addn(b, CACHE_MAGIC, 8);
    lg_str_addn(b, (const char *)&ver, 4);
    lg_str_addn(b, (const char *)identity, 16);
    lg_str_addn(b, (const char *)&kl, 4);
    lg_str_addn(b, key, kl);
    lg_str_addn(b, (const char *)&psize, 8);
    lg_str_addn(b, (const char *)&sum, 8);
    if (size)
        lg_str_addn(b, data, size);
}

const char *lg_cache_entry_check(const char *buf, size_t len, const lg_digest *identity,
                                 const char *key, const char **payload, size_t *payload_size)
{
    *payload = NULL;
    *payload_size = 0;
    /* the key is the caller's (at most CACHE_MAX_KEY bytes), never the entry's: every
     * offset below is known before a byte of the entry is trusted */
    size_t klen = strlen(key);
    size_t head = 8 + 4 + 16 + 4 + klen + 8 + 8;
    uint32_t ver = 0, kl = 0;
    uint64_t psize = 0, sum = 0;
    if (len < head || memcmp(buf, CACHE_MAGIC, 8) != 0)
        return "bad header";
    memcpy(&ver, buf + 8, 4);
    memcpy(&kl, buf + 28, 4);
    if (ver != CACHE_VERSION)
        return "written by another cache format version";
    if (memcmp(buf + 12, identity, 16) != 0)
        return "its identity does not match (stale)";
    if (kl != klen || memcmp(buf + 32, key, klen) != 0)
        return "its key does not match";
    memcpy(&psize, buf + 32 + klen, 8);
    memcpy(&sum, buf + 40 + klen, 8);
    /* the declared size is compared with the bytes there are, never used to allocate */
    if (psize != len - head)
        return "truncated or padded";
    if (lg_hash64(buf + head, (size_t)psize, 0) != sum)
        return "checksum mismatch";
    *payload = buf + head;
    *payload_size = (size_t)psize;
    return NULL;
}
