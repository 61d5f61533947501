#!/usr/bin/env python3
"""_prefilter.py: the probe section's Custom study (tools/accuracy/sections/probe.py): runs
tools/prefilter_study.c (build/tools/lg_prefilter_study) and writes its rows in the atlas's
columns (tools/accuracy/study.py ROW_COLUMNS).

usage: _prefilter.py --build BUILD --out DIR [--root ROOT] [--quick]

lg_prefilter_study prefilters the forest probe (box-downsampled, resampled once to a cube)
into GGX chains with 16, 32, ... samples per texel, with the n.l weighting (source-lod
filtering on and off) and the n.l Vis weighting, and measures each chain's split sum
(lg_probe_ggx_split_sum, the formula `reflect` evaluates) against the Monte Carlo oracle
lg_probe_ggx_reference. Here, per chain: knobs `weighting` (nol, nol_vis), `source_lod` (on,
off) and `samples`; rel_rmse is the root mean square over the five roughnesses of the
program's relative RMS error at n = v (where the split sum is exact but for sampling, so
what remains is the prefilter's); time_ms the prefilter's wall time (median of the
program's runs, min and max beside it); rmse, ssim and dssim are empty (not an image).
Writes DIR/prefilter.csv and keeps the program's own CSV and output beside it.
"""
import argparse
import csv
import math
import os
import statistics
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.dirname(os.path.abspath(__file__))))))
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    exe = os.path.join(a.build, "tools", "lg_prefilter_study")
    if not os.access(exe, os.X_OK):
        sys.exit("_prefilter.py: %s is not built (ninja -C %s tools/lg_prefilter_study)"
                 % (exe, a.build))
    probe = os.path.join(a.root, "assets", "probes", "forest_1024x512.hdr")
    if a.quick:
        args, runs = ["--down", "8", "--face", "16", "--levels", "3", "--dirs", "8",
                      "--oracle", "4096", "--max-samples", "32"], 1
    else:
        args, runs = ["--down", "4", "--face", "64", "--levels", "5", "--dirs", "32",
                      "--oracle", "65536", "--max-samples", "1024"], 3
    times = {}
    errors = {}
    for k in range(runs):
        raw = os.path.join(a.out, "prefilter_study_%d.csv" % k)
        cmd = [exe, "--probe", probe, "--threads", "2", "--csv", raw] + args
        r = subprocess.run(cmd, capture_output=True, text=True)
        with open(os.path.join(a.out, "prefilter_study_%d.txt" % k), "w") as f:
            f.write("$ " + " ".join(cmd) + "\n" + r.stdout + r.stderr)
        if r.returncode != 0:
            sys.exit("_prefilter.py: `%s` failed (exit %d):\n%s" % (" ".join(cmd), r.returncode,
                                                                    r.stderr or r.stdout))
        with open(raw, newline="") as f:
            for rec in csv.DictReader(f):
                key = (rec["mode"], int(rec["samples"]))
                times.setdefault(key, {})[k] = float(rec["seconds"]) * 1e3
                if rec["view"] == "n=v":
                    errors.setdefault(key, {})[rec["roughness"]] = float(rec["rel_rms_error"])
    if not errors:
        sys.exit("_prefilter.py: lg_prefilter_study wrote no n=v rows")
    modes = {"source-lod": ("nol", "on"), "no-source-lod": ("nol", "off"),
             "source-lod-vis": ("nol_vis", "on")}
    with open(os.path.join(a.out, "prefilter.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["weighting", "source_lod", "samples", "time_ms", "time_min_ms",
                    "time_max_ms", "rmse", "rel_rmse", "ssim", "dssim", "ref_ms"])
        for (mode, samples), es in sorted(errors.items(), key=lambda kv: (kv[0][0], kv[0][1])):
            t = list(times[(mode, samples)].values())
            e = math.sqrt(sum(v * v for v in es.values()) / len(es))
            w.writerow(list(modes[mode]) + [samples, "%.4f" % statistics.median(t),
                                            "%.4f" % min(t), "%.4f" % max(t), "",
                                            "%.6g" % e, "", "", ""])


if __name__ == "__main__":
    main()
