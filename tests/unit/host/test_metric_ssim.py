#!/usr/bin/env python3
"""host/cli/metric.c's SSIM against an independent one, written here from the paper.

    test_metric_ssim.py TEST_METRIC

Wang, Bovik, Sheikh, Simoncelli, "Image quality assessment: from error visibility to
structural similarity", IEEE TIP 13(4), 2004: equation 13 in every 11x11 window fully inside
the image, the moments weighted by the circular-symmetric Gaussian of sigma 1.5 (normalised
to 1) of section III-B, C1 = (0.01 L)^2, C2 = (0.03 L)^2, the mean over the windows. Here the
2-D window is built as a whole and each window summed directly (metric.c filters along x
then y, in a ring of rows); L and the luminance are metric.h's rules, the windows holding a
non-finite pixel are left out. The images are small and seeded, written as text for
`test_metric ssim_of A B`; the two answers must agree to 1e-6 (they agree to about 1e-15),
the window counts exactly.
"""
import math
import os
import random
import struct
import subprocess
import sys
import tempfile

WIN, SIGMA, K1, K2, MIN_RANGE = 11, 1.5, 0.01, 0.03, 1e-3


def f32(v):
    """v as the float the C side reads (the images are float)."""
    return struct.unpack('f', struct.pack('f', v))[0]


def luminance(p):
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]


def finite(p):
    return all(math.isfinite(c) for c in p)


def ssim(a, b, w, h):
    """(mean SSIM, windows, skipped, L) of image a against the reference b."""
    g = [[math.exp(-((i - 5) ** 2 + (j - 5) ** 2) / (2 * SIGMA ** 2)) for i in range(WIN)]
         for j in range(WIN)]
    total = sum(sum(r) for r in g)
    g = [[v / total for v in r] for r in g]
    lum = [luminance(p) for p in b if finite(p)]
    L = max([MIN_RANGE] + lum)
    c1, c2 = (K1 * L) ** 2, (K2 * L) ** 2
    s, n, skipped = 0.0, 0, 0
    for oy in range(h - WIN + 1):
        for ox in range(w - WIN + 1):
            px = [(x, y) for y in range(oy, oy + WIN) for x in range(ox, ox + WIN)]
            if not all(finite(a[y * w + x]) and finite(b[y * w + x]) for x, y in px):
                skipped += 1
                continue
            ma = mb = 0.0
            for x, y in px:
                wt = g[y - oy][x - ox]
                ma += wt * luminance(a[y * w + x])
                mb += wt * luminance(b[y * w + x])
            va = vb = cov = 0.0
            for x, y in px:
                wt = g[y - oy][x - ox]
                da, db = luminance(a[y * w + x]) - ma, luminance(b[y * w + x]) - mb
                va += wt * da * da
                vb += wt * db * db
                cov += wt * da * db
            s += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2))
            n += 1
    return (s / n if n else float('nan')), n, skipped, L


def write(path, img, w, h):
    with open(path, 'w') as f:
        f.write('%d %d\n' % (w, h))
        for p in img:
            f.write(' '.join(repr(c) for c in p) + '\n')


def cases():
    """(name, A, B, w, h): seeded images, HDR values, a black reference, non-finite pixels."""
    rnd = random.Random(23)

    def image(w, h, fn):
        return [tuple(f32(c) for c in fn(x, y)) for y in range(h) for x in range(w)]

    w, h = 24, 19
    ref = image(w, h, lambda x, y: (0.5 + 0.4 * math.sin(x * 0.7) * math.cos(y * 0.5),
                                    0.3 + 0.02 * x, 0.2 + 0.03 * y))
    noisy = [tuple(f32(c + rnd.gauss(0, 0.1)) for c in p) for p in ref]
    yield 'noise', noisy, ref, w, h
    hdr = image(w, h, lambda x, y: (rnd.uniform(0, 20), rnd.uniform(0, 5), rnd.uniform(0, 1)))
    hdr2 = [tuple(f32(c * rnd.uniform(0.7, 1.3)) for c in p) for p in hdr]
    yield 'hdr', hdr2, hdr, w, h
    yield 'swapped', ref, noisy, w, h
    dark = image(15, 13, lambda x, y: (0.0, 0.0, 0.0))
    faint = image(15, 13, lambda x, y: (1e-4 * ((x + y) % 3), 0.0, 2e-4 * (x % 2)))
    yield 'black_reference', faint, dark, 15, 13
    holes = list(noisy)
    holes[5 * w + 3] = (float('nan'), 0.1, 0.1)
    holes[17 * w + 20] = (0.1, float('inf'), 0.1)
    yield 'nonfinite', holes, ref, w, h
    yield 'square', image(11, 11, lambda x, y: (x * 0.1, y * 0.1, 0.5)), \
        image(11, 11, lambda x, y: (y * 0.1, x * 0.1, 0.5)), 11, 11


def main():
    exe = sys.argv[1]
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        pa, pb = os.path.join(tmp, 'a.txt'), os.path.join(tmp, 'b.txt')
        for name, a, b, w, h in cases():
            write(pa, a, w, h)
            write(pb, b, w, h)
            out = subprocess.run([exe, 'ssim_of', pa, pb], capture_output=True, text=True)
            if out.returncode != 0:
                print('%s: test_metric failed: %s' % (name, out.stderr), file=sys.stderr)
                failures += 1
                continue
            f = out.stdout.split()
            got = (float(f[1]), int(f[3]), int(f[5]), float(f[7]))
            want = ssim(a, b, w, h)
            ok = (abs(got[0] - want[0]) <= 1e-6 and got[1:3] == want[1:3]
                  and abs(got[3] - want[3]) <= 1e-12 * want[3])
            print('%-16s C %.12f  Python %.12f  |diff| %.2g  windows %d skipped %d  L %.6g  %s'
                  % (name, got[0], want[0], abs(got[0] - want[0]), got[1], got[2], got[3],
                     'ok' if ok else 'DIFFERENT'))
            if not ok:
                print('%s: C gives %r, Python %r' % (name, got, want), file=sys.stderr)
                failures += 1
    if failures:
        print('test_metric_ssim: %d case(s) differ' % failures, file=sys.stderr)
        return 1
    print('test_metric_ssim: every case agrees to 1e-6')
    return 0


if __name__ == '__main__':
    sys.exit(main())
