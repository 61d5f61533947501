"""Shadow maps: the shadowmap node's resolution, fit, culling and normal offset, seen through
the phong node's shadow test, against a map converged in resolution; since issue 25 also a
point light's cube and a spot light's map, with PCF."""
import os

from accuracy.study import Study

TITLE = "Shadow maps: resolution, fit, bias"
ORDER = 30
INTRO = """\
The `shadowmap` node renders one orthographic depth map per directional light, which the
`phong` node tests once per pixel, one texel per test, no filtering (the plugins have no
filtered lookup, PCF or other, so there is no filtering knob to sweep);
[plugins/shadowmap/README.md](../plugins/shadowmap/README.md). Scene: the bunny box under a
sun and a bulb (`examples/phong_scene.lgraph`, the sun's shadow mapped), shaded per pixel.
**Reference:** no plugin ray-traces surface shadows, so the reference is the same graph with
the node's largest useful map, 8192 x 8192 texels (a texel of about 0.4 mm across the
2-metre box, against the 320 x 180 render's pixel of about 1 cm), `fit = frustum`, the
default biases: converged in resolution, so what remains is the bias's own offset, which every
row shares. Knobs swept: `resolution` (128 .. 4096) x `fit` (`bounds`: the whole scene;
`frustum`: the part the camera sees, which here is the whole open box, so the two fits make
the same maps: a larger scene would separate them); the normal offset (texels of the light's
`texel_world`) and the constant depth bias at 1024 (`cull` is not swept: the bunny box's
materials are double-sided, so no face is culled). Time: the `shadowmap` node's (its one
run: it renders on the first frame only, so its time includes llvmpipe's compilation of its
two shaders, a constant of a few ms), median of the repeats. Metric: relative RMSE of the lit
image's linear radiance; the shadow edges are where it lives (see the heat map).

Since issue 25 the node maps point lights (a cube of six perspective maps) and spot lights
(one perspective map fitted to the cone) and publishes a PCF radius
([plugins/shadowmap/README.md](../plugins/shadowmap/README.md), "Spot and point lights",
"Filtering"). The first three studies keep the sun alone mapped (their own shadow node on
`sun`), as before. Two more sweep `pcf_radius` (0 .. 3) x `resolution` (256 .. 2048) for a
bulb alone (point light at the example's bulb, 1.5 cd: its cube) and for a spot alone (the
same place, aimed at the bunny, cone 50 degrees), each against its own graph with a 4096 map
and no filtering (a converged hard shadow: PCF blurs the edge, so at high resolution its
error is the blur's own). Their time is the shadow node's (resolution); PCF's cost is in
phong, (2 r + 1)^2 fetches per shadowed pixel. **Not yet against Embree visibility**: no plugin ray-traces
surface shadows; a ray-traced reference (embree_common, as prt_bake and
volumetric_reference use it) is the open item of this section."""


LOCAL = """lightgraph 1
scene = gltf {{ file = "{root}/assets/meshes/bunny_cornell_box.glb" }}
lamp = light {{ scene = scene, {light}, position = [0, 1.85, -1.6], intensity = 1.5 }}
shadow = shadowmap {{ scene = lamp, resolution = 1024 }}
lit = phong {{ scene = lamp, shadows = shadow, ambient = [0.1, 0.1, 0.1], falloff = none,
              background = [0.02, 0.02, 0.03] }}
output lit "{out}"
"""


def studies(ctx):
    # the sun's map alone, as before issue 25 (the example's `shadow` maps the bulb too now)
    graph = ctx.write("shadow.lgraph",
                      'lightgraph 1\n'
                      'include "%s"\n'
                      'sunshadow = shadowmap { scene = sun, resolution = 1024 }\n'
                      'lit = phong { scene = bulb, shadows = sunshadow, ambient = [0.3, 0.3, 0.3], '
                      'ks_scale = 20, background = [0.02, 0.02, 0.03] }\n'
                      'output lit "%s"\n'
                      % (os.path.join(ctx.root, "examples/phong_scene.lgraph"),
                         os.path.join(ctx.tmp, "lit.exr")))
    ref_res = "2048" if ctx.quick else "8192"
    ref = ["sunshadow.resolution=%s" % ref_res, "sunshadow.fit=frustum"]
    label = ("shadowmap %s x %s, fit = frustum, the default biases: no plugin ray-traces "
             "surface shadows" % (ref_res, ref_res))
    common = dict(technique="shadowmap", backend="gl", graph=graph, time_node="sunshadow",
                  size="320x180", quick_size="96x54", frames=1, repeat=3, ref_sets=ref,
                  reference_label=label, metric="rel_rmse")
    return [
        Study(id="shadow_resolution", title="resolution x fit",
              vary=[("sunshadow.resolution", ["128", "256", "512", "1024", "2048", "4096"]),
                    ("sunshadow.fit", ["bounds", "frustum"])],
              quick_vary=[("sunshadow.resolution", ["128", "512"]), ("sunshadow.fit", ["frustum"])],
              **common),
        Study(id="shadow_normal_offset", title="normal offset at 1024 (fit = bounds)",
              sets=["sunshadow.resolution=1024"],
              vary=[("sunshadow.normal_offset", ["0", "0.5", "1", "2", "4"])],
              **common),
        Study(id="shadow_bias", title="constant depth bias at 1024 (fit = bounds)",
              sets=["sunshadow.resolution=1024"],
              vary=[("sunshadow.bias_constant", ["0", "0.0002", "0.001", "0.005"])],
              **common),
    ] + [local_study(ctx, kind, light) for kind, light in (
        ("point", "type = point"),
        ("spot", "type = spot, direction = [0.15, -1, 0.5], inner_cone_deg = 40, "
                 "outer_cone_deg = 50"))]


def local_study(ctx, kind, light):
    """pcf_radius x resolution for one point or spot light alone, against a 4096 map."""
    graph = ctx.write("shadow_%s.lgraph" % kind,
                      LOCAL.format(root=ctx.root, light=light,
                                   out=os.path.join(ctx.tmp, "lit_%s.exr" % kind)))
    ref_res = "1024" if ctx.quick else "4096"
    return Study(id="shadow_%s_pcf" % kind,
                 title="%s light: pcf_radius x resolution" % kind,
                 technique="shadowmap", backend="gl", graph=graph, time_node="shadow",
                 vary=[("shadow.pcf_radius", ["0", "1", "2", "3"]),
                       ("shadow.resolution", ["256", "512", "1024", "2048"])],
                 quick_vary=[("shadow.pcf_radius", ["0", "2"]), ("shadow.resolution", ["256"])],
                 size="320x180", quick_size="96x54", frames=1, repeat=3,
                 ref_sets=["shadow.resolution=%s" % ref_res, "shadow.pcf_radius=0"],
                 reference_label="the same %s light's map at %s x %s, no filtering: no plugin "
                                 "ray-traces surface shadows" % (kind, ref_res, ref_res),
                 metric="rel_rmse")
