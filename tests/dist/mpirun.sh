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
# An ASan build (tests/meson.build sets ASAN_OPTIONS in every build; others ignore it):
# whole stacks for LeakSanitizer, so that tests/lsan.supp's Open MPI entries match the
# allocations MPI_Init makes through libraries without frame pointers.
if [ -n "${ASAN_OPTIONS:-}" ]; then
  export ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"
fi
exec mpirun -np "$np" --oversubscribe --bind-to none "$@"
