#!/bin/sh
# tests/dist/render_dist.sh CASE LIGHTGRAPH PLUGIN_DIR MPIRUN_SH GRAPH WORKDIR: `lightgraph
# render` of the test_shard node (tests/dist/testshard.c) under mpirun (docs/distributed.md).
#   same NP     one process, then NP ranks: the two .exr files are identical bit for bit
#               (uneven items in dynamic chunks; NP 3 oversubscribes this machine)
#   jobfail     rank 1's chunks fail inside the job: exit 1, "on rank 1" and the reason on
#               stderr, no output file
#   itemfail    item 700 fails on whichever rank takes it: exit 1, the item, "on rank" and
#               the reason, no output file
#   before      rank 1 fails before its job while rank 0 starts it: exit 1, rank 1's reason,
#               no output file, no hang (the test's timeout)
#   cache       rank 0's cache is warm, rank 1's cold: one answer (a miss), every rank
#               computes, the same bits, exit 0; rank 1 writes no cache entry
#   affinity NP two passes of one affinity family, the other ranks late to the second: rank
#               0 reran every chunk of its own first (without affinity none are its own),
#               and the bits of one process
#   steal NP    the same run: rank 0, done with its own, steals the late ranks' chunks
#   plain       a run without mpirun prints what it printed before the MPI layer: the
#               report only, no "rank" anywhere
set -u
case_=$1 lg=$2 plugins=$3 mpirun=$4 graph=$5 work=$6
np=${7:-2}
rm -rf "$work"
mkdir -p "$work"
export LIGHTGRAPH_PLUGIN_PATH="$plugins" LIGHTGRAPH_CACHE_DIR="$work/cache"
fail() { echo "render_dist.sh $case_: $*" >&2; exit 1; }
render() { "$lg" render "$graph" --no-cache "$@"; }
expect_fail() { # expect_fail OUT TEXT... -- mpirun args
  out=$1; shift
  texts=""
  while [ "$1" != "--" ]; do texts="$texts|$1"; shift; done
  shift
  sh "$mpirun" "$np" "$lg" render "$graph" --no-cache -o "$out" "$@" 2>"$work/err"
  st=$?
  cat "$work/err" >&2
  [ $st -eq 1 ] || fail "exit status $st, expected 1"
  [ -e "$out" ] && fail "$out was written"
  ls -a "$work" | grep -q lgtmp && fail "a temporary file was left in $work"
  old_ifs=$IFS; IFS='|'
  for t in $texts; do
    [ -z "$t" ] && continue
    grep -qF -- "$t" "$work/err" || fail "stderr lacks '$t'"
  done
  IFS=$old_ifs
  return 0
}
case $case_ in
  same)
    render -o "$work/one.exr" --set s.grain=7 || fail "one process failed"
    sh "$mpirun" "$np" "$lg" render "$graph" --no-cache --set s.grain=7 -o "$work/many.exr" ||
      fail "$np ranks failed"
    cmp "$work/one.exr" "$work/many.exr" || fail "$np ranks differ from one process"
    # a second run with another grain: the same bits again
    sh "$mpirun" "$np" "$lg" render "$graph" --no-cache --set s.grain=1 -o "$work/g1.exr" ||
      fail "$np ranks, grain 1, failed"
    cmp "$work/one.exr" "$work/g1.exr" || fail "$np ranks with grain 1 differ"
    echo "render_dist.sh: 1 process and $np ranks give the same bits"
    ;;
  jobfail)
    expect_fail "$work/out.exr" "on rank 1" "refused on this rank by request (fail_rank)" -- \
      --set s.fail_rank=1 --set s.fail_where=job --set s.slow_us=2000 --set s.grain=4
    ;;
  itemfail)
    expect_fail "$work/out.exr" "item 700 refused by request (fail_at)" " on rank " "pixels " -- \
      --set s.fail_at=700
    ;;
  before)
    expect_fail "$work/out.exr" "rank 1" \
      "failing before the job on rank 1 by request (fail_rank)" -- \
      --set s.fail_rank=1 --set s.fail_where=before
    ;;
  cache)
    # rank 0's cache made warm by a plain run; rank 1's folder stays empty
    mkdir -p "$work/cache0" "$work/cache1"
    LIGHTGRAPH_CACHE_DIR="$work/cache0" "$lg" render "$graph" --set s.cached=true \
      -o "$work/one.exr" 2>"$work/err0" || fail "the warming run failed"
    grep -q "computed the image" "$work/err0" || fail "the warming run did not compute"
    [ -n "$(ls "$work/cache0")" ] || fail "the warming run wrote no cache entry"
    cat >"$work/rankcache.sh" <<EOS
#!/bin/sh
LIGHTGRAPH_CACHE_DIR="$work/cache\$OMPI_COMM_WORLD_RANK" exec "\$@"
EOS
    sh "$mpirun" 2 sh "$work/rankcache.sh" "$lg" render "$graph" --set s.cached=true -v \
      -o "$work/many.exr" 2>"$work/err" || { cat "$work/err" >&2; fail "the mixed-cache run failed"; }
    cat "$work/err" >&2
    grep -q "the ranks' entries differ" "$work/err" || fail "rank 0 did not say the ranks disagreed"
    grep -q "cache hit" "$work/err" || fail "rank 0's own cache did not hit"
    grep -q "computed the image" "$work/err" || fail "rank 0 did not compute (its hit was used)"
    cmp "$work/one.exr" "$work/many.exr" || fail "the mixed-cache run differs"
    [ -z "$(ls "$work/cache1")" ] && true || fail "rank 1 wrote a cache entry"
    # both warm now? rank 1's is still cold (rank 0 alone writes): warm it, then both hit
    cp -r "$work/cache0/." "$work/cache1/"
    sh "$mpirun" 2 sh "$work/rankcache.sh" "$lg" render "$graph" --set s.cached=true \
      -o "$work/hit.exr" 2>"$work/err2" || { cat "$work/err2" >&2; fail "the warm run failed"; }
    grep -q "reused the cached image" "$work/err2" || fail "two warm ranks did not hit"
    cmp "$work/one.exr" "$work/hit.exr" || fail "the warm run differs"
    echo "render_dist.sh: warm rank 0 and cold rank 1 agree on a miss; two warm ranks hit"
    ;;
  affinity | steal)
    # rank 0's placement line (-v -v) of the run's job $2 (default its last): "ran N chunks
    # (O its own, S stolen)"
    placement() { grep -o "shard: rank 0 ran [0-9]* chunks ([0-9]* its own, [0-9]* stolen)" \
                    "$1" | sed -n "${2:-\$}p" | tr -dc '0-9 ' | awk '{ print $2, $3, $4 }'; }
    render -o "$work/one.exr" --set s.grain=4 || fail "one process failed"
    render -o "$work/one3.exr" --set s.grain=4 --set s.passes=3 --set s.affinity=7 ||
      fail "one process, three passes, failed"
    cmp "$work/one.exr" "$work/one3.exr" || fail "three passes in one process differ"
    # Ranks other than 0 sleep 0.5 s in their first item of the second pass (hold_us): rank
    # 0, whose chunks take milliseconds, meets no competition for its own list, so what it
    # does is the protocol's and not the scheduler's (a slowed rank 0 racing the others, the
    # first version of this test, failed once in a loaded CI run: rank 0 had stolen two
    # chunks before the others, starved of CPU, reached their own lists).
    for aff in 7 0; do
      sh "$mpirun" "$np" "$lg" render "$graph" --no-cache -v -v -o "$work/many$aff.exr" \
        --set s.grain=4 --set s.passes=2 --set s.affinity=$aff --set s.hold_us=500000 \
        2>"$work/err$aff" || { cat "$work/err$aff" >&2; fail "$np ranks failed"; }
      cmp "$work/one.exr" "$work/many$aff.exr" || fail "$np ranks (affinity $aff) differ"
    done
    set -- $(placement "$work/err7" 1)
    [ $# -eq 3 ] || fail "no placement line on rank 0 for the first pass"
    first=$1
    set -- $(placement "$work/err7" 2)
    [ $# -eq 3 ] || fail "no placement line on rank 0 for the second pass"
    ran=$1 own=$2 stolen=$3
    echo "render_dist.sh: affinity, rank 0 ran $first chunks, then $ran: $own its own, $stolen stolen"
    [ "$first" -gt 0 ] || fail "rank 0 ran no chunk in the first pass"
    [ $((own + stolen)) -eq "$ran" ] ||
      fail "rank 0 ran chunks of no rank's list ($own + $stolen of $ran)"
    if [ "$case_" = affinity ]; then
      [ "$own" -eq "$first" ] ||
        fail "rank 0 did not rerun its own chunks ($own of its $first)"
    else
      [ "$stolen" -gt 0 ] || fail "rank 0 stole nothing from the ranks late to the job"
    fi
    set -- $(placement "$work/err0")
    [ $# -eq 3 ] && [ "$2" -eq 0 ] && [ "$3" -eq 0 ] ||
      fail "without affinity rank 0's chunks were not fresh ($*)"
    echo "render_dist.sh: $np ranks, affinity and not: the bits of one process"
    ;;
  single)
    # api_shard in one process: grain 1, the default, one chunk for all: the same bits
    render -o "$work/g16.exr" || fail "grain 16 failed"
    render -o "$work/g1.exr" --set s.grain=1 || fail "grain 1 failed"
    render -o "$work/gbig.exr" --set s.grain=1000000 || fail "grain 1e6 failed"
    LIGHTGRAPH_THREADS=3 render -o "$work/t3.exr" --set s.grain=5 || fail "3 threads failed"
    for f in g1 gbig t3; do
      cmp "$work/g16.exr" "$work/$f.exr" || fail "$f differs from grain 16"
    done
    # a failing item: the node, the chunk's items and the reason; no output file
    render -o "$work/fail.exr" --set s.fail_at=700 --set s.grain=8 2>"$work/err"
    st=$?
    cat "$work/err" >&2
    [ $st -eq 1 ] || fail "fail_at: exit status $st"
    [ -e "$work/fail.exr" ] && fail "fail_at: the output was written"
    grep -qF "pixels 696..703: testshard: item 700 refused by request (fail_at)" "$work/err" ||
      fail "fail_at: the message lacks the chunk or the reason"
    grep -qF "node 's'" "$work/err" || fail "fail_at: the node is not named"
    echo "render_dist.sh: grains 1, 16, 1e6 and 3 threads agree; a failure names its items"
    ;;
  bad)
    for b in grain0:"grain is 0" bytes0:"item_bytes is 0" run_null:"run is NULL" \
             out_null:"out is NULL" overflow:"more than this host can hold"; do
      mode=${b%%:*} text=${b#*:}
      render -o "$work/bad.exr" --set s.bad=$mode 2>"$work/err"
      st=$?
      cat "$work/err" >&2
      [ $st -eq 1 ] || fail "bad = $mode: exit status $st"
      [ -e "$work/bad.exr" ] && fail "bad = $mode: the output was written"
      grep -qF "shard" "$work/err" && grep -qF "$text" "$work/err" ||
        fail "bad = $mode: the message lacks '$text'"
    done
    echo "render_dist.sh: every bad job is refused with its reason"
    ;;
  plain)
    render -o "$work/plain.exr" >"$work/out" 2>"$work/err" || fail "a plain run failed"
    cat "$work/out" "$work/err"
    grep -qi "rank\|mpi" "$work/out" "$work/err" && fail "a plain run mentions ranks or MPI"
    [ -s "$work/out" ] && fail "a plain run printed on stdout: $(cat "$work/out")"
    echo "render_dist.sh: a plain run is quiet about MPI"
    ;;
  *) fail "unknown case" ;;
esac
exit 0
