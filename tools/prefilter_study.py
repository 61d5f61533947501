#!/usr/bin/env python3
"""The prefilter study (docs/probes.md "Glossy prefiltering"): runs lg_prefilter_study,
which writes docs/images/prefilter_study.csv and prints the tables, then gnuplot
(tools/prefilter_study.gp) for docs/images/prefilter_study.png.

    make study-prefilter          or   tools/prefilter_study.py --build build [-- ARGS]

ARGS go to lg_prefilter_study (--face, --levels, --threads, --max-samples ...).
"""
import argparse
import os
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--build', default='build')
    ap.add_argument('--source', default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument('rest', nargs='*')
    a = ap.parse_args()
    images = os.path.join(a.source, 'docs', 'images')
    os.makedirs(images, exist_ok=True)
    csv = os.path.join(images, 'prefilter_study.csv')
    png = os.path.join(images, 'prefilter_study.png')
    exe = os.path.join(a.build, 'tools', 'lg_prefilter_study')
    cmd = [exe, '--probe', os.path.join(a.source, 'assets', 'probes', 'forest_1024x512.hdr'),
           '--csv', csv] + a.rest
    print('$ ' + ' '.join(cmd), flush=True)
    r = subprocess.run(cmd)
    if r.returncode:
        sys.exit(r.returncode)
    gp = os.path.join(a.source, 'tools', 'prefilter_study.gp')
    r = subprocess.run(['gnuplot', '-e', "csv='%s'; png='%s'" % (csv, png), gp])
    if r.returncode:
        sys.exit(r.returncode)
    print('wrote %s and %s' % (csv, png))


if __name__ == '__main__':
    main()
