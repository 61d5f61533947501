"""volumetric_reference's multiple-scattering knobs (order, paths) against the reference at a
high order: how much radiance single scattering (what every real-time method computes)
misses, and what each further order and path costs."""
from accuracy.study import Study

TITLE = "Volumetric lighting: multiple scattering in the reference"
ORDER = 61
INTRO = """\
`volumetric_reference` with `order` > 1 adds scattering orders 2 .. n by path tracing
(phase-function sampling, free flight, next-event estimation to every light; surfaces
absorb), `paths` paths per ray
([plugins/volumetric_reference/README.md](../plugins/volumetric_reference/README.md),
"Multiple scattering"). The scene: the bunny box (`examples/volumetric_scene.lgraph`) with
its sun replaced by a point light of 10 cd at [0, 1.2, -0.6], the fog made denser (density 3,
sigma_t 0.3, albedo 0.9, g 0.4), where orders 2+ matter (at density 5 they add 61 % for
this bulb: the README's table). Secondary rays end at the scene's box (the open side).
**Reference:** the same node at `order` 8 and 256 paths per ray (the orders beyond 8 add
less than 0.1 % here: each order multiplies by about albedo x the chance not to escape),
with the same steps (32) and rays per pixel (1, through pixel centres), so that the single
scattering part is identical and the error is the missing orders plus the paths' noise.
Knobs swept: `order` x `paths`. Time: the node's (the Embree build included). Metric:
relative RMSE of `inscatter`. Row `order = 1` is the error of the single-scattering
assumption itself: no real-time method in this repository can do better than it. The
paths' noise is heavy-tailed (a path segment passing a distance H from the bulb carries
1/H: sparse bright pixels, variance only logarithmically bounded), so at these budgets it
outweighs the missing orders in RMSE; the sums over the image converge much faster
(plugins/volumetric_reference/README.md's table). (The
`transmittance` knob, ratio or delta tracking, needs a medium with a density field: its
study comes with the medium node's field parameters.)"""

GRAPH = """lightgraph 1
include "{root}/examples/volumetric_scene.lgraph"
vol = volumetric_reference {{ scene = fog, base = lit, z_limit = 8, steps = 32, spp = 1,
    subpixel = centre, seed = 1 }}
output vol.inscatter "vol.exr" float
"""

SETS = ["sun.type=point", "sun.position=[0,1.2,-0.6]", "fog.density=3",
        "fog.scattering=[0.09,0.09,0.09]", "fog.absorption=[0.01,0.01,0.01]"]


def studies(ctx):
    graph = ctx.write("scattering.lgraph", GRAPH.format(root=ctx.root))
    return [Study(id="reference_orders",
                  title="volumetric_reference: scattering order x paths per ray",
                  technique="volumetric_reference", backend="cpu", graph=graph,
                  time_node="vol",
                  vary=[("vol.order", ["1", "2", "3", "4"]), ("vol.paths", ["4", "16", "64"])],
                  quick_vary=[("vol.order", ["1", "2"]), ("vol.paths", ["4"])],
                  sets=SETS, ref_sets=["vol.order=8", "vol.paths=256"],
                  reference_label="volumetric_reference, order 8, 256 paths per ray",
                  size="160x90", quick_size="32x18", frames=1, repeat=3,
                  metric="rel_rmse")]
