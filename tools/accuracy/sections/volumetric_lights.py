"""Volumetric lighting with point and spot lights (issue 25): every volumetric method against
volumetric_reference on the bunny box with a bulb and with a spot, and froxel's integration
of a point light along a slice. The cases, plans and runner are sections/volumetric.py's
(LIGHTS, PLANS, `volumetric.py run`); this file picks the cases of this section, so that
they are made again (`--only volumetric_lights`) without the directional studies."""
from accuracy.sections import volumetric as V

TITLE = "Volumetric lighting: point and spot lights"
ORDER = 62
INTRO = """\
Issue 25's local lights in the homogeneous fog of [the volumetric section](#volumetric) (the
examples' bunny box, density 1, sigma_s 0.1, g 0.4), each method with its example's settings:
a **point light**, a bulb of 20 cd at [0, 0.9, 0] by the bunny's ears (its shadows from a cube
of six perspective maps), and a **spot light** of 60 cd under the ceiling at [-0.3, 1.5, -0.5]
shining down across the view, cones 10 and 25 degrees (one perspective map fitted to its
cone). glTF's inverse-square falloff and smooth cone
([docs/volumetric.md](volumetric.md), "Every light in every medium").
**Reference:** `volumetric_reference` with the same light, Embree visibility towards the light,
256 steps and 4 rays per pixel through pixel centres, rendered once per light and shared by
the studies (its own error 0.13 % at 256 steps, its README). **At 160 x 90**, not the
volumetric section's 320 x 180 x 1024 steps: on this shared machine (load 20-25) those
references did not finish in the time a run had.
**Knobs swept:** screen space `samples` (gl; cpu gives the same error), polygonal the shadow
map's `resolution` (a point light's cube: six meshes), froxel the grid W x H x D x `slicing`
on cl and cpu (gl agrees with them to 1e-3, its tests, and is the slowest here under
llvmpipe) for both lights; for the bulb, froxel's
`point_integration` x `point_nodes` x `depth` on cpu (one column: `sample`, the light's
falloff and phase at the froxel's point, or `analytic, point_nodes=N`, the airlight integral
over the slice's segment by N Gauss-Legendre nodes in the airlight angle; the three backends
agree to 1e-3, their tests). **Time:** the `vol` node's per frame in steady state (3 frames,
the first left out). **Metric:** relative RMSE of the linear in-scatter over the image."""
TARGET = None


def studies(ctx):
    return V.case_studies(ctx, V.cases("volumetric_lights"))
