#!/bin/sh
# tests/dist/mpirun.sh NP COMMAND...: runs COMMAND as NP MPI ranks on this machine, as the
# distributed tests do (docs/distributed.md). As root Open MPI refuses to start without its
# two consent variables; --oversubscribe lets NP exceed the cores (a 2-core CI machine
# runs 3 ranks to check that results do not depend on the schedule); --bind-to none keeps
# a rank's threads free to use every core. The environment (LIGHTGRAPH_*, LG_*) reaches
# every rank: local ranks inherit mpirun's.
set -e
if [ $# -lt 2 ]; then
  echo "usage: tests/dist/mpirun.sh NP COMMAND..." >&2
  exit 2
fi
np=$1
shift
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# No network interfaces to probe on a single machine; keeps startup quiet and fast.
export OMPI_MCA_btl="self,vader" OMPI_MCA_btl_vader_single_copy_mechanism=none
# No leak check in the ranks of an ASan build (other builds ignore ASAN_OPTIONS), set here
# whatever the caller's environment: Open MPI's start-up allocations and those of the
# components it dlclose's in MPI_Finalize come through libraries without frame pointers, so
# LeakSanitizer's fast stacks never reach the names tests/lsan.supp gives; the slow unwinder
# (fast_unwind_on_malloc=0), tried first, deadlocks: ASan's malloc interceptor unwinds
# through libgcc's _Unwind_Find_FDE, whose lock the thread may already hold (prt_bake dist
# np2/np3 hung for 11 minutes in CI on 2026-11-29, gdb showed it). Address and
# undefined-behaviour checks stay on; the nodes' own leaks are checked by the same code's
# one-process tests.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
exec mpirun -np "$np" --oversubscribe --bind-to none "$@"
