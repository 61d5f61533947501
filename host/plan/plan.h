/*
 * host/plan/plan.h: the plan layer: from a checked graph to the nodes that run, and what
 * --explain says about them. Builds on the runtime (exec/exec.h): planning creates and
 * prepares nodes through it.
 */
#ifndef LG_HOST_PLAN_PLAN_H
#define LG_HOST_PLAN_PLAN_H

#include <stdio.h>

#include "exec/exec.h"

/* Makes the plan: cull (kept only what an output or a side-effect node needs), then in
 * topological order: gate by scene features, load plugins, create and prepare. */
int lg_plan(lg_exec *ex);
/* After lg_plan with ex->viewer.prev: the adopted nodes now belong to ex (the earlier plan may
 * be freed), or go back to ex->viewer.prev as they were (ex failed: free it, keep ex->viewer.prev). */
void lg_plan_commit(lg_exec *ex);
void lg_plan_rollback(lg_exec *ex);

void lg_explain_print(lg_exec *ex, FILE *f);
/* The estimated wall time of lg_execute() from what the kept nodes declared in prepare
 * (lg_declare_work): each node's estimate times the runs it will make (once, or every
 * frame). When `top` is given, it receives the nodes that make most of it, largest first
 * ("sh (sh_project): 2.7e+08 samples x 4096 coefficients, about 1.4 h; ..."). Nodes that
 * declared nothing count as 0. */
double lg_plan_estimate(const lg_exec *ex, lg_str *top);

#endif
