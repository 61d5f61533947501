"""Shadow maps: the shadowmap node's resolution, fit, culling and normal offset, seen through
the phong node's shadow test, against a map converged in resolution."""
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
image's linear radiance; the shadow edges are where it lives (see the heat map)."""


def studies(ctx):
    graph = ctx.write("shadow.lgraph",
                      'lightgraph 1\n'
                      'include "%s"\n'
                      'lit = phong { scene = bulb, shadows = shadow, ambient = [0.3, 0.3, 0.3], '
                      'ks_scale = 20, background = [0.02, 0.02, 0.03] }\n'
                      'output lit "%s"\n'
                      % (os.path.join(ctx.root, "examples/phong_scene.lgraph"),
                         os.path.join(ctx.tmp, "lit.exr")))
    ref_res = "2048" if ctx.quick else "8192"
    ref = ["shadow.resolution=%s" % ref_res, "shadow.fit=frustum"]
    label = ("shadowmap %s x %s, fit = frustum, the default biases: no plugin ray-traces "
             "surface shadows" % (ref_res, ref_res))
    common = dict(technique="shadowmap", backend="gl", graph=graph, time_node="shadow",
                  size="320x180", quick_size="96x54", frames=1, repeat=3, ref_sets=ref,
                  reference_label=label, metric="rel_rmse")
    return [
        Study(id="shadow_resolution", title="resolution x fit",
              vary=[("shadow.resolution", ["128", "256", "512", "1024", "2048", "4096"]),
                    ("shadow.fit", ["bounds", "frustum"])],
              quick_vary=[("shadow.resolution", ["128", "512"]), ("shadow.fit", ["frustum"])],
              **common),
        Study(id="shadow_normal_offset", title="normal offset at 1024 (fit = bounds)",
              sets=["shadow.resolution=1024"],
              vary=[("shadow.normal_offset", ["0", "0.5", "1", "2", "4"])],
              **common),
        Study(id="shadow_bias", title="constant depth bias at 1024 (fit = bounds)",
              sets=["shadow.resolution=1024"],
              vary=[("shadow.bias_constant", ["0", "0.0002", "0.001", "0.005"])],
              **common),
    ]
