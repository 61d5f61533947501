# The README's two commands: `make demo` and `make test` (and `make fuzz`, docs/fuzzing.md).
# Both install missing Debian packages (as root; otherwise they print the apt-get line),
# configure, build, then render the default example / run the whole test suite.

BUILD      ?= build
ASAN_BUILD ?= build-asan
MESON_OPTS ?= -Dwerror=true
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)

FUZZ_BUILD ?= build-fuzz
SECONDS    ?= 60

.PHONY: all deps build demo test test-sanitize fuzz bench accuracy accuracy-quick \
	study-prefilter study-format study-prt \
	pictures-prt pictures-sh bench-volumetric study-volumetric pictures-volumetric format format-check stability \
	clean

all: build

deps:
	@sh tools/deps.sh

$(BUILD)/build.ninja:
	@sh tools/deps.sh
	meson setup $(BUILD) $(MESON_OPTS)

build: $(BUILD)/build.ninja
	ninja -C $(BUILD)

# Renders the default example into out/ and prints the per-node profile.
demo: build
	@mkdir -p out
	$(BUILD)/lightgraph render examples/demo.lgraph -o out/demo.png --profile --explain
	@echo "wrote out/demo.png"

# Runs every suite; the last line is 'N passed, N failed, N skipped'.
test: build
	-meson test -C $(BUILD) --num-processes $(JOBS) --print-errorlogs
	@python3 tools/test_summary.py $(BUILD)

# docs/stability.md: every hard case with its policy, backends and status in the last run
# (tools/stability.py reads tests/stability.toml, meson's tests and BUILD's testlog.json).
# Run it after `make test`; it fails, naming each, on a hard case without its test or a
# test of suite 'stability' without its entry. Adding a hard case: docs/stability.md's head.
stability:
	python3 tools/stability.py --build $(BUILD) --out docs/stability.md

# The same suite in an ASan+UBSan build.
$(ASAN_BUILD)/build.ninja:
	@sh tools/deps.sh
	meson setup $(ASAN_BUILD) $(MESON_OPTS) -Db_sanitize=address,undefined -Db_lundef=false \
	  -Dbuildtype=debug

test-sanitize: $(ASAN_BUILD)/build.ninja
	ninja -C $(ASAN_BUILD)
	-meson test -C $(ASAN_BUILD) --num-processes $(JOBS) --print-errorlogs --timeout-multiplier 4
	@python3 tools/test_summary.py $(ASAN_BUILD)

# Every libFuzzer target (tests/fuzz) for SECONDS seconds each, in its own build with
# Debian's clang, ASan and UBSan, memory bounded; a finding is copied into the target's
# seed corpus (tests/fuzz/corpus_NAME/finding-SHA1) and fails the command. docs/fuzzing.md.
FUZZ_TARGETS = graph image gltf cache registry probe cache_kinds script sweep tune

$(FUZZ_BUILD)/build.ninja:
	@sh tools/deps.sh fuzz
	CC=clang CXX=clang++ meson setup $(FUZZ_BUILD) $(MESON_OPTS) -Dfuzzing=true \
	  -Db_sanitize=address,undefined -Db_lundef=false -Dbuildtype=debugoptimized

fuzz: $(FUZZ_BUILD)/build.ninja
	ninja -C $(FUZZ_BUILD) $(addprefix tests/fuzz/fuzz_,$(FUZZ_TARGETS))
	python3 tools/fuzz.py --build $(FUZZ_BUILD) --seconds $(SECONDS) $(FUZZ_TARGETS)

bench: build
	ninja -C $(BUILD) bench-reinhard
	ninja -C $(BUILD) bench-prt
	ninja -C $(BUILD) bench-prt-bake
	ninja -C $(BUILD) bench-froxel

# What accuracy costs, for every technique: docs/accuracy.md, its plots and images in
# docs/images/accuracy/ (tools/accuracy/accuracy.py; how a technique adds its section:
# tools/accuracy/README.md). All or nothing; under 20 minutes on 2 cores. ONLY=phong,reinhard
# remakes those sections and keeps the others; TARGET=0.05 answers for 5% instead of 1%;
# KEEP_GOING=1 writes the sections that finished when one fails (it keeps the page's own).
# accuracy-quick: tiny sizes, two points per knob, into out/accuracy (what the test runs).
accuracy: build
	python3 tools/accuracy/accuracy.py --build $(BUILD) --out docs $(if $(ONLY),--only $(ONLY),) \
	  $(if $(TARGET),--target $(TARGET),) $(if $(KEEP_GOING),--keep-going,)

accuracy-quick: build
	mkdir -p out
	python3 tools/accuracy/accuracy.py --build $(BUILD) --out out/accuracy --quick \
	  $(if $(ONLY),--only $(ONLY),)

# The old studies, now sections of docs/accuracy.md (tools/accuracy/sections/): the probe
# formats, layouts and the glossy prefilter (tools/format_study.py, prefilter_study.py
# retired; tools/prefilter_study.c is the section's oracle study) and PRT's bands, samplers,
# samples, visibility, bounces and backends (tools/prt_study.py, sh_project_study.py retired).
study-prefilter study-format: build
	$(MAKE) accuracy ONLY=probe

study-prt: build
	$(MAKE) accuracy ONLY=prt

# The pictures of docs/prt.md: examples/prt.lgraph with each transfer mode.
pictures-prt: build
	for m in unshadowed shadowed interreflected; do \
	  $(BUILD)/lightgraph render examples/prt.lgraph --size 480x270 --set bake.mode=$$m \
	    -o docs/images/prt_$$m.png || exit 1; done

# Seed 0's figure of the lighting reconstructed with 1, 3, 5 and 7 bands (docs/sh.md, "Seeing
# the reconstruction"): examples/sh_background.lgraph at each band count, and the probe.
pictures-sh: build
	for b in 1 3 5 7; do \
	  $(BUILD)/lightgraph render examples/sh_background.lgraph --size 512x256 \
	    --set seen.bands=$$b -o docs/images/sh_bands_$$b.png || exit 1; done
	$(BUILD)/lightgraph render examples/sh_background.lgraph --size 512x256 \
	  --set exposure.image=panorama -o docs/images/sh_bands_probe.png

# The volumetric thesis's experiments (seed 2, chapter 4), as they came out: time against
# output size for every method and "disabled" (where the ranking flips), the thesis's Table 6
# per scene with measured triangle counts and the polygonal node's fragment counters, time and
# peak memory against 1..8 lights, the cost of gated nodes; each configuration 3 times
# (medians, min-max). Over an hour on the shared 2 cores (QUICK=1: a few-minute smoke run;
# BENCH_ARGS for more or less, e.g. --scenes bunny,dragon). Tables and plots into
# docs/images/volumetric/ (docs/volumetric.md, "The thesis's experiments").
bench-volumetric: build
	mkdir -p out docs/images/volumetric
	rm -f out/bench_volumetric/*.png
	python3 tools/bench_volumetric.py --build $(BUILD) --out out/bench_volumetric \
	  --frames 2 --repeat 3 $(if $(QUICK),--quick,) $(BENCH_ARGS)
	cp out/bench_volumetric/bench_volumetric.md out/bench_volumetric/*.csv \
	  out/bench_volumetric/*.png docs/images/volumetric/

# The thesis's interiors (tools/gen_scene.py classroom and courtyard; docs/volumetric.md, "The
# thesis's interiors"): generated, never committed; examples/classroom.lgraph and
# courtyard.lgraph read them from out/scenes/. The courtyard (3.4 million triangles, 65 MB)
# takes about 40 s.
.PHONY: scenes
scenes:
	mkdir -p out/scenes
	python3 tools/gen_scene.py classroom -o out/scenes/classroom.glb
	python3 tools/gen_scene.py courtyard -o out/scenes/courtyard.glb

# What volumetric accuracy costs: the accuracy atlas's volumetric section alone
# (tools/accuracy/sections/volumetric.py; docs/accuracy.md#volumetric), 3 to 6 minutes.
study-volumetric:
	$(MAKE) accuracy ONLY=volumetric,volumetric_lights,volumetric_media KEEP_GOING=1

# The pictures of docs/volumetric.md: the four examples side by side, in-scatter and error.
pictures-volumetric: build
	mkdir -p docs/images/volumetric
	python3 tools/volumetric_pictures.py --build $(BUILD) --out docs/images/volumetric

# The C and C++ sources in the house style (.clang-format, clang-format 14; docs/style.md):
# format-check lists each file that is not, with its first diff hunk, and fails; format
# rewrites them in place. FILES="a.c b.h" limits either to those files.
format:
	@sh tools/deps.sh
	sh tools/format.sh --fix $(FILES)

format-check:
	@sh tools/deps.sh
	sh tools/format.sh --check $(FILES)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(FUZZ_BUILD) out
