#!/bin/sh
# tests/dist/expect.sh STATUS [--stderr TEXT]... [--no-file FILE]... -- COMMAND...: runs
# COMMAND (normally tests/dist/mpirun.sh NP ...) and fails unless it exits with STATUS, its
# stderr holds every TEXT and no FILE exists afterwards. The distributed tests' failure
# cases (docs/distributed.md): a rank's failure is the job's, named on rank 0's stderr, and
# no output file is written.
want=$1
shift
texts=""
files=""
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  case "$1" in
    --stderr) texts="$texts
$2"; shift 2 ;;
    --no-file) files="$files $2"; shift 2 ;;
    *) echo "expect.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ "$1" = "--" ] && shift
err=$(mktemp)
trap 'rm -f "$err"' EXIT
"$@" 2>"$err"
got=$?
cat "$err" >&2
bad=0
if [ "$got" != "$want" ]; then
  echo "expect.sh: exit status $got, expected $want: $*" >&2
  bad=1
fi
old_ifs=$IFS
IFS='
'
for t in $texts; do
  if ! grep -qF -- "$t" "$err"; then
    echo "expect.sh: stderr lacks '$t'" >&2
    bad=1
  fi
done
IFS=$old_ifs
for f in $files; do
  if [ -e "$f" ]; then
    echo "expect.sh: $f was written" >&2
    bad=1
  fi
done
exit $bad
