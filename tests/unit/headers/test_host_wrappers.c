/*
 * The inline wrappers of lightgraph/host.h against hosts of every 2.x age, without a host:
 * an lg_host_api filled here, its struct_size set as an older host's would be.
 *
 *   lg_cache_store (ABI 2.7): a 2.7 host's cache_store answers; an older host (struct_size
 *   ending before cache_store, or the slot NULL) gets cache_put, and LG_OK from it is
 *   LG_CACHE_UNKNOWN (it returns LG_OK whether or not it stored), never LG_CACHE_STORED.
 *   lg_cache_reject (ABI 2.7): a 2.7 host's cache_reject gets the key and the reason; an
 *   older host (or a NULL slot) gets one warning through log, naming both, and nothing else.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "common/check.h"
#include "lightgraph/lightgraph.h"

static int put_rc, put_calls, store_calls;

static int fake_put(lg_node *n, const char *key, const void *data, size_t size)
{
    (void)n, (void)key, (void)data, (void)size;
    put_calls++;
    return put_rc;
}

static int fake_store(lg_node *n, const char *key, const void *data, size_t size)
{
    (void)n, (void)key, (void)data;
    store_calls++;
    return size == 1 ? LG_CACHE_OFF : LG_CACHE_STORED;
}

static int reject_calls, log_calls;
static char last[256];

static void fake_reject(lg_node *n, const char *key, const char *why)
{
    (void)n;
    reject_calls++;
    snprintf(last, sizeof last, "%s|%s", key, why);
}

static void fake_log(lg_node *n, lg_log_level level, const char *fmt, va_list ap)
{
    (void)n;
    log_calls += level == LG_LOG_WARN;
    vsnprintf(last, sizeof last, fmt, ap);
}

int main(void)
{
    lg_host_api api;
    memset(&api, 0, sizeof api);
    api.cache_put = fake_put;
    api.cache_store = fake_store; /* there, but an older host's size does not reach it */
    lg_node n;
    memset(&n, 0, sizeof n);
    n.host = &api;
    const char data[2] = {1, 2};

    /* a 2.6 host: the struct ends where cache_store begins */
    api.struct_size = offsetof(lg_host_api, cache_store);
    put_rc = LG_OK;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_UNKNOWN && put_calls == 1 &&
          store_calls == 0);
    put_rc = LG_ERR_IO;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_NOT_STORED);
    put_rc = LG_ERR_INVALID;
    CHECK(lg_cache_store(&n, NULL, data, 2) == LG_ERR_INVALID);

    /* a 2.7 host that left the slot NULL: the same fallback */
    api.struct_size = sizeof api;
    api.cache_store = NULL;
    put_rc = LG_OK;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_UNKNOWN && store_calls == 0);

    /* a 2.7 host: its answer, cache_put not called */
    api.cache_store = fake_store;
    put_calls = 0;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_STORED && store_calls == 1);
    CHECK(lg_cache_store(&n, "k", data, 1) == LG_CACHE_OFF && put_calls == 0);

    /* the slot took a reserved pointer: the struct's size is what 2.6 plugins were built
     * with (set_view_independent, the last 2.6 field, then 24 reserved pointers), and
     * cache_store lies inside it */
    CHECK(sizeof(lg_host_api) == offsetof(lg_host_api, set_view_independent) + 25 * sizeof(void *));
    CHECK(offsetof(lg_host_api, cache_store) < offsetof(lg_host_api, reserved));

    /* lg_cache_reject: a 2.7 host takes it; an older one (or a NULL slot) gets a warning */
    api.log = fake_log;
    api.cache_reject = fake_reject;
    lg_cache_reject(&n, "k", "float 3 = nan is not finite");
    CHECK(reject_calls == 1 && log_calls == 0 && !strcmp(last, "k|float 3 = nan is not finite"));
    api.struct_size = offsetof(lg_host_api, cache_reject);
    lg_cache_reject(&n, "k", "float 3 = nan is not finite");
    CHECK(reject_calls == 1 && log_calls == 1 && strstr(last, "'k'") &&
          strstr(last, "float 3 = nan is not finite"));
    api.struct_size = sizeof api;
    api.cache_reject = NULL;
    lg_cache_reject(&n, "k", "why");
    CHECK(reject_calls == 1 && log_calls == 2);
    CHECK(offsetof(lg_host_api, cache_reject) < offsetof(lg_host_api, reserved));
    return check_report("sdk_host_wrappers");
}
