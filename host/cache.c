/* The on-disk cache for expensive static results.
 *
 * Directory: $LIGHTGRAPH_CACHE_DIR, else $XDG_CACHE_HOME/lightgraph, else
 * ~/.cache/lightgraph. One file per entry, named by a digest of the node's identity (plugin,
 * version, type, parameters, content keys, inputs' identities) and the entry key, so a
 * change to any of them looks up another file: stale entries are never found. The file
 * repeats the identity and key and carries the payload size and a checksum; an entry whose
 * header, size or checksum disagrees is corrupt: reported, removed, and treated as a miss.
 * The entry's bytes are written and checked by cache_entry.c (the format is there).
 */
#include "host.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define CACHE_MAX_KEY 1024u

char *lg_cache_dir(void)
{
    const char *e = getenv("LIGHTGRAPH_CACHE_DIR");
    if (e && *e)
        return lg_xstrdup(e);
    e = getenv("XDG_CACHE_HOME");
    if (e && *e)
        return lg_xasprintf("%s/lightgraph", e);
    e = getenv("HOME");
    return lg_xasprintf("%s/.cache/lightgraph", e && *e ? e : "/tmp");
}

static int mkdir_p(const char *dir)
{
    char *d = lg_xstrdup(dir);
    int rc = 0;
    for (char *p = d + 1;; p++) {
        if (*p == '/' || !*p) {
            char c = *p;
            *p = 0;
            if (mkdir(d, 0777) != 0 && errno != EEXIST) {
                rc = -1;
                break;
            }
            *p = c;
            if (!c)
                break;
        }
    }
    free(d);
    return rc;
}

static char *entry_path(lg_exec *ex, lg_pnode *n, const char *key)
{
    if (!ex->cache_dir)
        ex->cache_dir = lg_cache_dir();
    lg_digest d = n->identity;
    lg_digest_add_str(&d, key);
    char hex[33];
    lg_digest_hex(&d, hex);
    return lg_xasprintf("%s/%s-%s.lgc", ex->cache_dir, n->schema->name, hex);
}

static bool key_ok(lg_pnode *n, const char *key)
{
    if (!key || strlen(key) > CACHE_MAX_KEY) {
        lg_node_errorf(n, "cache key missing or longer than %u bytes", CACHE_MAX_KEY);
        return false;
    }
    return true;
}

/* The largest entry read back: the largest buffer a resource may hold (16 GiB) plus the
 * header. */
#define CACHE_MAX_ENTRY (((size_t)1 << 34) + 4096)

int lg_cache_get(lg_exec *ex, lg_pnode *n, const char *key, void **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    if (!key_ok(n, key))
        return LG_ERR_INVALID;
    char *path = entry_path(ex, n, key);
    size_t len = 0;
    char why_read[256];
    /* bounded: an entry that is a FIFO, a device (a link to /dev/zero) or larger than any
     * payload can be is refused before it is read, and treated as a corrupt entry */
    char *buf = lg_read_file_limit(path, CACHE_MAX_ENTRY, &len, why_read, sizeof why_read);
    if (!buf) {
        if (errno != ENOENT) {
            lg_hlog(LG_HWARN, "node '%s': cache entry %s cannot be used (%s); removing it and "
                              "recomputing",
                    n->pub.name, path, why_read);
            remove(path);
        }
        free(path);
        n->cache_misses++;
        return LG_ERR_NOTFOUND;
    }
    const char *payload = NULL;
    size_t psize = 0;
    const char *why = lg_cache_entry_check(buf, len, &n->identity, key, &payload, &psize);
    if (why) {
        lg_hlog(LG_HWARN, "node '%s': cache entry %s is corrupt (%s); removing it and recomputing",
                n->pub.name, path, why);
        remove(path);
        free(buf);
        free(path);
        n->cache_misses++;
        return LG_ERR_NOTFOUND;
    }
    void *out = malloc(psize ? psize : 1);
    if (!out) {
        free(buf);
        free(path);
        return LG_ERR_NOMEM;
    }
    memcpy(out, payload, psize);
    free(buf);
    lg_hlog(LG_HINFO, "node '%s': cache hit %s (%llu bytes)", n->pub.name, path,
            (unsigned long long)psize);
    free(path);
    *data = out;
    *size = psize;
    n->cache_hits++;
    return LG_OK;
}

int lg_cache_put(lg_exec *ex, lg_pnode *n, const char *key, const void *data, size_t size)
{
    if (!key_ok(n, key))
        return LG_ERR_INVALID;
    if (!data && size)
        return lg_node_errorf(n, "cache_put with NULL data"), LG_ERR_INVALID;
    char *path = entry_path(ex, n, key);
    if (mkdir_p(ex->cache_dir) != 0) {
        lg_hlog(LG_HWARN, "node '%s': cannot create cache directory %s: %s", n->pub.name,
                ex->cache_dir, strerror(errno));
        free(path);
        return LG_ERR_IO;
    }
    lg_str b = {0};
    lg_cache_entry_encode(&b, &n->identity, key, data, size);
    int rc = 0;
    if (lg_write_file_atomic(path, b.s, b.len) != 0) {
        lg_hlog(LG_HWARN, "node '%s': cannot write cache entry %s: %s", n->pub.name, path,
                strerror(errno));
        rc = LG_ERR_IO;
    }
    free(path);
    lg_str_free(&b);
    return rc;
}
