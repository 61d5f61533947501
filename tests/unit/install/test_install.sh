#!/bin/sh
# meson install into a temporary root, then use only what was installed, as a plugin author
# would: the installed program runs with NO LD_LIBRARY_PATH (its $ORIGIN-relative RPATH) and
# finds its plugins; the four pkg-config files give the flags; the SDK's shader twins and
# test data are there and embed.py finds the twins; the SDK template plugin builds out of
# tree against the installed headers, library and pkg-config files, runs through the
# installed host, and its test runs on the installed harness, which finds the installed
# host by itself; a host that cannot start is named with the loader's message. (The
# template as an author meets it, under env -i, with all its tests and conform:
# tests/unit/template_ci.)
set -eu
BUILD="$LG_BUILD_ROOT"
SRC="$LG_SOURCE_ROOT"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# Nothing here may lean on LD_LIBRARY_PATH: the installed files must work as they are.
unset LD_LIBRARY_PATH
meson install -C "$BUILD" --destdir "$TMP/root" --no-rebuild --quiet >"$TMP/install.log" 2>&1 || {
  cat "$TMP/install.log"; echo "FAIL: meson install"; exit 1; }
pc=$(find "$TMP/root" -name lightgraph.pc | head -1)
[ -n "$pc" ] || { echo "FAIL: lightgraph.pc not installed"; exit 1; }
for p in lightgraph-test lightgraph-gl lightgraph-cl; do
  [ -f "$(dirname "$pc")/$p.pc" ] || { echo "FAIL: $p.pc not installed"; exit 1; }
done
find "$TMP/root" -name 'liblightgraph-test.so*' | grep -q . || { echo "FAIL: liblightgraph-test not installed"; exit 1; }
for h in lightgraph.h plugin.h host.h types.h image.h gl.h cl.h color.h config.h test.h glad/gl.h; do
  find "$TMP/root" -path "*/include/lightgraph/$h" | grep -q . || { echo "FAIL: header $h not installed"; exit 1; }
done
find "$TMP/root" -name 'lg_core.so' | grep -q . || { echo "FAIL: plugins not installed"; exit 1; }
EXE=$(find "$TMP/root" -path '*/bin/lightgraph' -type f -perm -u+x | head -1)
[ -n "$EXE" ] || { echo "FAIL: host not installed"; exit 1; }
PREFIX=$(dirname "$(dirname "$EXE")")
libdir=$(dirname "$(find "$TMP/root" -name 'liblightgraph.so*' | head -1)")

# The installed program, its plugins and the harness library find liblightgraph through an
# RPATH relative to their own file ($ORIGIN), never the build's prefix or the build tree.
for f in "$EXE" "$libdir/liblightgraph-test.so" "$(find "$TMP/root" -name lg_core.so | head -1)"; do
  readelf -d "$f" | grep -E 'R(UN)?PATH' | grep -q 'ORIGIN' || {
    readelf -d "$f" | grep -E 'R(UN)?PATH' || true
    echo "FAIL: $f has no \$ORIGIN-relative RPATH"; exit 1; }
done
"$EXE" --version >"$TMP/version.txt" 2>&1 || {
  cat "$TMP/version.txt"; echo "FAIL: the installed program does not start without LD_LIBRARY_PATH"; exit 1; }
# ... and its own plugins, beside it in the destdir (not <prefix> as configured)
LIGHTGRAPH_PLUGIN_PATH="" "$EXE" plugins >"$TMP/plugins.txt" 2>&1 || {
  cat "$TMP/plugins.txt"; echo "FAIL: installed lightgraph plugins"; exit 1; }
grep -q "^core .*$TMP/root/.*/lg_core.so" "$TMP/plugins.txt" || {
  cat "$TMP/plugins.txt"; echo "FAIL: the installed program does not find its installed plugins"; exit 1; }

export PKG_CONFIG_PATH="$(dirname "$pc")"
export PKG_CONFIG_SYSROOT_DIR="$TMP/root"
# Two names of one folder (a relocatable .pc file's ${pcfiledir}/../.. or a plain path).
same_dir() { [ -d "$1" ] && [ "$(cd "$1" && pwd -P)" = "$(cd "$2" && pwd -P)" ]; }
# The four packages: each gives the SDK's include folder and its library; the CL part
# pulls OpenCL in (a cl plugin must link it, not rely on the host having loaded it); the
# harness links its own library and the SDK's.
for p in lightgraph lightgraph-gl lightgraph-cl lightgraph-test; do
  flags=$(pkg-config --cflags --libs "$p") || { echo "FAIL: pkg-config $p"; exit 1; }
  # the include folder, as written (relocatable .pc files say ${pcfiledir}/../../../include)
  inc=$(for f in $flags; do case "$f" in -I*) echo "${f#-I}";; esac; done | head -1)
  same_dir "$inc" "$PREFIX/include" || { echo "FAIL: pkg-config $p: no -I$PREFIX/include in: $flags"; exit 1; }
  case " $flags " in *" -llightgraph "*) ;; *) echo "FAIL: pkg-config $p: no -llightgraph in: $flags"; exit 1 ;; esac
done
case " $(pkg-config --libs lightgraph-cl) " in *" -lOpenCL "*) ;; *)
  echo "FAIL: pkg-config lightgraph-cl does not link OpenCL: $(pkg-config --libs lightgraph-cl)"; exit 1 ;; esac
case " $(pkg-config --libs lightgraph-test) " in *" -llightgraph-test "*) ;; *)
  echo "FAIL: pkg-config lightgraph-test does not link the harness"; exit 1 ;; esac

# The GLSL and OpenCL C twins of the SDK's contracts, as in the source tree, where the
# pkg-config variable says; embed.py resolves an #include of one with -I that folder, and
# the installed embed.py by itself.
shadersdir=$(pkg-config --variable=shadersdir lightgraph)
same_dir "$shadersdir" "$PREFIX/share/lightgraph/shaders" || { echo "FAIL: shadersdir is '$shadersdir'"; exit 1; }
for f in rgbe.glsl rgbe.cl probe.glsl probe.cl medium.glsl medium.cl; do
  cmp -s "$SRC/shaders/common/$f" "$shadersdir/$f" || { echo "FAIL: shader twin $f not installed in $shadersdir"; exit 1; }
done
embed=$(pkg-config --variable=embed lightgraph)
mkdir "$TMP/sh"
printf '#version 450\n#include "rgbe.glsl"\n#include "probe.glsl"\nvoid main() {}\n' >"$TMP/sh/t.comp"
python3 "$embed" -I "$shadersdir" "$TMP/sh/t.comp" "$TMP/sh/a.h" || { echo "FAIL: embed.py -I shadersdir"; exit 1; }
python3 "$embed" "$TMP/sh/t.comp" "$TMP/sh/b.h" || { echo "FAIL: the installed embed.py does not find the twins by itself"; exit 1; }
for h in a b; do
  grep -q "GLSL source strings: 0 t.comp, 1 .*rgbe.glsl, 2 .*probe.glsl" "$TMP/sh/$h.h" || {
    head -5 "$TMP/sh/$h.h"; echo "FAIL: embed.py did not include the installed twins ($h.h)"; exit 1; }
done

# The test data: an image and a scene that the installed program renders.
testdata=$(pkg-config --variable=testdatadir lightgraph)
for f in forest_256x128.exr cornell_box.gltf README.md LICENSE-CC0.txt LICENSE-Apache-2.0.txt; do
  [ -f "$testdata/$f" ] || { echo "FAIL: test data $f not installed in $testdata"; exit 1; }
done
printf 'lightgraph 1\nsrc = image { file = "%s/forest_256x128.exr" }\noutput src "%s/forest.exr"\n' \
  "$testdata" "$TMP" >"$TMP/td_image.lgraph"
printf 'lightgraph 1\nscene = gltf { file = "%s/cornell_box.gltf" }\nview = preview { scene = scene }\noutput view "%s/box.png"\n' \
  "$testdata" "$TMP" >"$TMP/td_scene.lgraph"
"$EXE" render "$TMP/td_image.lgraph" -q && [ -s "$TMP/forest.exr" ] || { echo "FAIL: render the installed test image"; exit 1; }
if ! "$EXE" render "$TMP/td_scene.lgraph" --size 32x24 -q 2>"$TMP/td.err"; then
  cat "$TMP/td.err"
  grep -q 'no OpenGL 4.5 device' "$TMP/td.err" || { echo "FAIL: render the installed test scene"; exit 1; }
fi

export PKG_CONFIG_PATH="$(dirname "$pc")"
export PKG_CONFIG_SYSROOT_DIR="$TMP/root"
[ -f "$PREFIX/share/lightgraph/template/meson.build" ] || { echo "FAIL: the template is not installed"; exit 1; }
cp -r "$SRC/sdk/template" "$TMP/template"
san=""
if [ -n "${LG_SANITIZE:-}" ] && [ "$LG_SANITIZE" != none ]; then
  san="-Db_sanitize=$LG_SANITIZE -Db_lundef=false"
fi
# shellcheck disable=SC2086 # $san is two words or none
(cd "$TMP/template" && meson setup build $san >"$TMP/setup.log" 2>&1 && ninja -C build >"$TMP/ninja.log" 2>&1) || {
  cat "$TMP/setup.log" "$TMP/ninja.log" 2>/dev/null; echo "FAIL: template build"; exit 1; }
# The template, built against the installed SDK, exports lg_plugin_entry only (the rule of
# tests/unit/abi, plugin_exports, for every in-tree plugin).
sh "$SRC/tests/unit/abi/check_exports.sh" "$TMP/template/build/lg_acme_blur.so" || {
  echo "FAIL: the template plugin exports more than lg_plugin_entry"; exit 1; }
export LIGHTGRAPH_PLUGIN_PATH="$TMP/template/build"
# From here on the installed program, not the build's.
LG_EXE="$EXE"
"$LG_EXE" inspect acme_blur --json | grep -q '"sigma"' || { echo "FAIL: inspect acme_blur"; exit 1; }
cat >"$TMP/g.lgraph" <<G
lightgraph 1
c = constant { color = [0.25, 0.5, 0.75] }
blur = acme_blur { image = c, sigma = 1 }
output blur "$TMP/out.exr"
G
"$LG_EXE" render "$TMP/g.lgraph" --size 4x2 -q
cat >"$TMP/e.lgraph" <<G
lightgraph 1
c = constant { color = [0.25, 0.5, 0.75] }
output c "$TMP/expected.exr"
G
"$LG_EXE" render "$TMP/e.lgraph" --size 4x2 -q
"$LG_EXE" diff "$TMP/out.exr" "$TMP/expected.exr" --max-abs 0.001 >/dev/null || {
  echo "FAIL: acme_blur changed a constant image"; exit 1; }
# backend = gl runs the template's compute shader, embedded by the installed embed.py with
# its #include resolved (shaders/blur.comp includes shaders/common/acme_blur.glsl)
h=$(find "$TMP/template/build" -name 'blur.comp.h' | head -1)
[ -n "$h" ] && grep -q 'GLSL source strings: 0 blur.comp, 1 acme_blur.glsl' "$h" || {
  echo "FAIL: the template's shader was not embedded by the installed embed.py with its #include"; exit 1; }
sed 's/sigma = 1 }/sigma = 1, backend = gl }/; s#out.exr#out_gl.exr#' "$TMP/g.lgraph" >"$TMP/g_gl.lgraph"
if ! "$LG_EXE" render "$TMP/g_gl.lgraph" --size 40x24 -q 2>"$TMP/gl.err"; then
  cat "$TMP/gl.err"
  if grep -q 'no OpenGL 4.5 device' "$TMP/gl.err"; then
    echo "SKIP: no GL device: the template's gl backend is not run"; exit 77
  fi
  echo "FAIL: acme_blur backend = gl"; exit 1
fi
"$LG_EXE" render "$TMP/e.lgraph" --size 40x24 -q
"$LG_EXE" diff "$TMP/out_gl.exr" "$TMP/expected.exr" --max-abs 0.001 >/dev/null || {
  echo "FAIL: acme_blur backend = gl changed a constant image"; exit 1; }
# The template's own test, on the installed harness (liblightgraph-test), without LG_EXE:
# the harness runs the program installed beside its library. One case here (every case, on
# every backend: tests/unit/template_ci).
(unset LG_EXE; meson test -C "$TMP/template/build" --print-errorlogs range >"$TMP/test.log" 2>&1) || {
  cat "$TMP/test.log"; echo "FAIL: the template's test on the installed harness"; exit 1; }
(unset LG_EXE; LG_TEST_VERBOSE=1 "$TMP/template/build/test_template" range >"$TMP/verbose.log" 2>&1) || {
  cat "$TMP/verbose.log"; echo "FAIL: test_template range"; exit 1; }
grep -q "^\\$ $EXE " "$TMP/verbose.log" || {
  cat "$TMP/verbose.log"; echo "FAIL: the harness did not run the host installed beside it ($EXE)"; exit 1; }
grep -E '^ *[0-9]+/[0-9]+ ' "$TMP/test.log"
grep -Eq '^Ok: +1 *$' "$TMP/test.log" || { cat "$TMP/test.log"; echo "FAIL: the template's test 'range' did not pass"; exit 1; }
harness=$(ldd "$TMP/template/build/test_template" | awk '/liblightgraph-test\.so/ {print $3}')
[ -n "$harness" ] && same_dir "$(dirname "$harness")" "$libdir" || {
  ldd "$TMP/template/build/test_template"; echo "FAIL: test_template does not use the installed harness"; exit 1; }
# A host that cannot start (its liblightgraph not found: a copy of the program away from
# its prefix): the harness says so with the loader's message, exits 99 (a harness error,
# not a failed check), and names the scratch folder it keeps.
mkdir -p "$TMP/lonely/bin"
cp "$EXE" "$TMP/lonely/bin/lightgraph"
set +e
LG_EXE="$TMP/lonely/bin/lightgraph" "$TMP/template/build/test_template" range >"$TMP/lonely.log" 2>&1
rc=$?
set -e
[ $rc -eq 99 ] || { cat "$TMP/lonely.log"; echo "FAIL: a host that cannot start: exit $rc, not 99"; exit 1; }
grep -q "could not start (exit 127" "$TMP/lonely.log" && grep -q "liblightgraph.so.*cannot open shared object file" "$TMP/lonely.log" || {
  cat "$TMP/lonely.log"; echo "FAIL: a host that cannot start is not named with the loader's message"; exit 1; }
if grep -q "LIGHTGRAPH_PLUGIN_PATH" "$TMP/lonely.log"; then
  cat "$TMP/lonely.log"; echo "FAIL: a host that cannot start is blamed on the plugin path"; exit 1
fi
kept=$(sed -n 's/^lightgraph-test: scratch folder kept: //p' "$TMP/lonely.log")
[ -n "$kept" ] && [ -d "$kept" ] || { cat "$TMP/lonely.log"; echo "FAIL: the harness did not name the scratch folder it kept"; exit 1; }
rm -rf "$kept"

echo "ok: the installed prefix works without LD_LIBRARY_PATH (host, its plugins, the harness finding the host); pkg-config lightgraph, -gl, -cl, -test; shader twins and test data; the template builds (its shader embedded by the installed embed.py), runs on cpu and gl, and its test runs on the installed harness; a host that cannot start is named"
