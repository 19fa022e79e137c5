#!/usr/bin/env python3
"""Where a cut's feed force wanders: block means of the contact forces per tool face against
the block means of F'f (docs/validation.md, "Cut results with error bars").

A cut's output directory holds `forces.csv` (the tool's force per unit width every few
steps) and `mu_history.csv` (every friction window's normal and shear stress at each
update, with its face: rake, edge, flank). This script sums each face's windows into a
normal and a tangential line load (stress × window length, N/mm), drops the warm-up (the
first `--skip` fraction of the updates), forms `--blocks` consecutive block means of each
and of |F'f| and |F'c| at the same instants, and prints them with the correlation of each
face's block means with F'f's: a face whose load follows F'f's slow wander is where the wander
lives. Two rows describe where the chip bears on the rake: the centroid of the rake's normal
load and the rake contact's extent (the farthest rake window in contact for more than
`--in-contact` of its length), both in µm from the cutting edge.

    python3 scripts/ff_by_face.py CUT_DIR [--blocks 8] [--skip 0.2] [--window-um 10] \
        [--in-contact 0.05]
"""
import argparse
import collections
import csv
import os

import numpy as np

FACES = ('rake', 'edge', 'flank')


def face_loads(path, window_um, in_contact):
    """Per update step: time, each face's normal and tangential line load, N/mm, and the rake
    load's centroid and the rake contact's extent, µm from the edge."""
    loads = collections.defaultdict(lambda: collections.defaultdict(float))
    rake = collections.defaultdict(list)
    time = {}
    with open(path, newline='') as f:
        for r in csv.DictReader(f):
            step = int(r['step'])
            time[step] = float(r['time_s'])
            scale = window_um * 1e-3  # MPa × mm = N/mm
            normal = float(r['normal_stress_MPa']) * scale
            loads[step][r['face'] + ' normal'] += normal
            loads[step][r['face'] + ' tangential'] += float(r['shear_stress_MPa']) * scale
            if r['face'] == 'rake':
                rake[step].append((float(r['distance_from_edge_um']), normal,
                                   float(r['contact_fraction'])))
    for step, windows in rake.items():
        total = sum(n for _, n, _ in windows)
        loads[step]['rake centroid um'] = (sum(s * n for s, n, _ in windows) / total
                                           if total > 0 else float('nan'))
        loads[step]['rake extent um'] = max((s for s, _, c in windows if c > in_contact),
                                            default=float('nan'))
    steps = sorted(loads)
    keys = [f'{face} {part}' for face in FACES for part in ('normal', 'tangential')]
    keys += ['rake centroid um', 'rake extent um']
    table = np.array([[loads[s].get(k, float('nan')) for k in keys] for s in steps])
    return np.array([time[s] for s in steps]), keys, table


def forces_at(path, times):
    """|F'c| and |F'f|, N/mm, at the recorded instant nearest after each of `times`."""
    with open(path, newline='') as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r['time_s']) for r in rows])
    fc = np.abs([float(r['force_x_N_per_mm']) for r in rows])
    ff = np.abs([float(r['force_y_N_per_mm']) for r in rows])
    i = np.searchsorted(t, times).clip(0, len(t) - 1)
    return fc[i], ff[i]


def block_means(values, blocks):
    n = len(values) // blocks
    return np.array([np.nanmean(values[k * n:(k + 1) * n], axis=0) for k in range(blocks)])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('cut_dir')
    ap.add_argument('--blocks', type=int, default=8)
    ap.add_argument('--skip', type=float, default=0.2, help='warm-up fraction of the updates')
    ap.add_argument('--window-um', type=float, default=10.0, help='friction window length, µm')
    ap.add_argument('--in-contact', type=float, default=0.05,
                    help='contact share above which a rake window counts as in contact')
    a = ap.parse_args()
    times, keys, table = face_loads(os.path.join(a.cut_dir, 'mu_history.csv'), a.window_um,
                                    a.in_contact)
    fc, ff = forces_at(os.path.join(a.cut_dir, 'forces.csv'), times)
    start = int(len(times) * a.skip)
    if len(times) - start < 2 * a.blocks:
        raise SystemExit(f'{a.cut_dir}: {len(times) - start} updates after the warm-up; '
                         f'too few for {a.blocks} blocks')
    b_ff = block_means(ff[start:], a.blocks)
    b_fc = block_means(fc[start:], a.blocks)
    b_faces = block_means(table[start:], a.blocks)
    print(f"F'f block means, N/mm: {np.round(b_ff, 1).tolist()}  (sd {b_ff.std(ddof=1):.2f})")
    print(f"F'c block means, N/mm: {np.round(b_fc, 1).tolist()}  (sd {b_fc.std(ddof=1):.2f})")
    print(f"{'face load':<18} {'block means, N/mm (rake rows: µm)':<52} {'sd':>5} {'corr F_f':>8}")
    for j, key in enumerate(keys):
        col = b_faces[:, j]
        corr = np.corrcoef(b_ff, col)[0, 1] if col.std() > 0 else float('nan')
        print(f'{key:<18} {str(np.round(col, 1).tolist()):<52} {col.std(ddof=1):5.2f} {corr:8.2f}')


if __name__ == '__main__':
    main()
