"""Volumetric lighting: every volumetric method's knobs (volumetric_screen, volumetric_polygonal,
volumetric_froxel on each of its backends) per light type and medium kind the plugins
support, against volumetric_reference. Folds in and retires tools/volumetric_study.py.

Two things here are not one plain `lightgraph sweep`, so every study is a Custom one run by
this file itself (`python3 tools/accuracy/sections/volumetric.py run SPEC OUT`):

- the reference (about 40 s at 320 x 180 on this machine) is rendered once per light and
  medium case, timed (its whole render, from --profile-json, as sweep's ref_ms) and shared
  by every study of the case through a graph of one `image` node; a sweep per study would
  render it again each time (minutes);
- the froxel grid is one knob, `vol.grid` = "WxHxD" (width, height and depth set together):
  sweep's --vary is a cartesian product of independent knobs, and the answer must name a
  grid ("froxel 95x45x64 exponential"), not a depth at a fixed width and height. A linked
  knob runs one sweep per value, the other knobs varied within it, and the rows are merged.

Adding a light type or a medium kind is one more entry in LIGHTS or MEDIA (the node it puts
in place of the example scene's `sun` or `fog`, and the methods that support it); adding a
knob to a method is one more entry in PLANS. Plain Python 3.11 standard library.
"""
import csv
import fcntl
import json
import math
import os
import re
import shutil
import subprocess
import sys

if __name__ == "__main__":  # run as a program: the accuracy package is tools/accuracy
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))))

from accuracy.study import ROW_COLUMNS, Custom, StudyError  # noqa: E402

TITLE = "Volumetric lighting"
ORDER = 60
INTRO = """\
Single scattering in a participating medium, by the three real-time methods of
[docs/volumetric.md](volumetric.md): screen-space light shafts (`volumetric_screen`, Mitchell
2007; gl and cpu), polygonal light volumes (`volumetric_polygonal`, Billeter et al. 2010; gl)
and froxel grids (`volumetric_froxel`, Wronski 2014; gl, cl and cpu). Scene: the examples'
bunny box filled with fog (`examples/volumetric_scene.lgraph`: density 1, sigma_s 0.1,
g 0.4) and a low sun shining in through its open side (L_c = 10), each method with its
example's settings (`examples/volumetric_<method>.lgraph`) but the knobs swept.
**Light types and media** (issue 25): this section is the example's sun in the homogeneous
fog; point and spot lights are [the next section but one](#volumetric_lights), fBm noise,
height fog and a VDB cloud [the one after](#volumetric_media) (each case costs a reference
render: a section of its own is made again without the others; their cases and runner are
this section's file).
**Reference:** `volumetric_reference`, the same integral ray-marched per pixel with exact
visibility (Embree rays towards the sun, not shadow maps) and the transmittance integrated
analytically over each step; 1024 steps and 4 rays per pixel, every ray through the pixel
centre (as the methods sample: their error holds no antialiasing term). Its own error at 256
steps is 0.13 % and falls as 1/steps
([plugins/volumetric_reference/README.md](../plugins/volumetric_reference/README.md)), so
below 0.05 % here. It is rendered once per case and shared by the studies; its time is its
whole render's, on cpu.
**Knobs swept:** screen: `samples` on gl and cpu, `decay` x `normalize` at 16 samples
(`model = thesis` is left out: its L_v has no units, it is not comparable with a physical
reference); polygonal: the shadow map's `resolution` (one mesh vertex per texel), the mesh's
`resolution` on a 1024^2 map; froxel: the grid W x H x D (one knob, `grid`) x `slicing` on each
backend, `accumulation` (the thesis's sum against the energy-conserving integration),
`z_near`, the shadow map's `resolution`, and temporal reprojection's `history` (0 = off)
after 16 frames. **Time:** the `vol` node's per frame in steady state (3 frames, the first,
with its shader compilation, left out; `per_frame = true`). **Metric:** relative RMSE of the
linear in-scatter `inscatter` (L_v alone) over the image and R, G, B.
**The classroom's blinds** (issue 24; docs/volumetric.md, "The thesis's interiors"): the
generated classroom (`tools/gen_scene.py classroom`: 24 slats of 3 mm per window, the sun
through them) with `examples/classroom.lgraph`'s settings, froxel on gl, the grid W x H x D
swept: the slats' striped shafts are finer than a coarse grid's froxels. Its reference is
`volumetric_reference` at 256 steps and 2 rays per pixel through pixel centres (the
slats' stripes are what is measured; 1024 x 4 would cost minutes here)."""
TARGET = None

# ---- what is swept ---------------------------------------------------------------------------

EXAMPLES = "examples"
SCENE = "volumetric_scene.lgraph"


class Case:
    """A light type or a medium kind: `tag` names it in the study ids; `need` is the scene
    feature the volumetric nodes declare for it (`lightgraph inspect --json`, "needs"; the
    test accuracy_volumetric checks that every one they declare has its entry here, and a
    node that needs `light` covers every light type: `light_type` says which type a LIGHTS
    entry is); `node` is the graph text that takes the place of the example scene's node of
    that role (`sun` for a light, `fog` for a medium; it keeps that name and chains as the
    scene does: `sun` from `cam`, `fog` from `sun`), None for the example's own; `methods`
    the methods that support it (None: all); `plans` the PLANS ids it runs at full size and
    `quick_plans` at --quick ("id" or "id:backend"; None: all; the light types and media
    beyond the first each add a reference, so they keep to a few studies); `requires`
    [(node type, parameter)] that the case's node text uses: a case whose node type lacks
    one is skipped, saying so (a parameter another branch adds); `ref` {"full": (steps, rays
    per pixel, size), "quick": ...} in place of REF for a case whose reference costs more
    (the studies of the case run at its size too); `section` the page's section that
    measures it (volumetric, volumetric_lights or volumetric_media: each case costs a
    reference, and a section of its own is made again without the others)."""

    def __init__(self, tag, label, need, node=None, methods=None, light_type=None, plans=None,
                 quick_plans=None, requires=(), ref=None, section="volumetric"):
        self.tag, self.label, self.need = tag, label, need
        self.node, self.methods = node, methods
        self.light_type, self.plans, self.quick_plans = light_type, plans, quick_plans
        self.requires = list(requires)
        self.ref, self.section = ref, section


# The light types every volumetric node that needs `light` models.
LIGHT_TYPES = {"directional", "point", "spot"}

# A bulb and a spot in the bunny box (issue 25): the bulb hangs above the bunny at the
# height of its ears, the spot shines down from under the ceiling across the view.
POINT_LIGHT = ("sun = light { scene = cam, type = point, position = [0, 0.9, 0], "
               "intensity = 20 }")
SPOT_LIGHT = ("sun = light { scene = cam, type = spot, position = [-0.3, 1.5, -0.5], "
              "direction = [0.3, -1, -0.2], inner_cone_deg = 10, outer_cone_deg = 25, "
              "intensity = 60 }")
# A heterogeneous fog (issue 25, item 3): the `medium` node's density-field parameters; a
# build without them skips these cases, saying so. Height fog needs a field (uniform: the
# medium node ignores height_falloff with field = none, the homogeneous medium, and warns).
FOG = "density = 1, scattering = [0.1, 0.1, 0.1], absorption = [0, 0, 0], g = 0.4"
FBM_FOG = ("fog = medium { scene = sun, %s, field = fbm, frequency = 2, octaves = 4 }" % FOG)
HEIGHT_FOG = ("fog = medium { scene = sun, %s, field = uniform, height_falloff = 2, "
              "height_base = 0 }" % FOG)
# The cases beyond the directional light in the homogeneous fog each cost a reference, and
# on this shared machine (load 20-25, every process a twelfth of a core) the directional
# case's 320 x 180 x 1024 steps x 4 rays did not finish for them (the fBm reference stalled
# the last run): they are measured at 160 x 90 with 256 steps x 4 rays (the reference's own
# error: 0.13 % at 256 steps in a homogeneous medium, its README; in fBm noise, ratio tracking,
# 0.82 %: two seeds differ by 1.15 % relative RMSE at 64 x 36, / sqrt 2), and with one
# backend's studies where the backends agree to 1e-3 (froxel cl and cpu, not gl: llvmpipe is
# the slowest; screen space on gl).
LIGHT_PLANS = ["screen_samples:gl", "polygonal_shadow", "froxel_grid:cl", "froxel_grid:cpu"]
FIELD_PLANS = ["froxel_grid:cpu"]  # cl gave cpu's errors to 5 digits in fBm (09:2x run)
SMALL_REF = {"full": (256, 4, "160x90"), "quick": (64, 1, "64x36")}
FBM_REF = SMALL_REF

LIGHTS = [Case("dir", "directional light", "directional_light", light_type="directional"),
          Case("point", "point light", "point_light", node=POINT_LIGHT, light_type="point",
               plans=LIGHT_PLANS + ["froxel_point"],
               quick_plans=["screen_samples:cpu", "froxel_grid:cpu", "froxel_point:cpu"],
               ref=SMALL_REF, section="volumetric_lights"),
          Case("spot", "spot light", "light", node=SPOT_LIGHT, light_type="spot",
               plans=LIGHT_PLANS, quick_plans=["screen_samples:cpu"], ref=SMALL_REF,
               section="volumetric_lights")]
MEDIA = [Case("hom", "homogeneous medium", "medium"),
         Case("fbm", "fBm noise medium", "medium", node=FBM_FOG, methods=["froxel"],
              plans=FIELD_PLANS, quick_plans=["froxel_grid:cpu"],
              requires=[("medium", "field"), ("medium", "frequency"), ("medium", "octaves")],
              ref=FBM_REF, section="volumetric_media"),
         Case("height", "height fog", "medium", node=HEIGHT_FOG, methods=["froxel"],
              plans=FIELD_PLANS, quick_plans=["froxel_grid:cpu"],
              requires=[("medium", "field"), ("medium", "height_falloff"),
                        ("medium", "height_base")], ref=SMALL_REF, section="volumetric_media")]


def light_covered(needs, case):
    """Whether a node with these needs runs on a scene whose only light is the case's: it
    needs `light` (any type), or exactly the case's own need."""
    return "light" in needs or case.need in needs


def cases(section=None):
    """The (light, medium) cases measured: every light type in the homogeneous medium, and
    every other medium with the directional light (not the product: each case costs a
    reference render, and the product would say little more); those of one section when
    `section` names it (the section of a case's non-default light or medium)."""
    out = ([(light, MEDIA[0]) for light in LIGHTS] +
           [(LIGHTS[0], medium) for medium in MEDIA[1:]])
    if section is None:
        return out
    return [(lt, md) for lt, md in out
            if (lt.section if lt.section != "volumetric" else md.section) == section]


class Plan:
    """One study of a method on a backend: `vary` [(NODE.PARAM, [values])] as sweep takes it,
    except a key of LINKED (one sweep per value); `quick_vary` the same at --quick; `quick`:
    whether --quick runs it (a quick run keeps one or two studies per method, since the page's
    quick test must stay under its budget)."""

    def __init__(self, id, method, backend, title, vary, quick_vary, sets=(), frames=3,
                 quick=False, light_types=None):
        self.id, self.method, self.backend, self.title = id, method, backend, title
        self.vary, self.quick_vary, self.sets = vary, quick_vary, list(sets)
        self.frames, self.quick = frames, quick
        self.light_types = light_types  # the light types it is about (None: any)


def grids(sizes, depths):
    return ["%sx%d" % (s, d) for s in sizes for d in depths]


# The knobs that are several parameters set together: the value -> its --set list.
LINKED = {
    "vol.grid": lambda v: ["vol.width=%s" % v.split("x")[0], "vol.height=%s" % v.split("x")[1],
                           "vol.depth=%s" % v.split("x")[2]],
    # froxel's point and spot lights: "sample" (point_nodes does nothing then) or
    # "analytic:N" (N Gauss-Legendre nodes per slice): one column, no rows that repeat
    "vol.point": lambda v: (["vol.point_integration=%s" % v.split(":")[0]] +
                            (["vol.point_nodes=%s" % v.split(":")[1]] if ":" in v else [])),
}
POINT_MODES = ["sample", "analytic:1", "analytic:2", "analytic:4", "analytic:8"]

SLICING = ("vol.slicing", ["uniform_clip", "exponential"])
QUICK_GRIDS = ["24x12x8", "48x22x16"]  # quick: small grids, or a quick run takes seconds

PLANS = [
    Plan("screen_samples", "screen", "gl", "samples",
         [("vol.samples", ["4", "16", "64", "256"])],
         [("vol.samples", ["8", "64"])], quick=True),
    Plan("screen_samples", "screen", "cpu", "samples",
         [("vol.samples", ["4", "16", "64", "256"])],
         [("vol.samples", ["8", "64"])], quick=True),
    # at 64 samples normalize changes nothing (its decay is per 1/64 of the path): 16 here
    Plan("screen_decay", "screen", "gl", "decay x normalize (16 samples)",
         [("vol.decay", ["0.9", "0.94", "1"]), ("vol.normalize", ["true", "false"])],
         [("vol.decay", ["0.9", "1"])], sets=["vol.samples=16"]),
    Plan("polygonal_shadow", "polygonal", "gl",
         "shadow map resolution (mesh: one vertex per texel)",
         [("shadow.resolution", ["128", "256", "512", "1024"])],
         [("shadow.resolution", ["64", "128"])], quick=True),
    Plan("polygonal_mesh", "polygonal", "gl", "mesh resolution on a 1024^2 shadow map",
         [("vol.resolution", ["32", "64", "128", "256", "512"])],
         [("vol.resolution", ["32", "64"])], sets=["shadow.resolution=1024"]),
    Plan("froxel_grid", "froxel", "gl", "grid W x H x D x slicing",
         [("vol.grid", grids(["48x22", "95x45"], [16, 32, 64, 128]) +
           grids(["190x90"], [64, 128])), SLICING],
         [("vol.grid", QUICK_GRIDS)], quick=True),
    Plan("froxel_grid", "froxel", "cl", "grid W x H x D x slicing",
         [("vol.grid", grids(["95x45"], [32, 64, 128])), SLICING],
         [("vol.grid", QUICK_GRIDS)], quick=True),
    Plan("froxel_grid", "froxel", "cpu", "grid W x H x D x slicing",
         [("vol.grid", grids(["95x45"], [32, 64, 128])), SLICING],
         [("vol.grid", QUICK_GRIDS)], quick=True),
    Plan("froxel_accumulation", "froxel", "gl", "accumulation x depth (190 x 90, uniform_clip)",
         [("vol.accumulation", ["thesis", "energy_conserving"]), ("vol.depth", ["16", "64"])],
         [("vol.accumulation", ["thesis", "energy_conserving"]), ("vol.depth", ["16"])]),
    Plan("froxel_znear", "froxel", "gl", "z_near x slicing (95 x 45 x 32)",
         [("vol.z_near", ["0.05", "0.2", "0.5"]), SLICING],
         [("vol.z_near", ["0.05", "0.5"])],
         sets=["vol.width=95", "vol.height=45", "vol.depth=32"]),
    Plan("froxel_shadow", "froxel", "gl", "shadow map resolution (95 x 45 x 64)",
         [("shadow.resolution", ["256", "512", "1024", "2048"])],
         [("shadow.resolution", ["64", "128"])],
         sets=["vol.width=95", "vol.height=45", "vol.depth=64"]),
    # issue 25: the point light's in-scattering per froxel, sampled at the froxel's point or
    # integrated over the slice's segment (Gauss-Legendre in the airlight angle), at a coarse
    # and the example's depth; cpu: the backends agree to 1e-3 (their tests) and it is the
    # fastest with point lights here
    Plan("froxel_point", "froxel", "cpu",
         "point_integration x point_nodes x depth (190 x 90, z_near 0.2)",
         [("vol.point", POINT_MODES), ("vol.depth", ["32", "128"])],
         [("vol.point", ["sample", "analytic:2"]), ("vol.depth", ["16"])], quick=True,
         light_types=["point"]),
    Plan("froxel_temporal", "froxel", "gl",
         "temporal reprojection: history (0 = off) x depth (95 x 45), after 16 frames",
         [("vol.history", ["0", "0.9"]), ("vol.depth", ["32", "64"])],
         [("vol.history", ["0", "0.9"])],
         sets=["vol.temporal=true", "vol.width=95", "vol.height=45"], frames=16),
]

# How the page names a value: "resolution=1024" alone would not say which resolution.
VALUE_LABELS = {
    "shadow.resolution": {str(2 ** k): "%d^2 shadow map" % 2 ** k for k in range(4, 14)},
    "vol.point": dict([("sample", "point_integration=sample")] +
                      [("analytic:%d" % n, "analytic, point_nodes=%d" % n)
                       for n in range(1, 9)]),
}

# The reference: steps, rays per pixel, at the full and the quick size.
REF = {"full": (1024, 4, "320x180"), "quick": (128, 1, "64x36")}
REPEAT = 3  # timed runs per point at full size (median and spread); 1 at --quick


def read(path):
    with open(path) as f:
        return f.read()


def example_node(root, example, name):
    """The `NAME = type { ... }` node of an example, as its file writes it (on one line or a
    braced block), so that the studies measure the example's own settings."""
    text = read(os.path.join(root, EXAMPLES, example))
    m = re.search(r"^%s = [a-z_]+ \{[^\n]*\}$|^%s = [a-z_]+ \{\n.*?^\}" % (name, name), text,
                  re.S | re.M)
    if not m:
        raise StudyError("examples/%s: no `%s = ... { ... }` node" % (example, name))
    return m.group(0)


def scene_text(root, light, medium):
    """The example scene with the case's light and medium in place of its `sun` and `fog`,
    its relative file paths made absolute (the text is written elsewhere)."""
    text = read(os.path.join(root, EXAMPLES, SCENE))
    for name, case in (("sun", light), ("fog", medium)):
        if case.node is not None:
            text = text.replace(example_node(root, SCENE, name), case.node)
    base = os.path.join(root, EXAMPLES)
    return re.sub(r'file = "([^"/][^"]*)"',
                  lambda m: 'file = "%s"' % os.path.normpath(os.path.join(base, m.group(1))),
                  text)


def method_graph(ctx, scene_path, method, out):
    return ('lightgraph 1\ninclude "%s"\n%s\noutput vol.inscatter "%s"\n'
            % (scene_path, example_node(ctx.root, "volumetric_%s.lgraph" % method, "vol"), out))


def inspect(ctx, node):
    """`lightgraph inspect NODE --json`, or None when the node type is not built."""
    r = subprocess.run([ctx.lightgraph, "inspect", node, "--json"], capture_output=True,
                       text=True)
    return json.loads(r.stdout) if r.returncode == 0 else None


def skip(what, why):
    sys.stderr.write("volumetric: skipping %s: %s\n" % (what, why))


def plan_wanted(case, plan, quick):
    wanted = case.quick_plans if quick else case.plans
    if wanted is None:
        return True
    return plan.id in wanted or "%s:%s" % (plan.id, plan.backend) in wanted


def studies(ctx):
    """This section's: the directional light in the homogeneous medium, and the classroom;
    the other light types and media are sections volumetric_lights and volumetric_media."""
    return case_studies(ctx, cases("volumetric")) + [classroom_study(ctx)]


def case_studies(ctx, which):
    """The studies of the (light, medium) cases `which`, each case's reference shared by
    its studies."""
    mode = "quick" if ctx.quick else "full"
    info = {}

    def node_info(name):
        if name not in info:
            info[name] = inspect(ctx, name)
        return info[name]

    out = []
    for light, medium in which:
        case = "%s_%s" % (light.tag, medium.tag)
        refs = medium.ref or light.ref or REF
        steps, spp, size = refs[mode]
        label = ("volumetric_reference, %d steps, %d spp through pixel centres, on cpu"
                 % (steps, spp))
        missing = []
        for node, param in light.requires + medium.requires:
            d = node_info(node)
            if d is None or param not in {p["key"] for p in d["parameters"]}:
                missing.append("%s.%s" % (node, param))
        if missing:
            skip("case %s (%s, %s)" % (case, light.label, medium.label),
                 "the node has no parameter %s here (it comes with another branch)"
                 % ", ".join(missing))
            continue
        ref_node = node_info("volumetric_reference")
        if ref_node is None or not light_covered(ref_node["needs"], light):
            skip("case %s (%s, %s)" % (case, light.label, medium.label),
                 "volumetric_reference does not model %ss here (its needs: %s)"
                 % (light.label, ", ".join(ref_node["needs"]) if ref_node else "not built"))
            continue
        scene = ctx.write("%s/scene.lgraph" % case, scene_text(ctx.root, light, medium))
        ref_dir = os.path.join(ctx.tmp, case, "reference")
        ref_graph = ctx.write("%s/reference.lgraph" % case, method_graph(
            ctx, scene, "reference", os.path.join(ref_dir, "reference.exr")))
        reference = {"dir": ref_dir, "graph": ref_graph, "size": size,
                     "sets": ["vol.steps=%d" % steps, "vol.spp=%d" % spp,
                              "vol.subpixel=centre"]}
        for p in PLANS:
            if ctx.quick and not p.quick:
                continue
            if any(c.methods is not None and p.method not in c.methods
                   for c in (light, medium)):
                continue
            if not (plan_wanted(light, p, ctx.quick) and plan_wanted(medium, p, ctx.quick)):
                continue
            if p.light_types is not None and light.light_type not in p.light_types:
                continue
            m = node_info("volumetric_%s" % p.method)
            if m is None or not light_covered(m["needs"], light):
                skip("%s %s on case %s" % (p.id, p.backend, case),
                     "volumetric_%s does not model %ss here (its needs: %s)"
                     % (p.method, light.label, ", ".join(m["needs"]) if m else "not built"))
                continue
            sid = "%s_%s_%s" % (p.id, p.backend, case)
            graph = ctx.write("%s/%s.lgraph" % (case, sid), method_graph(
                ctx, scene, p.method, os.path.join(ctx.tmp, case, sid + ".exr")))
            sets = ["vol.per_frame=true"] + p.sets
            if p.method != "polygonal":  # polygonal has one backend and no parameter
                sets.append("vol.backend=%s" % p.backend)
            spec = {"id": sid, "lightgraph": ctx.lightgraph, "graph": graph,
                    "time_node": "vol", "size": size, "sets": sets,
                    "vary": p.quick_vary if ctx.quick else p.vary,
                    "frames": 2 if ctx.quick else p.frames,
                    "repeat": 1 if ctx.quick else (ctx.repeat or REPEAT), "reference": reference}
            path = ctx.write("%s/%s.json" % (case, sid), json.dumps(spec, indent=1))
            out.append(Custom(
                id=sid, title="%s %s: %s (%s, %s)" % (p.method, p.backend, p.title,
                                                     light.label, medium.label),
                technique="volumetric_%s" % p.method, backend=p.backend,
                command=[sys.executable, os.path.abspath(__file__), "run", path, "{out}"],
                csv="rows.csv", reference_label=label, metric="rel_rmse",
                reference_image="reference.exr"))
            out[-1].value_labels = {k: VALUE_LABELS[k] for k, _ in spec["vary"]
                                    if k in VALUE_LABELS}
    return out


# ---- the examples' studies -----------------------------------------------------------------------

def example_spec(ctx, example, sub, scene_path, vol, sid, backend, vary, ref):
    """The run file of a study of an example's `vol` node (its text `vol`, on the scene file
    `scene_path`) on `backend` over `vary`, against volumetric_reference with the example's
    z_limit at ref = (steps, spp, size); written under ctx.tmp/sub, its path returned."""
    steps, spp, size = ref
    z_limit = re.search(r"z_limit = ([0-9.]+)", vol)
    if not z_limit:
        raise StudyError("examples/%s: its vol node has no z_limit" % example)
    d = os.path.join(ctx.tmp, sub)
    ref_dir = os.path.join(d, "reference")
    ref_graph = ctx.write("%s/reference.lgraph" % sub, (
        'lightgraph 1\ninclude "%s"\nvol = volumetric_reference { scene = fog, base = lit, '
        'z_limit = %s }\noutput vol.inscatter "%s"\n'
        % (scene_path, z_limit.group(1), os.path.join(ref_dir, "reference.exr"))))
    graph = ctx.write("%s/%s.lgraph" % (sub, sid), 'lightgraph 1\ninclude "%s"\n%s\n'
                      'output vol.inscatter "%s"\n'
                      % (scene_path, vol, os.path.join(d, sid + ".exr")))
    spec = {"id": sid, "lightgraph": ctx.lightgraph, "graph": graph, "time_node": "vol",
            "size": size, "sets": ["vol.per_frame=true", "vol.backend=" + backend],
            "vary": vary,
            "frames": 2 if ctx.quick else 3,
            "repeat": 1 if ctx.quick else (ctx.repeat or REPEAT),
            "reference": {"dir": ref_dir, "graph": ref_graph, "size": size,
                          "sets": ["vol.steps=%d" % steps, "vol.spp=%d" % spp,
                                   "vol.subpixel=centre"]}}
    return ctx.write("%s/%s.json" % (sub, sid), json.dumps(spec, indent=1))


# ---- the classroom's blinds (issue 24) -----------------------------------------------------------

CLASSROOM = "classroom.lgraph"
CLASSROOM_GRIDS = ["40x23x32", "80x45x64", "160x90x64", "160x90x128"]
CLASSROOM_REF = {"full": (256, 2, "320x180"), "quick": (64, 1, "64x36")}


def classroom_study(ctx):
    """froxel's grid against the reference on the generated classroom: the scene is written
    into ctx.tmp by tools/gen_scene.py (65 KB, a second) and examples/classroom.lgraph's
    nodes are used, its file path pointed there."""
    mode = "quick" if ctx.quick else "full"
    steps, spp, size = CLASSROOM_REF[mode]
    d = os.path.join(ctx.tmp, "classroom")
    os.makedirs(d, exist_ok=True)
    glb = os.path.join(d, "classroom.glb")
    r = subprocess.run([sys.executable, os.path.join(ctx.root, "tools", "gen_scene.py"),
                        "classroom", "-q", "-o", glb], capture_output=True, text=True)
    if r.returncode != 0:
        raise StudyError("tools/gen_scene.py classroom failed: %s" % r.stderr.strip())
    text = read(os.path.join(ctx.root, EXAMPLES, CLASSROOM))
    vol = example_node(ctx.root, CLASSROOM, "vol")
    scene = text[:text.index(vol)]
    scene, n = re.subn(r'file = "[^"]*"', 'file = "%s"' % glb, scene)
    if n != 1:
        raise StudyError("examples/%s: not one `file = ...` in its scene" % CLASSROOM)
    scene_path = ctx.write("classroom/scene.lgraph", scene)
    sid = "classroom_blinds_gl"
    path = example_spec(ctx, CLASSROOM, "classroom", scene_path, vol, sid, "gl",
                        [("vol.grid", QUICK_GRIDS if ctx.quick else CLASSROOM_GRIDS)],
                        (steps, spp, size))
    return Custom(id=sid, title="froxel gl: grid W x H x D on the classroom's blinds (24 slats "
                  "of 3 mm per window, directional sun, homogeneous medium)",
                  technique="volumetric_froxel", backend="gl",
                  command=[sys.executable, os.path.abspath(__file__), "run", path, "{out}"],
                  csv="rows.csv", reference_label="volumetric_reference, %d steps, %d spp "
                  "through pixel centres, on cpu" % (steps, spp), metric="rel_rmse",
                  reference_image="reference.exr")


# ---- a VDB cloud (issue 25) ------------------------------------------------------------------

CLOUD_SCENE = "volumetric_cloud_scene.lgraph"
CLOUD = "volumetric_cloud.lgraph"
CLOUD_VDB = os.path.join("plugins", "scene_tools", "cloud.vdb")  # in the build directory
CLOUD_REF = SMALL_REF


def cloud_study(ctx):
    """froxel's depth x tau_res against the reference on examples/volumetric_cloud.lgraph:
    the 64^3 VDB cloud the build writes (tools/make_vdb_cloud.cpp), lit by the sun; its
    scene's file paths pointed at the repository's mesh and the build's cloud."""
    mode = "quick" if ctx.quick else "full"
    steps, spp, size = CLOUD_REF[mode]
    vdb = os.path.join(ctx.build, CLOUD_VDB)
    if not os.path.exists(vdb):
        raise StudyError("%s does not exist: the cloud is written by a build with OpenVDB "
                         "(libopenvdb-dev, tools/deps.sh)" % vdb)
    text = read(os.path.join(ctx.root, EXAMPLES, CLOUD_SCENE))
    base = os.path.join(ctx.root, EXAMPLES)
    text, n = re.subn(r'file = "([^"/][^"]*)"', lambda m: 'file = "%s"' % os.path.normpath(
        os.path.join(base, m.group(1))), text)
    text, k = re.subn(r'vdb = "[^"]*"', lambda m: 'vdb = "%s"' % vdb, text)
    if n != 1 or k != 1:
        raise StudyError("examples/%s: want one `file = ...` and one `vdb = ...` (have %d and "
                         "%d)" % (CLOUD_SCENE, n, k))
    scene_path = ctx.write("cloud/scene.lgraph", text)
    vol = example_node(ctx.root, CLOUD, "vol")
    sid = "froxel_cloud_cpu"
    path = example_spec(ctx, CLOUD, "cloud", scene_path, vol, sid, "cpu",
                        ([("vol.depth", ["16"]), ("vol.tau_res", ["8", "32"])] if ctx.quick else
                         [("vol.depth", ["32", "128"]), ("vol.tau_res", ["16", "64"])]),
                        (steps, spp, size))
    return Custom(id=sid, title="froxel cpu: depth x tau_res on a VDB cloud (64^3 grid, "
                  "directional sun, examples/volumetric_cloud.lgraph: 190 x 90, exponential)",
                  technique="volumetric_froxel", backend="cpu",
                  command=[sys.executable, os.path.abspath(__file__), "run", path, "{out}"],
                  csv="rows.csv", reference_label="volumetric_reference, %d steps, %d spp "
                  "through pixel centres, ratio tracking, on cpu" % (steps, spp),
                  metric="rel_rmse", reference_image="reference.exr")


# ---- the runner (one study) ------------------------------------------------------------------

def die(msg):
    sys.stderr.write("volumetric: %s\n" % msg)
    sys.exit(1)


def run(cmd, what):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        die("%s: `%s` failed (exit %d):\n%s" % (what, " ".join(cmd), r.returncode,
                                               (r.stderr or r.stdout).strip()))
    return r


def reference(spec):
    """The case's reference, rendered by the first study that needs it (under a lock, should
    studies ever run at once) and timed: returns (its image, the image graph the sweeps
    read it through, the time of its whole render in ms)."""
    ref = spec["reference"]
    d = ref["dir"]
    os.makedirs(d, exist_ok=True)
    exr, meta = os.path.join(d, "reference.exr"), os.path.join(d, "reference.json")
    img_graph = os.path.join(d, "image.lgraph")
    with open(os.path.join(d, "lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not os.path.exists(meta):
            prof = os.path.join(d, "profile.json")
            cmd = [spec["lightgraph"], "render", ref["graph"], "--size", ref["size"],
                   "--profile-json", prof]
            for s in ref["sets"]:
                cmd += ["--set", s]
            sys.stderr.write("volumetric: the reference: %s\n" % " ".join(cmd))
            run(cmd, "the reference of %s" % spec["id"])
            pj = json.loads(read(prof))
            if not any(n["name"] == "vol" for n in pj["nodes"]):
                die("the reference's profile %s has no node `vol`" % prof)
            with open(img_graph, "w") as f:
                # the sweep writes the reference it reads into its own folder; this output
                # names where a plain render of the graph would
                f.write('lightgraph 1\nref = image { file = "%s" }\noutput ref "%s"\n'
                        % (exr, os.path.join(d, "copy.exr")))
            with open(meta + ".tmp", "w") as f:
                # its whole render, as sweep's ref_ms is (the page says so): the vol node
                # is nearly all of it
                json.dump({"ref_ms": pj["planning_ms"] + pj["execution_ms"]}, f)
            os.replace(meta + ".tmp", meta)  # written last: its presence means all is there
        ref_ms = json.loads(read(meta))["ref_ms"]
    return exr, img_graph, ref_ms


def ref_rms(path):
    """sqrt(mean b^2) over R, G, B of the reference, for sweeps that write no rel_rmse."""
    from accuracy.exr import read_exr
    _, _, ch = read_exr(path)
    vals = [v for c in ("R", "G", "B") for v in ch[c] if math.isfinite(v)]
    return math.sqrt(sum(v * v for v in vals) / len(vals)) if vals else 0.0


def run_study(spec_path, out):
    spec = json.loads(read(spec_path))
    exr, img_graph, ref_ms = reference(spec)
    os.makedirs(out, exist_ok=True)
    shutil.copyfile(exr, os.path.join(out, "reference.exr"))
    keys = [k for k, _ in spec["vary"]]
    linked = [k for k in keys if k in LINKED]
    if len(linked) > 1:
        die("study %s: more than one linked knob (%s)" % (spec["id"], ", ".join(linked)))
    swept = [(k, vs) for k, vs in spec["vary"] if k not in LINKED]
    parts = ([(v, LINKED[linked[0]](v)) for v in dict(spec["vary"])[linked[0]]] if linked
             else [(None, [])])
    rows, rms = [], None
    for i, (value, link_sets) in enumerate(parts):
        d = os.path.join(out, "part%d" % i)
        os.makedirs(d, exist_ok=True)
        cmd = [spec["lightgraph"], "sweep", spec["graph"], "--reference", img_graph,
               "--time", spec["time_node"], "--repeat", str(spec["repeat"]), "--frames",
               str(spec["frames"]), "--size", spec["size"], "-o", d]
        for s in spec["sets"] + link_sets:
            cmd += ["--set", s]
        if not swept:  # sweep wants a --vary: the linked knob's first parameter, as set
            k, v = link_sets[0].split("=", 1)
            swept_now = [(k, [v])]
        else:
            swept_now = swept
        for k, vs in swept_now:
            cmd += ["--vary", "%s=%s" % (k, ",".join(vs))]
        sys.stderr.write("volumetric: %s\n" % " ".join(cmd))
        run(cmd, "study %s" % spec["id"])
        with open(os.path.join(d, "sweep.csv"), newline="") as f:
            for rec in csv.DictReader(f):
                row = {k: (value if k in LINKED else rec[k]) for k in keys}
                for c in ROW_COLUMNS:
                    row[c] = rec.get(c, "")
                if not row["rel_rmse"] and row["rmse"]:  # a sweep before branch metric
                    if rms is None:
                        rms = ref_rms(exr)
                    e = float(row["rmse"])
                    row["rel_rmse"] = repr(e / rms if rms > 0 else (0.0 if e == 0 else math.inf))
                row["ref_ms"] = "%.3f" % ref_ms
                run_no = int(rec["run"])
                row["image"] = "part%d/run-%03d.exr" % (i, run_no)
                row["heat"] = "part%d/heat-%03d.png" % (i, run_no)
                rows.append(row)
    with open(os.path.join(out, "rows.csv.tmp"), "w", newline="") as f:
        w = csv.DictWriter(f, keys + ROW_COLUMNS + ["image", "heat"])
        w.writeheader()
        w.writerows(rows)
    os.replace(os.path.join(out, "rows.csv.tmp"), os.path.join(out, "rows.csv"))


def main(argv):
    if len(argv) != 3 or argv[0] != "run":
        sys.stderr.write("usage: volumetric.py run SPEC.json OUT_DIR (the accuracy generator "
                         "runs it; tools/accuracy/accuracy.py --only volumetric)\n")
        return 2
    run_study(argv[1], argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
