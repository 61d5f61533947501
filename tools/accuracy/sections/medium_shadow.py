"""The medium's shadow on surfaces (issue 25): phong's per-light optical-depth volumes, their
resolution against the same at the node's maximum."""
import os

from accuracy.study import Study

TITLE = "The medium's shadow on surfaces (phong)"
ORDER = 12
INTRO = """\
A medium with a density field shadows surfaces: the `phong` node multiplies each light by the
transmittance towards it through the field, read from one optical-depth volume per light
(`medium_shadows`, `medium_shadow_res` nodes along the volume's longest side;
[plugins/phong/README.md](../plugins/phong/README.md), "Shadows of the medium", which gives
its error against exact marches of a box of fog, height fog and fBm noise: at 64 nodes at
most 0.03 in T, 1e-5 to 2e-3 on average). The scene: the VDB cloud of
`examples/volumetric_cloud_scene.lgraph`, whose shadow lies on the ground, the `phong` node's
image alone. **Reference:** the same at 128 nodes, the node's maximum. Knob swept:
`medium_shadow_res`. Time: the `phong` node's per frame (`per_frame = true`, the mean of the
frames after the first), which leaves out the volume's build, made once per scene and light
(res^4 field reads: 1.7-2.8 s at 64 on the shared machine), llvmpipe. Metric: relative RMSE
of the linear radiance."""
TARGET = None


def studies(ctx):
    ref = 64 if ctx.quick else 128
    cloud = ctx.write("cloud.lgraph",
                      'lightgraph 1\n'
                      'include "%s"\n'
                      'output lit "%s"\n' % (os.path.join(ctx.root,
                                                          "examples/volumetric_cloud_scene.lgraph"),
                                             os.path.join(ctx.tmp, "cloud.exr")))
    return [Study(id="medium_shadow_res",
                  title="VDB cloud over the ground (the cloud's shadow): medium_shadow_res",
                  technique="phong", backend="gl", graph=cloud, time_node="lit",
                  vary=[("lit.medium_shadow_res", ["8", "16", "32", "64"])],
                  quick_vary=[("lit.medium_shadow_res", ["8", "32"])],
                  sets=["lit.per_frame=true"], ref_sets=["lit.medium_shadow_res=%d" % ref],
                  reference_label="the same at %d nodes" % ref, size="320x180",
                  quick_size="64x36", frames=4, repeat=3, metric="rel_rmse")]
