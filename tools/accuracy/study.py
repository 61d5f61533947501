"""study.py: what a section of the accuracy atlas declares (docs/accuracy-guide.md).

A section (tools/accuracy/sections/NAME.py) returns, from studies(ctx), a list of

  Study   one `lightgraph sweep`: a graph, the knobs it varies, the node it times, the
          reference it is compared with;
  Custom  a command that writes the same CSV columns itself (a study that is not one sweep,
          e.g. a C study program).

Both only describe; tools/accuracy/accuracy.py runs them (run_study) and turns their rows
into the section's table, plot and answer. Every row a study yields has the knob columns
(one per varied NODE.PARAM, named as such) plus ROW_COLUMNS.

Plain Python 3.11 standard library.
"""
import csv
import math
import os
import re
import subprocess

# The columns every study's rows carry after its knobs: the time per frame of the timed
# node (median of `repeat` runs, with the spread), the errors against the reference, and
# the reference's own time (ms, once per study). An empty value is None.
ROW_COLUMNS = ["time_ms", "time_min_ms", "time_max_ms", "rmse", "rel_rmse", "ssim", "dssim",
               "ref_ms"]

# The errors a study may name as its `metric` (smaller is better for all of them).
METRICS = {
    "rmse": "RMSE",
    "rel_rmse": "relative RMSE",
    "dssim": "DSSIM",
}

BACKENDS = ("cpu", "gl", "cl")

_ID = re.compile(r"^[a-z0-9_]+$")


class StudyError(Exception):
    """A study that is declared wrong or failed to run; the message names the study."""


def _check_common(kind, id, title, technique, backend, metric):
    if not isinstance(id, str) or not _ID.match(id):
        raise StudyError("%s id %r: must be [a-z0-9_]+" % (kind, id))
    if not title or not technique:
        raise StudyError("%s %s: title and technique are required" % (kind, id))
    if backend not in BACKENDS:
        raise StudyError("%s %s: backend %r is not one of %s" % (kind, id, backend,
                                                                 ", ".join(BACKENDS)))
    if metric not in METRICS:
        raise StudyError("%s %s: metric %r is not one of %s" % (kind, id, metric,
                                                                ", ".join(METRICS)))


def _check_display(id, display):
    if display not in ("reinhard", "clip"):
        raise StudyError("study %s: display %r is not reinhard or clip" % (id, display))


class Study:
    """One `lightgraph sweep` of `graph`: every combination of the `vary` values (the
    cartesian product, as sweep runs them), each compared with the reference (the graph
    `reference`, or `graph` itself with `ref_sets`) and timed at node `time_node` (None:
    the whole graph, every node's CPU wall time summed, as `sweep` without --time times it).

    vary        [(NODE.PARAM, [value, ...]), ...] (values as strings, as --vary takes them)
    quick_vary  the same for --quick; None: the first and the last value of each vary
    sets        ["NODE.PARAM=V", ...]: given to every run (--set)
    ref_sets    ["NODE.PARAM=V", ...]: given to the reference only (--ref-set)
    size        WxH of the full run; quick_size that of --quick
    frames      frames per run (a GL node's time is then its steady per-frame cost)
    repeat      timed runs per point (the median and its spread); --quick uses 1, --repeat
                overrides it for every study
    value_labels  {NODE.PARAM: {value: label}}: how the page names a value (e.g. a generated
                mesh's path as "L8 (224 tris)"); the CSV keeps the value
    display     how the page shows an EXR image: "reinhard" (tone-mapped, key 0.18) or
                "clip" (linear values clipped to [0, 1]: an image in display range already)
    """

    def __init__(self, id, title, technique, backend, graph, time_node, vary, quick_vary=None,
                 sets=(), reference=None, ref_sets=(), reference_label="", size="320x180",
                 quick_size="64x36", frames=1, repeat=5, metric="rel_rmse",
                 value_labels=None, display="reinhard"):
        _check_common("Study", id, title, technique, backend, metric)
        _check_display(id, display)
        if not vary:
            raise StudyError("Study %s: vary is empty" % id)
        for key, values in list(vary) + list(quick_vary or []):
            if "." not in key or not values:
                raise StudyError("Study %s: vary %r: want (NODE.PARAM, [values])" % (id, key))
        self.id, self.title, self.technique, self.backend = id, title, technique, backend
        self.graph, self.time_node = graph, time_node
        self.vary = [(k, [str(v) for v in vs]) for k, vs in vary]
        self.quick_vary = ([(k, [str(v) for v in vs]) for k, vs in quick_vary]
                           if quick_vary else
                           [(k, [vs[0], vs[-1]] if len(vs) > 1 else list(vs))
                            for k, vs in self.vary])
        self.sets, self.reference, self.ref_sets = list(sets), reference, list(ref_sets)
        self.reference_label = reference_label
        self.size, self.quick_size = size, quick_size
        self.frames, self.repeat, self.metric = frames, repeat, metric
        self.value_labels = dict(value_labels or {})
        self.display = display

    def knobs(self, quick):
        return [k for k, _ in (self.quick_vary if quick else self.vary)]

    def command(self, ctx, outdir, repeat=None):
        """The `lightgraph sweep` command line of this study into outdir."""
        quick = ctx.quick
        graph = self.graph if os.path.isabs(self.graph) else os.path.join(ctx.root, self.graph)
        rep = 1 if quick else (repeat or self.repeat)
        cmd = [ctx.lightgraph, "sweep", graph] + (["--time", self.time_node]
                                                   if self.time_node else [])
        cmd += ["--repeat", str(rep), "--frames", str(self.frames), "--size",
                self.quick_size if quick else self.size, "-o", outdir, "--metric", self.metric]
        for k, vs in (self.quick_vary if quick else self.vary):
            cmd += ["--vary", "%s=%s" % (k, ",".join(vs))]
        for s in self.sets:
            cmd += ["--set", s]
        if self.reference:
            ref = (self.reference if os.path.isabs(self.reference)
                   else os.path.join(ctx.root, self.reference))
            cmd += ["--reference", ref]
        for s in self.ref_sets:
            cmd += ["--ref-set", s]
        return cmd


class Custom:
    """A study that writes its rows itself: `command` (a list, run from the repository root;
    in each argument {out} is the study's scratch directory, {build} the build directory,
    {root} the repository root; an argument that is exactly "{quick}" becomes "--quick" in
    a quick run and is dropped otherwise) writes `csv` (relative to {out}) with a header of
    the knob columns and ROW_COLUMNS (any order; an empty field for a value it has not,
    e.g. ssim for an error that is not an image's). Two optional columns name files
    relative to {out}: `image` (the run's image, PNG or EXR) and `heat` (its heat map, PNG);
    `reference_image` (an attribute) names the reference's image the same way; `display`
    as Study's."""

    def __init__(self, id, title, technique, backend, command, csv, reference_label="",
                 metric="rel_rmse", reference_image=None, display="reinhard"):
        _check_common("Custom", id, title, technique, backend, metric)
        _check_display(id, display)
        if not command or not csv:
            raise StudyError("Custom %s: command and csv are required" % id)
        self.id, self.title, self.technique, self.backend = id, title, technique, backend
        self.command_template, self.csv = list(command), csv
        self.reference_label, self.metric = reference_label, metric
        self.reference_image = reference_image
        self.value_labels = {}
        self.display = display

    def command(self, ctx, outdir):
        out = []
        for a in self.command_template:
            if a == "{quick}":
                if ctx.quick:
                    out.append("--quick")
                continue
            out.append(a.replace("{out}", outdir).replace("{build}", ctx.build)
                       .replace("{root}", ctx.root))
        return out


def _number(text):
    """A CSV field as a float, None when empty or not finite-or-infinite text."""
    if text is None:
        return None
    text = text.strip()
    if not text:
        return None
    try:
        return float(text)
    except ValueError:
        return None


class Row:
    """One point of a study: its knob values (strings, in the study's order), its numbers
    (ROW_COLUMNS, floats or None) and its files (absolute paths or None)."""

    def __init__(self, study, knobs, values, image=None, heat=None):
        self.study, self.knobs, self.values = study, knobs, values
        self.image, self.heat = image, heat
        self.front = False

    def error(self):
        return self.values.get(self.study.metric)

    def time(self):
        return self.values.get("time_ms")

    def backend(self):
        """What this row ran on: the value of a varied NODE.backend knob (the SDK's shared
        parameter), else its study's backend."""
        for k, v in self.knobs:
            if k.endswith(".backend") and v in BACKENDS:
                return v
        return self.study.backend

    def shown(self, knob, value):
        """How the page names a knob's value (Study.value_labels, else the value)."""
        return self.study.value_labels.get(knob, {}).get(value, value)

    def label(self):
        return " ".join("%s=%s" % (k.split(".", 1)[1] if "." in k else k, self.shown(k, v))
                        for k, v in self.knobs)


def _quote(text, limit=4000):
    text = text.strip()
    if len(text) > limit:
        text = "...\n" + text[-limit:]
    return "\n".join("    | " + line for line in text.splitlines())


def _run(study, cmd, cwd, env=None):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        raise StudyError("study %s: `%s` failed (exit %d):\n%s" % (
            study.id, " ".join(cmd), r.returncode, _quote(r.stderr or r.stdout)))
    return r


def _ref_rms(path):
    """sqrt(mean b^2) over R, G, B of an EXR reference (for a sweep CSV without rel_rmse)."""
    from accuracy.exr import read_exr
    _, _, ch = read_exr(path)
    vals = [v for c in ("R", "G", "B") if c in ch for v in ch[c] if math.isfinite(v)]
    if not vals:
        return 0.0
    return math.sqrt(sum(v * v for v in vals) / len(vals))


def read_rows(study, path, knob_names, base, columns_of_sweep=False):
    """The rows of a study's CSV at `path`; files are named relative to `base`."""
    with open(path, newline="") as f:
        rd = list(csv.DictReader(f))
    rows = []
    for k, rec in enumerate(rd):
        missing = [n for n in knob_names if n not in rec]
        if missing:
            raise StudyError("study %s: %s has no column %s" % (study.id, path, missing[0]))
        values = {c: _number(rec.get(c)) for c in ROW_COLUMNS}
        if values["time_ms"] is None:
            raise StudyError("study %s: %s row %d has no time_ms" % (study.id, path, k + 1))
        image = heat = None
        if columns_of_sweep:
            run = rec.get("run", str(k))
            image = os.path.join(base, "run-%03d.exr" % int(run))
            heat = os.path.join(base, "heat-%03d.png" % int(run))
        else:
            if rec.get("image"):
                image = os.path.join(base, rec["image"])
            if rec.get("heat"):
                heat = os.path.join(base, rec["heat"])
        rows.append(Row(study, [(n, rec[n]) for n in knob_names], values, image, heat))
    return rows


def run_study(study, ctx, outdir, repeat=None):
    """Runs one study into outdir (created); returns (rows, reference image or None).
    Raises StudyError naming the study, with the failing command's stderr quoted."""
    os.makedirs(outdir, exist_ok=True)
    if isinstance(study, Custom):
        _run(study, study.command(ctx, outdir), ctx.root)
        path = os.path.join(outdir, study.csv)
        if not os.path.exists(path):
            raise StudyError("study %s: its command wrote no %s" % (study.id, study.csv))
        with open(path, newline="") as f:
            head = next(csv.reader(f), [])
        knobs = [c for c in head if c not in ROW_COLUMNS and c not in ("image", "heat", "run")]
        rows = read_rows(study, path, knobs, outdir)
        ref = (os.path.join(outdir, study.reference_image) if study.reference_image else None)
        return rows, ref
    _run(study, study.command(ctx, outdir, repeat), ctx.root)
    path = os.path.join(outdir, "sweep.csv")
    rows = read_rows(study, path, study.knobs(ctx.quick), outdir, columns_of_sweep=True)
    ref = os.path.join(outdir, "reference.exr")
    # sweeps before the shared metrics (branch metric) wrote rmse but not rel_rmse
    if rows and rows[0].values["rel_rmse"] is None and rows[0].values["rmse"] is not None:
        rms = _ref_rms(ref)
        for r in rows:
            e = r.values["rmse"]
            r.values["rel_rmse"] = (e / rms if rms > 0 else (0.0 if e == 0 else math.inf))
    return rows, ref
