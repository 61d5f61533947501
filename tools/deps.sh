#!/bin/sh
# Makes sure the Debian packages lightgraph needs are installed.
# As root: installs what is missing with apt-get. Otherwise: prints the exact apt-get line
# and fails, so that nothing half-works.
#
#   sh tools/deps.sh        what building, `make demo` and `make test` need (clang-format:
#                           Debian 12's, version 14, for `make format` and the test
#                           rules_format; docs/style.md; libopenvdb-dev for the medium
#                           node's VDB grids, with libboost-dev, whose headers OpenVDB's
#                           include but Debian's package does not depend on; Open MPI,
#                           libopenmpi-dev and openmpi-bin, for `mpirun -np N lightgraph`:
#                           docs/distributed.md)
#   sh tools/deps.sh fuzz   that, and what `make fuzz` needs besides (docs/fuzzing.md):
#                           Debian's clang (14 in bookworm) and its compiler-rt, which
#                           holds libFuzzer and the sanitizers' runtimes (libclang-rt-dev,
#                           which is libclang-rt-14-dev there). Optional: the suite's fuzz
#                           tests are plain programs built with gcc.
set -e
PKGS="meson ninja-build pkg-config gcc g++ python3 python3-glad
libosmesa6-dev libegl-dev libegl1-mesa-dev libglfw3-dev
ocl-icd-opencl-dev opencl-headers pocl-opencl-icd
libopenexr-dev libpng-dev glslang-tools gnuplot-nox pfstools pfstmo
libtinygltf-dev libdraco-dev nlohmann-json3-dev libjpeg62-turbo-dev libembree-dev xvfb abigail-tools
clang-format libopenvdb-dev libboost-dev libopenmpi-dev openmpi-bin"
FUZZ_PKGS="clang libclang-rt-dev"
case "${1:-}" in
  "") ;;
  fuzz) PKGS="$PKGS $FUZZ_PKGS" ;;
  *) echo "usage: sh tools/deps.sh [fuzz]" >&2; exit 2 ;;
esac
missing=""
for p in $PKGS; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing="$missing $p"
  fi
done
[ -z "$missing" ] && exit 0
if [ "$(id -u)" = 0 ]; then
  echo "lightgraph: installing missing packages:$missing" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends $missing >&2
else
  echo "lightgraph: missing Debian packages. Install them with:" >&2
  echo "  sudo apt-get install -y$missing" >&2
  exit 1
fi
