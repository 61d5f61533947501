#!/usr/bin/env python3
"""accuracy.py: what accuracy costs, for the whole renderer (issue 23, item 1): one generated
page, docs/accuracy.md, with every technique's error against its reference and its time.

usage: tools/accuracy/accuracy.py --build BUILD --out DIR [--quick] [--only SECTION,...]
                                  [--target 0.01] [--repeat N] [--keep-going]

Every module of tools/accuracy/sections/ is a section (one technique): its TITLE, ORDER,
INTRO and studies(ctx), a list of study.Study (one `lightgraph sweep`) and study.Custom (a
command writing the same CSV). For each section the generator runs its studies, then writes

  - a table per study: the knobs, the time (median [min-max] of the repeats), RMSE, relative
    RMSE, DSSIM, and a mark on the rows of the section's Pareto front (no other row of the
    section has both lower-or-equal time and lower-or-equal error, one of them strictly);
  - one gnuplot plot, error against time on log-log axes, every study a point style, the
    front as a line and the target as a horizontal line, captioned with the machine (CPU
    model, cores), the backends, the load average at the section's start and end, the date;
  - the one-line answer: the cheapest row within the target, and the reference's time;
  - the answer's image beside its error heat map, and the reference's image.

Output: DIR/accuracy.md, DIR/images/accuracy/*.png and DIR/images/accuracy/data/ (each
study's CSV, each section's gnuplot script and its page fragment). All or nothing: the files
are made in a temporary directory next to DIR and moved into place when every study has
succeeded; a failing study (its command's stderr quoted, its id named) fails the run with
exit status 1 and writes nothing. With --only the sections named are made again and the
others are kept as the page had them (their fragments in data/). --keep-going makes the unit
of all-or-nothing the section instead of the run: a section whose study fails keeps what the
page had (its fragment and images, or no place on the page if it had none), the sections that
finished are written, and the exit status is still 1 (the failed sections named).

--quick: every study at its quick_size, with its quick_vary (by default the first and last
value of each knob) and one repeat; for the test suite (meson test accuracy_quick), which
checks the page can be made, not its timings.

Exit status: 0 written, 1 a study or the writing failed, 2 bad usage or a section declared
wrong. Plain Python 3.11 and gnuplot. How to add a section: tools/accuracy/README.md.
"""
import argparse
import csv
import datetime
import importlib.util
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
from accuracy.study import (Custom, METRICS, ROW_COLUMNS, Study, StudyError,  # noqa: E402
                            run_study)
from accuracy.png import stretch_thin  # noqa: E402

IMAGES = os.path.join("images", "accuracy")
DATA = os.path.join(IMAGES, "data")


class UsageError(Exception):
    pass


# ---- the machine and the moment --------------------------------------------------------------

def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def loadavg():
    try:
        with open("/proc/loadavg") as f:
            return " ".join(f.read().split()[:3])
    except OSError:
        return "?"


def now_utc():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")


def git_commit():
    try:
        r = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"],
                           capture_output=True, text=True)
        return r.stdout.strip() or "unknown"
    except OSError:
        return "unknown"


# ---- sections --------------------------------------------------------------------------------

class Section:
    def __init__(self, name, module):
        self.name, self.module = name, module
        for attr in ("TITLE", "ORDER", "INTRO", "studies"):
            if not hasattr(module, attr):
                raise UsageError("section %s (%s): no %s" % (name, module.__file__, attr))
        self.title, self.order, self.intro = module.TITLE, module.ORDER, module.INTRO
        self.target = getattr(module, "TARGET", None)


def discover(sections_dir):
    """Every NAME.py of sections_dir (not starting with _), ordered by ORDER then name."""
    out = []
    for fn in sorted(os.listdir(sections_dir)):
        if not fn.endswith(".py") or fn.startswith("_"):
            continue
        name = fn[:-3]
        if not name.replace("_", "").isalnum() or name != name.lower():
            raise UsageError("section file %s: the name must be [a-z0-9_]" % fn)
        spec = importlib.util.spec_from_file_location("accuracy_section_" + name,
                                                      os.path.join(sections_dir, fn))
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        out.append(Section(name, mod))
    out.sort(key=lambda s: (s.order, s.name))
    return out


class Context:
    """What a section's studies(ctx) sees (tools/accuracy/README.md)."""

    def __init__(self, quick, build, tmp, repeat=None):
        self.quick, self.build, self.root, self.tmp = quick, build, ROOT, tmp
        # the generator's --repeat (None: each study's own), for Custom studies' commands
        self.repeat = repeat
        self.lightgraph = os.path.join(build, "lightgraph")
        os.makedirs(tmp, exist_ok=True)

    def write(self, name, text):
        path = os.path.join(self.tmp, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
        return path


# ---- numbers ---------------------------------------------------------------------------------

def usable(r):
    t, e = r.time(), r.error()
    return t is not None and e is not None and math.isfinite(t) and not math.isnan(e)


def pareto(rows):
    """Marks r.front on the rows no other row dominates (lower-or-equal time and error, one
    strictly); returns the front sorted by time. Rows without a time or an error are out."""
    pts = [r for r in rows if usable(r)]
    front = []
    for r in pts:
        t, e = r.time(), r.error()
        r.front = not any(o is not r and o.time() <= t and o.error() <= e and
                          (o.time() < t or o.error() < e) for o in pts)
        if r.front:
            front.append(r)
    for r in rows:
        if r not in pts:
            r.front = False
    return sorted(front, key=lambda r: (r.time(), r.error()))


def answer_row(rows, target):
    """The cheapest row within the target, or None. A row of error exactly 0 is the
    reference's own setting run again (per-pixel Phong against per-pixel Phong): it stays in
    the table and the front but is not an answer, whose line gives the reference's time."""
    ok = [r for r in rows if usable(r) and 0 < r.error() <= target]
    return min(ok, key=lambda r: (r.time(), r.error())) if ok else None


def fmt_time(ms):
    if ms is None:
        return "?"
    if ms >= 1000:
        return "%.3g s" % (ms / 1000)
    return "%.3g ms" % ms


def reference_time(rows, study):
    """The reference's time as the answer states it: the node's time of a row of the study
    with error 0 (the reference's own setting, timed like the others), else the sweep's
    ref_ms (the reference's whole render, once: planning and compilation included)."""
    zero = [r.time() for r in rows if r.study is study and usable(r) and r.error() == 0]
    if zero:
        return "%s per frame of the node" % fmt_time(min(zero))
    ref = next((r.values["ref_ms"] for r in rows if r.study is study and
                r.values["ref_ms"] is not None), None)
    if ref is not None:
        return "%s for its whole render, once" % fmt_time(ref)
    return "its time not measured"


def fmt_err(v):
    if v is None:
        return ""
    if math.isinf(v):
        return "inf"
    return "%.3g" % v


def fmt_target(metric, target):
    if metric == "rmse":
        return "RMSE %.3g" % target
    return "%g%% %s" % (target * 100, METRICS[metric])


# ---- images ----------------------------------------------------------------------------------

def displayable(ctx, src, dst, display):
    """dst (PNG) from src: a PNG is copied; an EXR is rendered by a tiny graph that loads it
    and, with display "reinhard", tone-maps it (Reinhard's operator, key 0.18, on the cpu
    backend); with "clip" its linear values go to the PNG writer as they are (clipped to
    [0, 1]: for images in display range already, a tone mapper's output)."""
    if src.endswith(".png"):
        shutil.copyfile(src, dst)
        stretch_thin(dst)
        return
    if display == "reinhard":
        body = ('src = image { file = "%s" }\ntone = reinhard { image = src, key = 0.18 }\n'
                'output tone "%s"\n' % (src, dst))
    else:
        body = 'src = image { file = "%s" }\noutput src "%s"\n' % (src, dst)
    g = ctx.write("topng_%s.lgraph" % os.path.basename(dst)[:-4], "lightgraph 1\n" + body)
    r = subprocess.run([ctx.lightgraph, "render", g], capture_output=True, text=True)
    if r.returncode != 0:
        raise StudyError("the image %s could not be made displayable:\n%s" % (src, r.stderr))
    # a strip a few pixels tall (prt's per-vertex images) is stretched to be seen
    stretch_thin(dst)


# ---- one section -----------------------------------------------------------------------------

def write_csv(path, study, rows):
    knobs = [k for k, _ in rows[0].knobs] if rows else []
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(knobs + ROW_COLUMNS + ["front"])
        for r in rows:
            w.writerow([v for _, v in r.knobs] +
                       ["" if r.values[c] is None else "%.6g" % r.values[c]
                        for c in ROW_COLUMNS] + [1 if r.front else 0])


COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b",
           "#e377c2", "#7f7f7f", "#bcbd22"]
POINTS = [5, 7, 9, 11, 13, 4, 6, 8, 10, 12]


def study_colour(i):
    """Study i's colour: with POINTS cycling every 10 studies, the colour shifts by one more
    each cycle, so no two of the first 100 studies share both point type and colour."""
    return COLOURS[(i + i // len(POINTS)) % len(COLOURS)]


def gp_string(text):
    """A gnuplot double-quoted string (escapes interpreted: \\n is a new line)."""
    return '"%s"' % text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")


def log_tics(lo, hi):
    """gnuplot tics at 1, 2, 5 x 10^k between lo and hi: a log axis spanning less than two
    decades otherwise has one label or none."""
    out = []
    mant = (1, 2, 5) if hi / lo < 1000 else (1,)  # past three decades, the decades suffice
    for k in range(int(math.floor(math.log10(lo))), int(math.ceil(math.log10(hi))) + 1):
        out += [m * 10.0 ** k for m in mant if lo <= m * 10.0 ** k <= hi]
    return "(%s)" % ", ".join("'%g' %.6g" % (v, v) for v in out)


def wrap(text, width):
    lines, cur = [], ""
    for part in text.split("; "):
        if cur and len(cur) + 2 + len(part) > width:
            lines.append(cur + ";")
            cur = part
        else:
            cur = cur + "; " + part if cur else part
    return lines + [cur]


def plot(section, studies, rows, front, target, caption, stage):
    """The section's gnuplot script (data/NAME.gp, self-contained) and plot (NAME.png).
    Errors of 0 (a row identical to its reference) cannot sit on a log axis: they are drawn
    on the bottom edge, which the caption says."""
    gp = os.path.join(stage, DATA, section.name + ".gp")
    png = section.name + ".png"
    metrics = sorted({s.metric for s in studies})
    ylabel = " / ".join(METRICS[m] for m in metrics) + " against the reference"
    pts = [r for r in rows if usable(r)]
    pos = [r.error() for r in pts if 0 < r.error() < math.inf] + [target]
    times = [r.time() for r in pts if r.time() > 0] or [1.0]
    ylo, yhi = min(pos) / 2, max(pos) * 2
    xlo, xhi = min(times) / 1.5, max(times) * 1.5
    zero = any(r.error() <= 0 for r in pts)

    def y(r):
        return min(max(r.error(), ylo), yhi)
    lines = ["# written by tools/accuracy/accuracy.py: %s, error against time" % section.title]
    blocks = []
    for i, s in enumerate(studies):
        sp = [r for r in pts if r.study is s and r.time() > 0]
        if not sp:
            continue
        lines.append("$s%d << EOD" % i)
        lines += ["%.6g %.6g" % (r.time(), y(r)) for r in sp]
        lines.append("EOD")
        blocks.append("$s%d using 1:2 with points pt %d ps 1.6 lw 1.5 lc rgb '%s' title '%s'"
                      % (i, POINTS[i % len(POINTS)], study_colour(i), s.id))
    fp = [r for r in front if r.time() > 0]
    if fp:
        lines.append("$front << EOD")
        lines += ["%.6g %.6g" % (r.time(), y(r)) for r in fp]
        lines.append("%.6g %.6g" % (xhi, y(fp[-1])))
        lines.append("EOD")
        blocks.insert(0, "$front using 1:2 with steps lw 2 lc rgb '#404040' "
                      "title 'Pareto front'")
    blocks.append("%.6g with lines dt 2 lw 2 lc rgb '#c00000' title 'target %s'"
                  % (target, fmt_target(metrics[0], target)))
    title = "\n".join([section.title] + wrap(caption + ("; error 0 drawn on the bottom edge"
                                                        if zero else ""), 110))
    lines += [
        "set terminal pngcairo size 1000,640 noenhanced font ',10'",
        "set output '%s'" % png,
        "set logscale xy",
        "set grid",
        "set key outside right top",
        "set xrange [%.6g:%.6g]" % (xlo, xhi),
        "set yrange [%.6g:%.6g]" % (ylo, yhi),
        "set xtics %s" % log_tics(xlo, xhi),
        "set ytics %s" % log_tics(ylo, yhi),
        "set xlabel 'time per frame of the timed node (ms, median)'",
        "set ylabel '%s'" % ylabel,
        "set title %s" % gp_string(title),
        "plot " + ", \\\n     ".join(blocks),
    ]
    with open(gp, "w") as f:
        f.write("\n".join(lines) + "\n")
    r = subprocess.run(["gnuplot", gp], cwd=os.path.join(stage, IMAGES), capture_output=True,
                       text=True)
    if r.returncode != 0 or not os.path.exists(os.path.join(stage, IMAGES, png)):
        raise StudyError("section %s: gnuplot failed on %s:\n%s" % (section.name, gp, r.stderr))
    return png


def run_section(section, args, stage, machine):
    target = section.target if section.target is not None else args.target
    ctx = Context(args.quick, args.build, os.path.join(stage, "work", section.name), args.repeat)
    try:
        studies = section.module.studies(ctx)
    except StudyError as e:
        raise UsageError("section %s: %s" % (section.name, e))
    if not studies:
        raise UsageError("section %s: studies(ctx) returned none" % section.name)
    ids = set()
    for s in studies:
        if not isinstance(s, (Study, Custom)):
            raise UsageError("section %s: %r is not a Study or a Custom" % (section.name, s))
        if s.id in ids:
            raise UsageError("section %s: study id %s twice" % (section.name, s.id))
        ids.add(s.id)
    load0, date, t0 = loadavg(), now_utc(), time.monotonic()
    rows, refs = [], {}
    for s in studies:
        sys.stderr.write("accuracy: %s / %s\n" % (section.name, s.id))
        srows, ref = run_study(s, ctx, os.path.join(ctx.tmp, s.id), args.repeat)
        if not srows:
            raise StudyError("study %s: no rows" % s.id)
        rows += srows
        refs[s.id] = ref
    load1, secs = loadavg(), time.monotonic() - t0
    front = pareto(rows)
    for s in studies:
        write_csv(os.path.join(stage, DATA, "%s-%s.csv" % (section.name, s.id)), s,
                  [r for r in rows if r.study is s])
    backends = ", ".join(sorted({r.backend() for r in rows}))
    caption = ("%s, %d cores; backend %s; load average %s at the start, %s at the end; %s%s"
               % (machine, os.cpu_count() or 0, backends, load0, load1, date,
                  "; --quick" if args.quick else ""))
    png = plot(section, studies, rows, front, target, caption, stage)

    # the answer
    metrics = {s.metric for s in studies}
    metric = sorted(metrics)[0]
    best = answer_row(rows, target)
    shown = best or min((r for r in rows if usable(r) and r.error() > 0),
                        key=lambda r: (r.error(), r.time()), default=None)
    if best:
        ans = "for %s: %s %s, %s on %s" % (fmt_target(best.study.metric, target),
                                           best.study.technique, best.label(),
                                           fmt_time(best.time()), best.backend())
    elif shown:
        ans = ("no setting swept reaches %s: best %s %s (%s %s) at %s on %s"
               % (fmt_target(metric, target), shown.study.technique, shown.label(),
                  METRICS[shown.study.metric], fmt_err(shown.error()), fmt_time(shown.time()),
                  shown.backend()))
    else:
        ans = "no row has both a time and an error"
    if shown:
        ans += "; the reference (%s): %s" % (shown.study.reference_label or "see below",
                                             reference_time(rows, shown.study))
    imgs, heat_note = [], ""
    if shown:
        ref = refs.get(shown.study.id)
        heat = shown.heat
        rmse = shown.values.get("rmse")
        if (shown.image and ref and shown.image.endswith((".exr", ".png")) and rmse and rmse > 0 and
                os.path.exists(shown.image) and os.path.exists(ref)):
            # the sweep's heat map puts white at the largest error, often one pixel, and the
            # rest is black; this one saturates at 4 x the RMSE, so the error's layout shows
            heat = os.path.join(ctx.tmp, "heat_answer.png")
            cmd = [ctx.lightgraph, "diff", shown.image, ref, "--heatmap", heat, "--heat-max",
                   "%.6g" % (4 * rmse)]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0 or not os.path.exists(heat):
                raise StudyError("section %s: `%s` failed:\n%s" % (section.name, " ".join(cmd),
                                                                    r.stderr))
            heat_note = ", white at 4 x its RMSE (%.3g)" % (4 * rmse)
        for kind, src in (("answer", shown.image), ("heat", heat), ("reference", ref)):
            if src and os.path.exists(src):
                dst = "%s-%s.png" % (section.name, kind)
                displayable(ctx, src, os.path.join(stage, IMAGES, dst),
                            "clip" if kind == "heat" else shown.study.display)
                imgs.append((kind, dst))

    md = ['<a id="%s"></a>' % section.name, "", "## %s" % section.title, "",
          section.intro.strip(), "", "**Answer:** %s." % ans, "",
          "![%s: error against time](%s/%s)" % (section.title, IMAGES, png), "",
          "*%s. Made in %.0f s at commit `%s`.*" % (caption, secs, git_commit()), ""]
    if imgs:
        names = {"answer": "%s (%s)" % (shown.label() or shown.study.id, shown.study.id),
                 "heat": "its error heat map" + heat_note, "reference": "the reference"}
        md += ["| " + " | ".join(names[k] for k, _ in imgs) + " |",
               "|" + "---|" * len(imgs),
               "| " + " | ".join("![%s](%s/%s)" % (k, IMAGES, f) for k, f in imgs) + " |", ""]
    for s in studies:
        srows = [r for r in rows if r.study is s]
        knobs = [k for k, _ in srows[0].knobs]
        ref_ms = next((r.values["ref_ms"] for r in srows if r.values["ref_ms"] is not None),
                      None)
        md += ["### %s" % s.title, "",
               "`%s`: %s on %s, against %s%s; error: %s. Data: [%s-%s.csv](%s/%s-%s.csv)." % (
                   s.id, s.technique, " / ".join(sorted({r.backend() for r in srows})),
                   s.reference_label or "its reference",
                   " (its whole render: %s)" % fmt_time(ref_ms) if ref_ms is not None else "",
                   METRICS[s.metric], section.name, s.id, DATA, section.name, s.id), "",
               "| " + " | ".join("`%s`" % k for k in knobs) +
               " | time ms, median [min-max] | RMSE | rel. RMSE | DSSIM | front |",
               "|" + "---|" * len(knobs) + "---:|---:|---:|---:|:---:|"]
        for r in srows:
            v = r.values
            spread = ""
            if v["time_min_ms"] is not None and v["time_max_ms"] is not None:
                spread = " [%s-%s]" % (fmt_err(v["time_min_ms"]), fmt_err(v["time_max_ms"]))
            elif v["time_min_ms"] is not None:  # a sweep before time_max_ms (branch metric)
                spread = " [min %s]" % fmt_err(v["time_min_ms"])
            md.append("| " + " | ".join(r.shown(k, x) for k, x in r.knobs) +
                      " | %s%s | %s | %s | %s | %s |" % (
                          fmt_err(v["time_ms"]), spread, fmt_err(v["rmse"]),
                          fmt_err(v["rel_rmse"]), fmt_err(v["dssim"]),
                          "**\u25cf**" if r.front else ""))
        md.append("")
    text = "\n".join(md)
    with open(os.path.join(stage, DATA, section.name + ".md"), "w") as f:
        f.write(text)
    sys.stderr.write("accuracy: %s done in %.1f s: %s\n" % (section.name, secs, ans))
    return text


# ---- the page --------------------------------------------------------------------------------

HOW_TO_READ = """\
**How to read it.** Every technique is compared with its *reference*: an image made by a
method that is exact for the scene (or converged far beyond the settings swept), named in
each study. The errors are over R, G and B of the linear images, on the pixels finite in both
([docs/metrics.md](metrics.md): the definitions `lightgraph diff`, `sweep` and `tune` share):

- **RMSE**: sqrt(mean (a - b)^2), in the image's units (linear radiance);
- **relative RMSE**: RMSE / sqrt(mean b^2), the error as a fraction of the reference's RMS
  (0.01 = 1%): numerically off;
- **SSIM / DSSIM**: the structural similarity of the luminance (Wang et al. 2004, 11x11
  Gaussian windows, the range L from the reference) and DSSIM = 1 - SSIM: visibly wrong
  (structure, edges, banding) rather than slightly off; empty where an image has no window.

**Time** is the time per frame of the node the technique runs in (its CPU wall time, which
includes its GL work, docs/devices.md), the **median of N repeated runs** with the smallest
and largest in brackets; a GL node renders several frames so that its time is the steady
one, not its shader compilation. A row is on the **Pareto front** (marked \u25cf, the line in
the plot) when no other row of its section is both as fast and as accurate and better in
one of the two: the settings worth choosing. The **answer** is the cheapest row within the
target error (a row of error 0, the reference's own setting run again, is not one); the
reference's own time is given beside it. Each figure names the machine,
the backend, the load average at its section's start and end, and the date, since times on a
shared machine move with its load. For a scene of your own, `lightgraph tune` searches a
node's knobs for the cheapest setting within an error ([docs/tune.md](tune.md)).
"""


def page(args, fragments, sections, cmdline):
    head = ["# What accuracy costs", "",
            "<!-- generated by tools/accuracy/accuracy.py: do not edit; `make accuracy` -->", "",
            "For every technique of the renderer: its error against its reference and its time, "
            "the settings on the Pareto front, and the cheapest setting within %s (the sections' "
            "targets may differ)." % fmt_target("rel_rmse", args.target), "",
            "**How it was made.** `%s` at commit `%s`, %s, on %s (%d cores)%s. "
            "How to add a technique: [tools/accuracy/README.md](../tools/accuracy/README.md)."
            % (cmdline, git_commit(), now_utc(), cpu_model(), os.cpu_count() or 0,
               "; **--quick: tiny sizes, two points per knob, one repeat: not a measurement**"
               if args.quick else ""), "",
            HOW_TO_READ, "## Contents", ""]
    for s in sections:
        if s.name in fragments:
            ans = next((ln for ln in fragments[s.name].splitlines()
                        if ln.startswith("**Answer:**")), "")
            head.append("- [%s](#%s): %s" % (s.title, s.name, ans[len("**Answer:** "):]))
    head.append("")
    body = [fragments[s.name] for s in sections if s.name in fragments]
    return "\n".join(head) + "\n" + "\n".join(body)


def drop_staged(stage, name):
    """Removes what a failed section left in stage's images (its files start with `name-`
    or `name.`), so that the page's own files of the section are kept in their place."""
    for d in (os.path.join(stage, IMAGES), os.path.join(stage, DATA)):
        if os.path.isdir(d):
            for fn in os.listdir(d):
                if fn.startswith((name + "-", name + ".")):
                    os.remove(os.path.join(d, fn))


def commit(stage, out, keep_from_old):
    """Moves stage's accuracy.md and images/accuracy into out; the old images directory stays
    as a backup until the new one is in place."""
    os.makedirs(os.path.join(out, "images"), exist_ok=True)
    new_img, old_img = os.path.join(stage, IMAGES), os.path.join(out, IMAGES)
    backup = os.path.join(stage, "old-images")
    if keep_from_old and os.path.isdir(old_img):
        for dirpath, _, files in os.walk(old_img):
            rel = os.path.relpath(dirpath, old_img)
            for fn in files:
                if not any(fn.startswith(p) for p in keep_from_old["drop"]):
                    dst = os.path.join(new_img, rel, fn)
                    if not os.path.exists(dst):
                        os.makedirs(os.path.dirname(dst), exist_ok=True)
                        shutil.copy2(os.path.join(dirpath, fn), dst)
    if os.path.isdir(old_img):
        os.replace(old_img, backup)
    try:
        os.replace(new_img, old_img)
    except OSError:
        if os.path.isdir(backup):
            os.replace(backup, old_img)
        raise
    os.replace(os.path.join(stage, "accuracy.md"), os.path.join(out, "accuracy.md"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="the build directory (has lightgraph)")
    ap.add_argument("--out", required=True, help="writes OUT/accuracy.md and OUT/images/accuracy")
    ap.add_argument("--quick", action="store_true", help="tiny sizes, 2 points, 1 repeat")
    ap.add_argument("--only", default="", help="comma-separated section names")
    ap.add_argument("--target", type=float, default=0.01,
                    help="the error the answers aim at (default 0.01: 1%% relative RMSE)")
    ap.add_argument("--repeat", type=int, default=None,
                    help="timed runs per point for every study (default: each study's own)")
    ap.add_argument("--keep-going", action="store_true",
                    help="a failing section keeps what the page had; the others are written "
                    "(exit status 1 all the same)")
    ap.add_argument("--sections", default=os.path.join(HERE, "sections"),
                    help=argparse.SUPPRESS)  # the self-test's sections
    try:
        args = ap.parse_args(argv)
    except SystemExit as e:
        return 2 if e.code else 0
    args.build = os.path.abspath(args.build)
    out = os.path.abspath(args.out)
    try:
        if not os.path.exists(os.path.join(args.build, "lightgraph")):
            raise UsageError("%s/lightgraph does not exist: build first" % args.build)
        if not args.target > 0:
            raise UsageError("--target %g: must be > 0" % args.target)
        if args.repeat is not None and args.repeat < 1:
            raise UsageError("--repeat %d: must be >= 1" % args.repeat)
        if not shutil.which("gnuplot"):
            raise UsageError("gnuplot is not installed (apt-get install gnuplot-nox)")
        sections = discover(args.sections)
        if args.only:
            names = [n for n in args.only.split(",") if n]
            unknown = [n for n in names if n not in {s.name for s in sections}]
            if unknown:
                raise UsageError("--only %s: no such section (there are: %s)"
                                 % (unknown[0], ", ".join(s.name for s in sections)))
            run = [s for s in sections if s.name in names]
        else:
            run = sections
        if not run:
            raise UsageError("no section to run in %s" % args.sections)
    except UsageError as e:
        sys.stderr.write("accuracy: %s\n" % e)
        return 2

    parent = os.path.dirname(out)
    if not os.path.isdir(parent):
        sys.stderr.write("accuracy: --out %s: its parent directory does not exist\n" % out)
        return 2
    stage = tempfile.mkdtemp(prefix=".accuracy-", dir=parent)
    os.makedirs(os.path.join(stage, DATA))
    machine = cpu_model()
    def rel(path):
        r = os.path.relpath(path, ROOT)
        return path if r.startswith("..") else r
    cmdline = "tools/accuracy/accuracy.py " + " ".join(
        a for a in ["--build", rel(args.build), "--out", rel(out)] +
        (["--quick"] if args.quick else []) +
        (["--only", args.only] if args.only else []) +
        (["--target", "%g" % args.target] if args.target != 0.01 else []) +
        (["--repeat", str(args.repeat)] if args.repeat else []) +
        (["--keep-going"] if args.keep_going else []))
    failed = []
    try:
        fragments = {}
        for s in run:
            try:
                fragments[s.name] = run_section(s, args, stage, machine)
            except StudyError as e:
                if not args.keep_going:
                    raise
                failed.append(s)
                drop_staged(stage, s.name)
                sys.stderr.write("accuracy: %s\naccuracy: --keep-going: section %s keeps what "
                                 "the page had\n" % (e, s.name))
        if failed and len(failed) == len(run):
            raise StudyError("every section run failed (%s)" % ", ".join(s.name for s in failed))
        keep = None
        if args.only or failed:
            # the sections not run, and those that failed, keep what the page had
            for s in sections:
                old = os.path.join(out, DATA, s.name + ".md")
                if (s not in run or s in failed) and os.path.exists(old):
                    with open(old) as f:
                        fragments[s.name] = f.read()
            keep = {"drop": [s.name + p for s in run if s not in failed for p in ("-", ".")]}
        with open(os.path.join(stage, "accuracy.md"), "w") as f:
            f.write(page(args, fragments, sections, cmdline.strip()))
        os.makedirs(out, exist_ok=True)
        commit(stage, out, keep)
    except UsageError as e:
        sys.stderr.write("accuracy: %s; nothing was written\n" % e)
        shutil.rmtree(stage, ignore_errors=True)
        return 2
    except (StudyError, OSError) as e:
        sys.stderr.write("accuracy: %s\naccuracy: nothing was written to %s\n" % (e, out))
        shutil.rmtree(stage, ignore_errors=True)
        return 1
    except KeyboardInterrupt:
        sys.stderr.write("accuracy: interrupted; nothing was written to %s\n" % out)
        shutil.rmtree(stage, ignore_errors=True)
        return 130
    shutil.rmtree(stage, ignore_errors=True)
    print("wrote %s and %s" % (os.path.join(out, "accuracy.md"), os.path.join(out, IMAGES)))
    if failed:
        sys.stderr.write("accuracy: written without the sections that failed (%s: kept as the "
                         "page had them)\n" % ", ".join(s.name for s in failed))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
