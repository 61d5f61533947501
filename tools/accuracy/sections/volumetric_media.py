"""Volumetric lighting in heterogeneous media (issue 25): froxel grids against
volumetric_reference in fBm noise, in height fog and on a VDB cloud. The cases, plans and
runner are sections/volumetric.py's (MEDIA, PLANS, cloud_study, `volumetric.py run`); this
file picks the cases of this section, so that they are made again (`--only
volumetric_media`) without the directional studies."""
from accuracy.sections import volumetric as V

TITLE = "Volumetric lighting: heterogeneous media"
ORDER = 63
INTRO = """\
Issue 25's density fields through the froxel grid, the one real-time method that samples a
field (screen space and polygonal refuse one; [docs/volumetric.md](volumetric.md)). Cases:
the bunny box of [the volumetric section](#volumetric) with its sun in **fBm noise** (`field =
fbm`, frequency 2, 4 octaves) and in **height fog** (`height_falloff = 2` from the floor), the
froxel grid W x H x D x `slicing` swept on cpu (cl gave the same errors to 5 digits in fBm in
a run that a rebuild of the binaries interrupted; gl agrees with them to 1e-3, its tests, and
is the slowest here under llvmpipe); and a **VDB cloud**
(`examples/volumetric_cloud.lgraph`: the 64^3 float grid the build writes with
tools/make_vdb_cloud.cpp, 5.1 m wide, sigma_s 6, g 0.6, a low sun), froxel on cpu with the
example's 190 x 90 grid and exponential slices, its `depth` x `tau_res` (the cells along the
longest side of the sun's optical-depth volume: the cloud's shadow on itself) swept.
**Reference:** `volumetric_reference` with ratio tracking through the field (unbiased
transmittance along the view ray and towards the sun), rays through pixel centres, **at 160 x
90 with 256 steps x 4 rays** (the fBm reference at the volumetric section's 320 x 180 x 1024 x
4 stalled the last run: on this shared machine, load 20-25, it took 69 s for 64 x 36 x 256 x
4). Its own error there, in fBm noise: **0.82 %** (two seeds differ by 1.15 % relative RMSE;
/ sqrt 2), so an error above 2 % is the method's to within 10 % (the two add in squares).
**Time:** the `vol` node's per frame in steady state (3 frames, the first left out).
**Metric:** relative RMSE of the linear in-scatter over the image."""
TARGET = None


def studies(ctx):
    return V.case_studies(ctx, V.cases("volumetric_media")) + [V.cloud_study(ctx)]
