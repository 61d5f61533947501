#!/bin/sh
# A plugin exports exactly one dynamic symbol, lg_plugin_entry (docs/sdk.md): any other can
# collide with the host's, liblightgraph's or another plugin's. The test plugin_exports runs
# it on every in-tree plugin; test_install.sh on the template built against the installed SDK.
#
#   check_exports.sh SO...                       exit 1 naming each extra or missing symbol
#   check_exports.sh --must-catch SYMBOL SO      the check's own test: it must fail on SO,
#                                                naming SYMBOL (test plugin_exports_catches)
set -eu
must=""
if [ "${1:-}" = "--must-catch" ]; then
  must=$2
  shift 2
fi
[ $# -ge 1 ] || { echo "usage: check_exports.sh [--must-catch SYMBOL] SO..." >&2; exit 99; }
bad=0
report=""
for so in "$@"; do
  [ -f "$so" ] || { echo "FAIL: $so: no such file"; exit 99; }
  syms=$(nm -D --defined-only "$so" | awk '{print $3}' | sort -u) || { echo "FAIL: nm -D $so"; exit 99; }
  extra=$(printf '%s\n' "$syms" | grep -vx 'lg_plugin_entry' | grep . || true)
  if ! printf '%s\n' "$syms" | grep -qx 'lg_plugin_entry'; then
    report="$report$so: does not export lg_plugin_entry
"
    bad=$((bad + 1))
  fi
  if [ -n "$extra" ]; then
    report="$report$so exports $(printf '%s\n' "$extra" | wc -l) symbol(s) besides lg_plugin_entry: $(printf '%s ' $extra)
"
    bad=$((bad + 1))
  fi
done
if [ -n "$must" ]; then
  printf '%s' "$report"
  [ $bad -gt 0 ] && printf '%s' "$report" | grep -q "$must" || {
    echo "FAIL: the check did not catch $must in $*"; exit 1; }
  echo "ok: the check fails on $*, naming $must"
  exit 0
fi
if [ $bad -gt 0 ]; then
  printf '%s' "$report"
  echo "FAIL: a plugin must export lg_plugin_entry and nothing else: build it with -fvisibility=hidden and a version script (plugins/plugin.map; plugin_kwargs in plugins/meson.build does both)"
  exit 1
fi
echo "ok: $# plugin(s) export lg_plugin_entry only"
