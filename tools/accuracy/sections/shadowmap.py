"""Shadow maps: the shadowmap node's resolution, fit, bias and filtering (PCF, PCSS) for every
light type, seen through the phong node's shadow test, against exact visibility (Embree shadow
rays, the shadow_reference node)."""
import os

from accuracy.study import Study

TITLE = "Shadow maps: resolution, fit, bias, PCF and PCSS against exact visibility"
ORDER = 30
INTRO = """\
The `shadowmap` node renders one depth map per directional light (orthographic), per spot
light (perspective) and six per point light (a cube), which the `phong` node tests per pixel
with percentage-closer filtering (`pcf_radius` r: (2 r + 1)^2 taps) or percentage-closer
soft shadows (`pcss_light_size`); [plugins/shadowmap/README.md](../plugins/shadowmap/README.md).
Scene: the bunny box lit by one light at a time, phong per pixel at 320 x 180: the sun of
`examples/phong_scene.lgraph` (directional, through the open side), a spot under the ceiling
at the example's bulb aimed at the bunny (cones 40 and 50 degrees), and a point light there
(the example's bulb, 1.5 cd: its cube).
**Reference: exact visibility.** `shadow_reference`
([plugins/shadow_reference/README.md](../plugins/shadow_reference/README.md)) takes phong's
image of the same scene without a shadow map and without the light, and adds the light's
unshadowed term (their difference: phong's own shading, bit for bit) times its visibility V
from Embree shadow rays at the surface point of the pixel centre: one ray for a hard light,
and for PCSS the visible fraction of an area light of the same diameter (`light_size` =
`pcss_light_size`; a disk facing the point, or a cone of that angular diameter for the sun)
over a fixed pattern of 256 rays. Its error is therefore the shadow test's alone: no
shading, sampling or antialiasing term (it is 0 where the test is right).
Knobs swept: `pcf_radius` 0 .. 4 x `resolution` 256 .. 2048 per light type; PCSS per light
type at two light sizes x resolution (each size against its own area-light reference; PCSS
sets its own kernel, so `pcf_radius` is not swept there); for the sun alone, as before issue
25, `fit`, the normal offset and the constant bias. **Time**: the whole graph per render
(one frame: loading the glTF, a few ms, the same in every row; the `shadowmap` node, which
draws once; phong, its shader compilation included), median of the repeats, so that a
larger map and a wider kernel both show. Metric: relative RMSE of the lit image's linear
radiance; shadow edges are where it lives (see the heat maps).
The point light's cube seams (the pixels whose PCF taps cross from one face to the next)
are measured apart, by `tools/accuracy/sections/_shadow_seams.py`, not on this page (a
region's error is not an image's, and would distort the front): the table is in
[plugins/shadowmap/README.md](../plugins/shadowmap/README.md), "Accuracy against exact
visibility"."""

# The phong settings every graph here shares: the studies' and the references' phong nodes
# must shade alike, or the reference's lit - unlit would not be the study's light.
PHONG = "ambient = [0.1, 0.1, 0.1], falloff = none, background = [0.02, 0.02, 0.03]"

LIGHTS = {
    "directional": "type = directional, direction = [0.6, -0.5, 1], intensity = 2",
    "spot": "type = spot, position = [0, 1.85, -1.6], intensity = 1.5, "
            "direction = [0.15, -1, 0.5], inner_cone_deg = 40, outer_cone_deg = 50",
    "point": "type = point, position = [0, 1.85, -1.6], intensity = 1.5",
}

# PCSS light sizes per light type: the sun's angular diameter (radians: the real sun's 0.0093
# and a hazy 0.05), a bulb's diameter (m)
PCSS = {
    "directional": ["0.0093", "0.05"],
    "spot": ["0.05", "0.2"],
    "point": ["0.05", "0.2"],
}

GRAPH = """lightgraph 1
scene = gltf {{ file = "{root}/assets/meshes/bunny_cornell_box.glb" }}
lamp = light {{ scene = scene, {light} }}
shadow = shadowmap {{ scene = lamp, resolution = 1024 }}
lit = phong {{ scene = lamp, shadows = shadow, {phong} }}
output lit "{out}"
"""

REFERENCE = """lightgraph 1
scene = gltf {{ file = "{root}/assets/meshes/bunny_cornell_box.glb" }}
lamp = light {{ scene = scene, {light} }}
lit = phong {{ scene = lamp, {phong} }}
unlit = phong {{ scene = scene, {phong} }}
ref = shadow_reference {{ scene = lamp, lit = lit, unlit = unlit }}
output ref "{out}"
"""


def _graphs(ctx, kind):
    graph = ctx.write("shadow_%s.lgraph" % kind, GRAPH.format(
        root=ctx.root, light=LIGHTS[kind], phong=PHONG,
        out=os.path.join(ctx.tmp, "lit_%s.exr" % kind)))
    ref = ctx.write("shadow_%s_ref.lgraph" % kind, REFERENCE.format(
        root=ctx.root, light=LIGHTS[kind], phong=PHONG,
        out=os.path.join(ctx.tmp, "ref_%s.exr" % kind)))
    return graph, ref


def studies(ctx):
    out = []
    common = dict(technique="shadowmap", backend="gl", time_node=None, size="320x180",
                  quick_size="96x54", frames=1, repeat=3, metric="rel_rmse")
    for kind in ("directional", "spot", "point"):
        graph, ref = _graphs(ctx, kind)
        hard = "Embree shadow rays (shadow_reference, one ray per pixel: exact hard shadows)"
        out.append(Study(id="shadow_%s_pcf" % kind,
                         title="%s light: pcf_radius x resolution" % kind,
                         graph=graph, reference=ref, reference_label=hard,
                         vary=[("shadow.pcf_radius", ["0", "1", "2", "3", "4"]),
                               ("shadow.resolution", ["256", "512", "1024", "2048"])],
                         quick_vary=[("shadow.pcf_radius", ["0", "2"]),
                                     ("shadow.resolution", ["256"])],
                         **common))
        # --quick (the test's run, every section within 90 s): one light size per type
        for k, size in enumerate(PCSS[kind][:1] if ctx.quick else PCSS[kind]):
            unit = "rad" if kind == "directional" else "m"
            out.append(Study(id="shadow_%s_pcss%d" % (kind, k + 1),
                             title="%s light: PCSS, light size %s %s x resolution"
                                   % (kind, size, unit),
                             graph=graph, reference=ref,
                             sets=["shadow.pcss_light_size=%s" % size],
                             ref_sets=["ref.light_size=%s" % size],
                             reference_label="Embree shadow rays to an area light of %s %s "
                                             "(256 rays per pixel, a fixed pattern)"
                                             % (size, unit),
                             vary=[("shadow.resolution", ["512", "1024", "2048"])],
                             quick_vary=[("shadow.resolution", ["256"])],
                             **common))
    # the sun's map, fit and biases (before issue 25 against an 8192 map, now exact)
    graph, ref = _graphs(ctx, "directional")
    sun = dict(common, graph=graph, reference=ref,
               reference_label="Embree shadow rays (shadow_reference: exact hard shadows)")
    out += [
        Study(id="shadow_resolution", title="sun: resolution x fit",
              vary=[("shadow.resolution", ["128", "256", "512", "1024", "2048", "4096"]),
                    ("shadow.fit", ["bounds", "frustum"])],
              quick_vary=[("shadow.resolution", ["128", "512"]), ("shadow.fit", ["frustum"])],
              **sun),
        Study(id="shadow_normal_offset", title="sun: normal offset at 1024 (fit = bounds)",
              vary=[("shadow.normal_offset", ["0", "0.5", "1", "2", "4"])], **sun),
        Study(id="shadow_bias", title="sun: constant depth bias at 1024 (fit = bounds)",
              vary=[("shadow.bias_constant", ["0", "0.0002", "0.001", "0.005"])], **sun),
    ]
    return out
