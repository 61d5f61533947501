"""Reinhard's operator on its three backends x its knobs that change the numbers (the input's
precision, the luminance weights) against the same operator evaluated on the cpu backend."""
import os
import subprocess

from accuracy.study import Study, StudyError

TITLE = "Tone mapping: Reinhard's operator, cpu / gl / cl"
ORDER = 20
INTRO = """\
The `reinhard` node (Reinhard et al. 2002, eqs. 1-4; seed 0, 3.1-3.3) maps the
GoldenGate probe (`assets/images/GoldenGate.exr`, box-reduced to 631 x 430) to display range
on the `cpu`,
`gl` (compute shaders) or `cl` backend; [plugins/reinhard/README.md](../plugins/reinhard/README.md).
**Reference:** the same operator on the `cpu` backend from the float input (the tests hold it
to their double-precision oracle within 1e-6 relative, `reinhard math`). The backends
differ from it only by the order of their float sums (a GL or CL reduction tree), so their
error is rounding (around 1e-7); what costs accuracy is the input's precision (half floats:
11-bit mantissa; RGBE: 8-bit mantissa shared by the three channels), and the seed's luminance
weights against Rec. 709's. Knobs swept: `backend` x `luminance` (rec709 | seed) in each
`mode` (luminance | rgb), and the input stored as float EXR, half EXR and RGBE (.hdr) x
`backend`. Time: the node's per frame (`adapt = true`, `adapt_rate = 0`, which adapts at once
and so maps each frame exactly as the static operator while running every frame: the steady
cost, not the first frame's shader and kernel compilation). Metric: relative RMSE of the
display-referred linear output."""

IMAGE = "assets/images/GoldenGate.exr"


def _run(cmd, what):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise StudyError("%s: `%s` failed:\n%s" % (what, " ".join(cmd), r.stderr))


def inputs(ctx):
    """The probe as float EXR, half EXR and RGBE, box-reduced 2x (631 x 430; 2 is the only
    factor that divides 1262 x 860): each run of a sweep reads and writes whole images, at
    full size seconds apiece on llvmpipe's shared 2 cores, and the node's time scales with
    the pixel count, which changes no comparison."""
    factor = "2"
    tool = os.path.join(ctx.build, "tools", "lg_exr_recompress")
    src = os.path.join(ctx.root, IMAGE)
    out = {}
    for kind in ("float", "half"):
        out[kind] = os.path.join(ctx.tmp, "goldengate_%s.exr" % kind)
        _run([tool, src, out[kind], "zip", kind, factor], "reinhard's %s input" % kind)
    out["rgbe"] = os.path.join(ctx.tmp, "goldengate_rgbe.hdr")
    g = ctx.write("to_rgbe.lgraph", 'lightgraph 1\nsrc = image { file = "%s" }\n'
                  'output src "%s"\n' % (out["float"], out["rgbe"]))
    _run([ctx.lightgraph, "render", g], "reinhard's rgbe input")
    return out


def studies(ctx):
    files = inputs(ctx)
    graph = ctx.write("reinhard.lgraph",
                      'lightgraph 1\n'
                      'src = image { file = "%s" }\n'
                      'tone = reinhard { image = src, key = 0.18, adapt = true, '
                      'adapt_rate = 0 }\n'
                      'output tone "%s"\n' % (files["float"], os.path.join(ctx.tmp, "tone.exr")))
    backends = ["cpu", "gl", "cl"]
    # no ref sets needed: the graph's own defaults (cpu, rec709, the float input) are the
    # reference; each study's --set of the mode applies to the reference as well
    common = dict(technique="reinhard", backend="cpu", graph=graph, time_node="tone",
                  size="631x430", quick_size="631x430", frames=4, repeat=3,
                  ref_sets=["tone.backend=cpu", "tone.luminance=rec709"], metric="rel_rmse",
                  display="clip")  # the output is in display range already
    labels = {"src.file": {files["float"]: "float EXR", files["half"]: "half EXR",
                           files["rgbe"]: "RGBE .hdr"}}
    out = []
    for mode in ("luminance", "rgb"):
        c = dict(common, backend="gl" if mode == "rgb" else "cpu")
        out.append(Study(
            id="reinhard_%s" % mode,
            title="mode = %s: backend x luminance weights" % mode,
            sets=["tone.mode=%s" % mode],
            vary=[("tone.backend", backends), ("tone.luminance", ["rec709", "seed"])],
            quick_vary=[("tone.backend", ["cpu", "cl"]), ("tone.luminance", ["seed"])],
            reference_label="reinhard on cpu, mode %s, Rec. 709 weights, float input" % mode,
            **c))
    out.append(Study(
        id="reinhard_input", title="input precision x backend (mode = luminance)",
        vary=[("src.file", [files["float"], files["half"], files["rgbe"]]),
              ("tone.backend", backends)],
        quick_vary=[("src.file", [files["half"], files["rgbe"]]), ("tone.backend", ["gl"])],
        reference_label="reinhard on cpu from the float input",
        value_labels=labels, **dict(common, backend="gl")))
    return out
