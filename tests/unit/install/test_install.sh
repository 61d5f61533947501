#!/bin/sh
# meson install into a temporary root, then build the SDK template plugin out of tree
# against the installed headers, library and pkg-config file, and run it through the host.
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
export PKG_CONFIG_PATH="$(dirname "$pc")"
export PKG_CONFIG_SYSROOT_DIR="$TMP/root"
cp -r "$SRC/sdk/template" "$TMP/template"
san=""
if [ -n "${LG_SANITIZE:-}" ] && [ "$LG_SANITIZE" != none ]; then
  san="-Db_sanitize=$LG_SANITIZE -Db_lundef=false"
fi
# shellcheck disable=SC2086 # $san is two words or none
(cd "$TMP/template" && meson setup build $san >"$TMP/setup.log" 2>&1 && ninja -C build >"$TMP/ninja.log" 2>&1) || {
  cat "$TMP/setup.log" "$TMP/ninja.log" 2>/dev/null; echo "FAIL: template build"; exit 1; }
libdir=$(dirname "$(find "$TMP/root" -name 'liblightgraph.so*' | head -1)")
export LD_LIBRARY_PATH="$libdir"
export LIGHTGRAPH_PLUGIN_PATH="$TMP/template/build"
"$LG_EXE" inspect template_invert --json | grep -q '"white"' || { echo "FAIL: inspect template_invert"; exit 1; }
cat >"$TMP/g.lgraph" <<G
lightgraph 1
c = constant { color = [0.25, 0.5, 0.75] }
inv = template_invert { image = c, white = 1 }
output inv "$TMP/out.exr"
G
"$LG_EXE" render "$TMP/g.lgraph" --size 4x2 -q
cat >"$TMP/e.lgraph" <<G
lightgraph 1
c = constant { color = [0.75, 0.5, 0.25] }
output c "$TMP/expected.exr"
G
"$LG_EXE" render "$TMP/e.lgraph" --size 4x2 -q
"$LG_EXE" diff "$TMP/out.exr" "$TMP/expected.exr" --max-abs 0.001 >/dev/null || {
  echo "FAIL: template_invert computed the wrong image"; exit 1; }
# backend = gl runs the template's compute shader, embedded by the installed embed.py with
# its #include resolved (shaders/invert.comp includes shaders/common/invert.glsl)
h=$(find "$TMP/template/build" -name 'invert.comp.h' | head -1)
[ -n "$h" ] && grep -q 'GLSL source strings: 0 invert.comp, 1 invert.glsl' "$h" || {
  echo "FAIL: the template's shader was not embedded by the installed embed.py with its #include"; exit 1; }
sed 's/white = 1 }/white = 1, backend = gl }/; s#out.exr#out_gl.exr#' "$TMP/g.lgraph" >"$TMP/g_gl.lgraph"
if ! "$LG_EXE" render "$TMP/g_gl.lgraph" --size 40x24 -q 2>"$TMP/gl.err"; then
  cat "$TMP/gl.err"
  if grep -q 'no OpenGL 4.5 device' "$TMP/gl.err"; then
    echo "SKIP: no GL device: the template's gl backend is not run"; exit 77
  fi
  echo "FAIL: template_invert backend = gl"; exit 1
fi
"$LG_EXE" render "$TMP/e.lgraph" --size 40x24 -q
"$LG_EXE" diff "$TMP/out_gl.exr" "$TMP/expected.exr" --max-abs 0.001 >/dev/null || {
  echo "FAIL: template_invert backend = gl computed the wrong image"; exit 1; }
# The template's own test, on the installed harness (liblightgraph-test): LG_EXE (set by
# meson for this test) names the program; the library found is the installed one.
meson test -C "$TMP/template/build" --print-errorlogs >"$TMP/test.log" 2>&1 || {
  cat "$TMP/test.log"; echo "FAIL: the template's test on the installed harness"; exit 1; }
grep -E '^ *[0-9]+/[0-9]+ ' "$TMP/test.log"
grep -Eq '^Ok: +2 *$' "$TMP/test.log" || { cat "$TMP/test.log"; echo "FAIL: the template's 2 tests did not both pass"; exit 1; }
ldd "$TMP/template/build/test_template" | grep -q "$libdir/liblightgraph-test.so" || {
  ldd "$TMP/template/build/test_template"; echo "FAIL: test_template does not use the installed harness"; exit 1; }
echo "ok: installed SDK builds the template (its shader embedded by the installed embed.py) and its test on the installed harness; the host runs it on cpu and gl"
