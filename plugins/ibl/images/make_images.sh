#!/bin/sh
# Makes the pictures of plugins/ibl/README.md (320x180) from a build in ../../../build.
# Run from this folder: ./make_images.sh
set -e
B=../../../build
"$B/lightgraph" render refl_vs_env.lgraph --size 320x180 -q
LIGHTGRAPH_PLUGIN_PATH="$B/tests/plugins/ibl" "$B/lightgraph" render roughness.lgraph --size 320x120 -q
"$B/lightgraph" render ../../../examples/ibl.lgraph --size 320x180 -o ibl.png -q
