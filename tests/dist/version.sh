#!/bin/sh
# tests/dist/version.sh MPIRUN_SH LIGHTGRAPH: `lightgraph --version` under mpirun -np 2
# prints its one line once (rank 0 alone prints), exits 0, and says what a plain run says.
set -e
plain=$("$2" --version)
out=$(sh "$1" 2 "$2" --version)
if [ "$out" != "$plain" ]; then
  echo "version.sh: under mpirun -np 2: '$out', plain: '$plain'" >&2
  exit 1
fi
echo "version.sh: '$out' once"
