"""The accuracy atlas's probe section (docs/probes.md, plugins/ibl/README.md): what a light
probe's storage and filtering cost in image-based lighting, through ibl's `reflect` on the
scene of examples/ibl.lgraph. Folds in the retired tools/format_study.py (rgba32f, rgba16f,
rgbe8) and tools/prefilter_study.{py,gp} (whose C program, tools/prefilter_study.c, is the
Custom study against the Monte Carlo oracle: _prefilter.py runs it).
"""
import os
import sys

from accuracy.study import Custom, Study

TITLE = "Light probes: formats, layouts, glossy prefiltering"
ORDER = 45
TARGET = None

INTRO = """Image-based lighting with `reflect` ([docs/probes.md](probes.md),
[plugins/ibl/README.md](../plugins/ibl/README.md)): the mirror sphere, the glossy gold sphere
and the copper bunny of `examples/ibl.lgraph` under the forest probe at 256 x 128
(`assets/probes/forest_256x128_half_none.exr`), on the CPU backend; the HDR output of
`reflect` (before tone mapping) is compared. There is no path-traced oracle of this scene in
the plugins, so each image study's reference is the node at its most exact setting, named in
its table: rgba32f for the pixel formats, the lat-long probe as loaded (no conversion) for
the layouts, 4096 samples per texel for the prefilter. The prefilter's bias (the split sum
against the real GGX integral) is measured by the last study, `tools/prefilter_study.c`,
against the Monte Carlo oracle `lg_probe_ggx_reference` (65,536 samples per direction) at
n = v over five roughnesses and 32 normals.

**Knobs**: `reflect.format` (rgba32f, rgba16f, rgbe8; once as the probe is and once 2^12
brighter, a sun in physical units beyond half's 65504), the probe's layout (`probe_convert`:
angular and cube at the source's texel count and at size 64, lat-long at heights 32 and 64;
every cube file layout, cross, strip and their vertical forms, is the same cube resource),
and the glossy prefilter's samples per texel (`prefilter_samples`, both weightings, 64^2
faces). The format and layout studies render every material as a mirror (`glossy = off`:
the lookups alone, no GGX chain); the prefilter studies build the chain in every run (the
sweeps run with the on-disk cache off). Time: the `refl` node (`reflect`). Error: relative
RMSE over the image and RGB (DSSIM beside it). The front mixes these references: each row
is as exact as its own study's reference says."""


# the forest at 256x128 (box-reduced from the 1024x512 one): the GGX chain of 64^2 faces is
# made from it in about a second, from the 1024x512 one in 5 to 13 s (2 cores, loaded)
PROBE = "assets/probes/forest_256x128_half_none.exr"


def _graph(ctx, name, probe_lines, probe_node):
    root = ctx.root
    return ctx.write(name, (
        "lightgraph 1\n"
        'scene = gltf { file = "%s" }\n'
        "cam = camera { scene = scene, mode = look_at, position = [0, 1.3, 9.5], "
        "target = [0, 0.95, 0], fov_deg = 30 }\n"
        "%s"
        "env = environment { scene = cam, probe = %s }\n"
        "bg = background { scene = env, probe = %s, backend = cpu }\n"
        "refl = reflect { scene = env, probe = %s, base = bg, fresnel = schlick, "
        "backend = cpu, prefilter_size = %d }\n"
        'output refl "refl.exr"\n') % (os.path.join(root, "assets", "meshes", "ibl_spheres.glb"),
                                       probe_lines, probe_node, probe_node, probe_node,
                                       16 if ctx.quick else 64))


def studies(ctx):
    q = ctx.quick
    probe = os.path.join(ctx.root, PROBE)
    sky = 'sky = probe { file = "%s" }\n' % probe
    graph = _graph(ctx, "ibl.lgraph", sky, "sky")
    conv = _graph(ctx, "ibl_convert.lgraph",
                  sky + "conv = probe_convert { probe = sky, layout = latlong, size = 0 }\n",
                  "conv")
    size, quick_size = "320x180", "64x36"
    common = dict(technique="reflect", backend="cpu", time_node="refl", size=size,
                  quick_size=quick_size, repeat=3, metric="rel_rmse")
    out = [
        Study(id="probe_format", title="reflect: output format (the forest probe)",
                      graph=graph, sets=["refl.glossy=off"],
                      vary=[("refl.format", ["rgba32f", "rgba16f", "rgbe8"])],
                      quick_vary=[("refl.format", ["rgba32f", "rgba16f", "rgbe8"])],
                      ref_sets=["refl.format=rgba32f"],
                      reference_label="reflect in rgba32f", **common),
        Study(id="probe_format_sun",
                      title="reflect: output format (the forest probe 2^12 brighter)",
                      graph=graph, sets=["sky.exposure=12", "refl.glossy=off"],
                      vary=[("refl.format", ["rgba32f", "rgba16f", "rgbe8"])],
                      quick_vary=[("refl.format", ["rgba32f", "rgba16f", "rgbe8"])],
                      ref_sets=["refl.format=rgba32f"],
                      reference_label="reflect in rgba32f, sky.exposure = 12", **common),
        Study(id="probe_layout",
                      title="probe_convert: layout x size (0: the source's texel count)",
                      graph=conv, reference=graph, sets=["refl.glossy=off"],
                      ref_sets=["refl.glossy=off"],
                      vary=[("conv.layout", ["angular", "cross"]), ("conv.size", ["0", "64"])],
                      quick_vary=[("conv.layout", ["angular", "cross"]),
                                  ("conv.size", ["0"])],
                      reference_label="the 256x128 lat-long probe as loaded (no conversion)",
                      **common),
        # lat-long to lat-long at size 0 is the reference itself (its texels copied): only
        # the smaller sizes
        Study(id="probe_layout_latlong",
                      title="probe_convert: lat-long resampled smaller (size = its height)",
                      graph=conv, reference=graph, sets=["refl.glossy=off"],
                      ref_sets=["refl.glossy=off"],
                      vary=[("conv.size", ["32", "64"])], quick_vary=[("conv.size", ["32"])],
                      reference_label="the 256x128 lat-long probe as loaded (no conversion)",
                      **common),
    ]
    for w in ("nol", "nol_vis"):
        out.append(Study(
            id="probe_prefilter_%s" % w,
            title="reflect: prefilter samples per texel (%s weighting, 64^2 faces)" % w,
            graph=graph, sets=["refl.prefilter_weighting=%s" % w],
            vary=[("refl.prefilter_samples", ["16", "64", "256", "1024"])],
            quick_vary=[("refl.prefilter_samples", ["16", "64"])],
            ref_sets=["refl.prefilter_samples=%d" % (256 if q else 4096)],
            reference_label="the same chain with %d samples per texel" % (256 if q else 4096),
            **common))
    out.append(Custom(
        id="probe_prefilter_oracle",
        title="GGX prefilter: split sum against the Monte Carlo oracle (n = v)",
        technique="reflect", backend="cpu",
        command=[sys.executable, os.path.join(ctx.root, "tools", "accuracy", "sections",
                                              "_prefilter.py"),
                 "--build", "{build}", "--out", "{out}", "--root", "{root}", "{quick}"],
        csv="prefilter.csv",
        reference_label="lg_probe_ggx_reference, %d samples per direction"
                        % (4096 if q else 65536),
        metric="rel_rmse"))
    return out
