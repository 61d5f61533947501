#!/bin/sh
# The SDK template as a plugin author meets it (docs/plugin-guide.md, section 1): lightgraph
# installed into a fresh prefix, then, with no environment variable but PATH, HOME,
# PKG_CONFIG_PATH and LIGHTGRAPH_PLUGIN_PATH (env -i: no LD_LIBRARY_PATH, no LG_EXE, no
# LIGHTGRAPH_* of the build tree):
#   1. the installed template (PREFIX/share/lightgraph/template) copied and built out of tree
#      with pkg-config only, a release build;
#   2. its tests (meson test) on the installed harness, which runs the installed host;
#   3. the plugin exports lg_plugin_entry alone;
#   4. lightgraph conform on it;
#   5. graphs rendered with it by the installed host on each backend: a constant image stays
#      that constant, and the installed test image is blurred alike by cpu, gl and cl.
# A failure keeps the folder and names it.
set -eu
TMP=$(mktemp -d "${TMPDIR:-/tmp}/lg-template-ci-XXXXXX")
ok=0
trap 'if [ $ok = 1 ]; then rm -rf "$TMP"; else echo "kept: $TMP"; fi' EXIT
fail() { echo "FAIL: $*"; exit 1; }

meson install -C "$LG_BUILD_ROOT" --destdir "$TMP/root" --no-rebuild --quiet \
  >"$TMP/install.log" 2>&1 || { cat "$TMP/install.log"; fail "meson install"; }
exe=$(find "$TMP/root" -path '*/bin/lightgraph' -type f | head -1)
[ -n "$exe" ] || fail "no bin/lightgraph installed"
PREFIX=$(dirname "$(dirname "$exe")")
pc=$(find "$PREFIX" -name lightgraph.pc | head -1)
[ -n "$pc" ] || fail "no lightgraph.pc installed"
grep -q '^prefix=${pcfiledir}/' "$pc" || fail "$pc says '$(grep '^prefix=' "$pc")': the \
pkg-config files of this build are not relocatable, so an installed prefix needs more than \
PKG_CONFIG_PATH; a fresh build dir has it (meson.build's default), an older one needs \
meson configure BUILD -Dpkgconfig.relocatable=true"
[ -f "$PREFIX/share/lightgraph/template/meson.build" ] || fail "the template is not installed"
cp -r "$PREFIX/share/lightgraph/template" "$TMP/template"
mkdir "$TMP/home"

# The sanitizer build: the template gets the same sanitizers (an ASan library can only be
# loaded into a program that has the ASan runtime), and the sanitizers their options.
san="" san_env=""
if [ -n "${LG_SANITIZE:-}" ] && [ "$LG_SANITIZE" != none ]; then
  san="-Db_sanitize=$LG_SANITIZE -Db_lundef=false"
  san_env="ASAN_OPTIONS=${ASAN_OPTIONS:-} LSAN_OPTIONS=${LSAN_OPTIONS:-} UBSAN_OPTIONS=${UBSAN_OPTIONS:-}"
fi
# shellcheck disable=SC2086 # $san_env: words or none
author() {
  env -i PATH="$PATH" HOME="$TMP/home" PKG_CONFIG_PATH="$(dirname "$pc")" \
    LIGHTGRAPH_PLUGIN_PATH="$TMP/template/build" $san_env "$@"
}

# 1. build, pkg-config only
# shellcheck disable=SC2086
(cd "$TMP/template" && author meson setup build $san >"$TMP/setup.log" 2>&1 &&
  author ninja -C build >"$TMP/ninja.log" 2>&1) || {
  cat "$TMP/setup.log" "$TMP/ninja.log" 2>/dev/null; fail "the template does not build"; }
python3 -c 'import json, sys
o = {x["name"]: x["value"] for x in json.load(open(sys.argv[1]))}
sys.exit(0 if o["buildtype"] == "release" else 1)' "$TMP/template/build/meson-info/intro-buildoptions.json" ||
  fail "the template is not a release build by default"
so="$TMP/template/build/lg_acme_blur.so"
[ -f "$so" ] || fail "no lg_acme_blur.so built"

# 2. its tests, on the installed harness and host
(cd "$TMP/template" && author meson test -C build --print-errorlogs >"$TMP/test.log" 2>&1) || {
  cat "$TMP/test.log"; fail "the template's tests"; }
grep -E '^ *[0-9]+/[0-9]+ ' "$TMP/test.log"
grep -Eq '^Ok: +5 *$' "$TMP/test.log" || {
  cat "$TMP/test.log"; fail "the template's 5 tests did not all pass (a skip: a device missing)"; }

# 3. one exported symbol
syms=$(nm -D --defined-only "$so" | awk '$2 ~ /^[TDBRi]$/ {print $3}' | sort | tr '\n' ' ')
[ "$syms" = "lg_plugin_entry " ] || fail "lg_acme_blur.so exports '$syms', not lg_plugin_entry alone"

# 4. conform
author "$exe" conform "$so" >"$TMP/conform.log" 2>&1 || {
  cat "$TMP/conform.log"; fail "lightgraph conform lg_acme_blur.so"; }

# 5. a render through the installed host, on every backend: the blur of a constant image is
# that constant (the weights sum to 1; clamp to edge) within float rounding
cat >"$TMP/c.lgraph" <<G
lightgraph 1
c = constant { color = [0.25, 0.5, 0.75] }
blur = acme_blur { image = c, sigma = 3 }
output blur "out.exr"
G
cat >"$TMP/e.lgraph" <<G
lightgraph 1
c = constant { color = [0.25, 0.5, 0.75] }
output c "expected.exr"
G
cd "$TMP"
author "$exe" render e.lgraph --size 24x16 -q || fail "render of the expected image"
for b in cpu gl cl; do
  author "$exe" render c.lgraph --size 24x16 -q --set blur.backend=$b 2>"$TMP/$b.err" ||
    { cat "$TMP/$b.err"; fail "render with acme_blur, backend $b"; }
  author "$exe" diff out.exr expected.exr --max-abs 1e-6 >/dev/null ||
    fail "acme_blur backend $b changed a constant image"
  rm -f out.exr
done
# ... and the installed test image (pkg-config testdatadir) blurred on each backend: gl and
# cl agree with cpu within the node's tolerance, 1e-5 x max(1, largest value), the image's
# largest being about 450 (measured: gl 0, cl 3.8e-6)
testdata=$(author pkg-config --variable=testdatadir lightgraph)
[ -f "$testdata/forest_256x128.exr" ] || fail "no test image in testdatadir '$testdata'"
cat >"$TMP/f.lgraph" <<G
lightgraph 1
src = image { file = "$testdata/forest_256x128.exr" }
blur = acme_blur { image = src, sigma = 2 }
output blur "forest.exr"
G
for b in cpu gl cl; do
  author "$exe" render f.lgraph -q --set blur.backend=$b 2>"$TMP/$b.err" ||
    { cat "$TMP/$b.err"; fail "render of the test image with acme_blur, backend $b"; }
  mv forest.exr "forest_$b.exr"
done
author "$exe" diff forest_cpu.exr forest_gl.exr --max-abs 4.5e-3 >/dev/null ||
  fail "acme_blur: gl and cpu differ on the installed test image"
author "$exe" diff forest_cpu.exr forest_cl.exr --max-abs 4.5e-3 >/dev/null ||
  fail "acme_blur: cl and cpu differ on the installed test image"
ok=1
echo "ok: the installed template builds with pkg-config only, passes its 5 tests on the" \
  "installed harness, exports lg_plugin_entry alone, passes conform and renders on cpu, gl" \
  "and cl through the installed host (a constant image kept, the installed forest_256x128.exr" \
  "blurred alike); environment: PATH, HOME, PKG_CONFIG_PATH," \
  "LIGHTGRAPH_PLUGIN_PATH"
