#!/usr/bin/env python3
"""An independent check of a cut's steady forces and their drift (docs/validation.md, "Cut
results with error bars"): numpy and scipy on the cut's `forces.csv`, none of greybox's code.

Over the stretch FROM_MM–TO_MM of cut (the `steady_state` `from_mm`/`to_mm` of the cut's
`summary.json` when not given), the force bins are cut into ten batches; the script prints
per force the mean with the 95 % batch-means interval (t with 9 degrees of freedom) and the
change across the stretch along the batch means' least-squares line with its 95 % interval
(t with 8), the change being significant where it exceeds its interval.

    python3 scripts/force_drift.py CUT_DIR [FROM_MM TO_MM]
"""
import csv
import json
import os
import sys

import numpy as np
from scipy import stats

BATCHES = 10


def main():
    cut = sys.argv[1]
    if len(sys.argv) >= 4:
        a, b = float(sys.argv[2]), float(sys.argv[3])
    else:
        st = json.load(open(os.path.join(cut, 'summary.json'), encoding='utf-8'))['steady_state']
        a, b = st['from_mm'], st['to_mm']
    rows = list(csv.reader(open(os.path.join(cut, 'forces.csv'), encoding='utf-8')))[1:]
    x0 = float(rows[0][1])
    x = np.array([x0 - float(r[1]) for r in rows])  # mm of cut
    sel = (x >= a) & (x <= b)
    for name, col in (("F'c", 3), ("F'f", 4)):
        f = np.array([float(r[col]) for r in rows])[sel]
        xs = x[sel]
        n = len(f) // BATCHES
        means = np.array([f[i * n:(i + 1) * n].mean() for i in range(BATCHES)])
        centres = np.array([xs[i * n:(i + 1) * n].mean() for i in range(BATCHES)])
        half = stats.t.ppf(0.975, BATCHES - 1) * means.std(ddof=1) / np.sqrt(BATCHES)
        line = stats.linregress(centres, means)
        span = centres[-1] - centres[0] + (centres[1] - centres[0])
        change = line.slope * span
        change_half = stats.t.ppf(0.975, BATCHES - 2) * line.stderr * span
        print(f'{name}: {means.mean():.2f} ± {half:.2f} N/mm ({100 * half / means.mean():.1f} %) over '
              f'{a:.3f}–{b:.3f} mm; change across it {change:+.2f} ± {change_half:.2f} N/mm '
              f'({"significant" if abs(change) > change_half else "not significant"})')


if __name__ == '__main__':
    main()
