/*
 * tests/unit/devices/devtest.h: what the device tests share besides the checks
 * (tests/common/check.h): a clock, and a minimal host (an lg_node whose lg_host_api has
 * only log and error) for the SDK helpers that report through the node.
 */
#ifndef LG_DEVTEST_H
#define LG_DEVTEST_H

#include <stdio.h>
#include <stdlib.h>

#include "common/check.h"
#include "lightgraph/host.h"

double devtest_now(void); /* monotonic seconds */

/* A node named "test" whose errors go to devtest_errors (cleared by devtest_clear) and
 * whose log messages go to stderr. */
lg_node *devtest_node(void);
extern char devtest_errors[16384];
extern int devtest_error_count;
void devtest_clear(void);

#endif
