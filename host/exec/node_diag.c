/* A node's messages: every error and warning the host reports about a node names it and
 * its type. Apart from the host API (hostapi.c) so that the files below it (resources,
 * the cache, devices) report through it without calling back up into the API table. */
#include "exec/exec.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

void lg_node_vmsg(lg_pnode *n, int level, const char *fmt, va_list ap)
{
    char *msg;
    if (vasprintf(&msg, fmt, ap) < 0)
        return;
    lg_hlog(level, "node '%s' (%s): %s", n->pub.name, n->schema ? n->schema->name : "?", msg);
    free(msg);
}

void lg_node_errorf(lg_pnode *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    lg_node_vmsg(n, LG_HERR, fmt, ap);
    va_end(ap);
    n->ex->failed = true;
}

void lg_node_warnf(lg_pnode *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    lg_node_vmsg(n, LG_HWARN, fmt, ap);
    va_end(ap);
}
