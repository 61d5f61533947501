#!/bin/sh
# meson install into a temporary root: what the SDK installs is there. (The template built
# against it and run through the installed host: tests/unit/template_ci.)
set -eu
BUILD="$LG_BUILD_ROOT"
SRC="$LG_SOURCE_ROOT"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
meson install -C "$BUILD" --destdir "$TMP/root" --no-rebuild --quiet >"$TMP/install.log" 2>&1 || {
  cat "$TMP/install.log"; echo "FAIL: meson install"; exit 1; }
pc=$(find "$TMP/root" -name lightgraph.pc | head -1)
[ -n "$pc" ] || { echo "FAIL: lightgraph.pc not installed"; exit 1; }
[ -f "$(dirname "$pc")/lightgraph-test.pc" ] || { echo "FAIL: lightgraph-test.pc not installed"; exit 1; }
find "$TMP/root" -name 'liblightgraph-test.so*' | grep -q . || { echo "FAIL: liblightgraph-test not installed"; exit 1; }
for h in lightgraph.h plugin.h host.h types.h image.h gl.h cl.h color.h config.h test.h glad/gl.h; do
  find "$TMP/root" -path "*/include/lightgraph/$h" | grep -q . || { echo "FAIL: header $h not installed"; exit 1; }
done
find "$TMP/root" -name 'lg_core.so' | grep -q . || { echo "FAIL: plugins not installed"; exit 1; }
find "$TMP/root" -name 'lightgraph' -type f -perm -u+x | grep -q . || { echo "FAIL: host not installed"; exit 1; }
[ -f "$(find "$TMP/root" -path '*/share/lightgraph/template/meson.build' | head -1)" ] || {
  echo "FAIL: the template is not installed"; exit 1; }
# The template built, tested, checked by conform and rendered from the installed prefix:
# tests/unit/template_ci.
echo "ok: installed headers, libraries, pkg-config files, host, plugins and template"
