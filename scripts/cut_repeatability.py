#!/usr/bin/env python3
"""Cut one set-up at nearly equal μ values and check that each cut's stated 95 % intervals
hold the others' means (docs/validation.md, "Cut results with error bars").

A cut at μ and one at μ + 0.001 are the same cut within its scatter: if the intervals say
how sure a cut is, the spread of the means matches the stated standard errors, and two cuts'
means differ by no more than the 95 % interval of a difference, 1.96 √(se_a² + se_b²) (a mean
lies inside another cut's own interval only 83 % of the time even then). The script
runs `greybox simulate cutting` once per μ (top-level `mu` replaced), reads each
`summary.json`, and prints F'c, F'f and the chip ratio with their intervals, whether every
mean lies inside every other cut's interval, the spread of the means against the mean
stated standard error, and the wall time.

    python3 scripts/cut_repeatability.py target/release/greybox validation/ti64-tanh-setup.toml \\
        --mu 0.300 0.301 0.302 --out /tmp/repeat [--cut-length-mm 2.0] [--refine] [--no-stop]

`--cut-length-mm` replaces `cut_length_m`, `--refine` adds the refined suites' region
(20 µm away from the tool when `--coarse-spacing-um 20`), `--no-stop` runs every cut to its
length, `--set KEY=VALUE` replaces or adds a key, `TABLE.KEY` inside a table (D09 of the suite
is the TANH template with `physical_cutting_speed_m_s=0.16667`, 10 m/min run at 600 m/min;
`tool_thermal.thermal_mass_scaling=200` a tool at its steady temperature sooner).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

from setup_toml import set_path

REGION = ('[refinement]\nregions = [{ ahead_m = 0.2e-3, behind_m = 0.02e-3, '
          'below_m = 0.04e-3, above_m = 0.3e-3 }]\n')


def variant(text, mu, args):
    text = set_path(text, 'mu', repr(mu))
    if args.cut_length_mm:
        text = set_path(text, 'cut_length_m', repr(args.cut_length_mm * 1e-3))
    if args.coarse_spacing_um:
        text = set_path(text, 'spacing_m', repr(args.coarse_spacing_um * 1e-6))
    for kv in args.set or []:
        key, _, value = kv.partition('=')
        text = set_path(text, key.strip(), value.strip())
    if args.no_stop:
        text = set_path(text, 'steady.stop_when_sure', 'false')
    if args.refine:
        text += '\n' + REGION
    return text


def quantity(summary, key):
    q = (summary.get('steady_state') or {}).get(key)
    return (q['mean'], q.get('ci95'), q.get('se')) if q else (None, None, None)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('greybox')
    ap.add_argument('config')
    ap.add_argument('--mu', type=float, nargs='+', required=True)
    ap.add_argument('--out', required=True)
    ap.add_argument('--cut-length-mm', type=float)
    ap.add_argument('--coarse-spacing-um', type=float)
    ap.add_argument('--refine', action='store_true')
    ap.add_argument('--no-stop', action='store_true')
    ap.add_argument('--set', action='append', metavar='KEY=VALUE',
                    help='a key of the set-up replaced or added, TABLE.KEY in a table (e.g. '
                         'physical_cutting_speed_m_s=0.16667 for a condition run time-scaled)')
    args = ap.parse_args()
    base = open(args.config, encoding='utf-8').read()
    os.makedirs(args.out, exist_ok=True)
    runs = []
    for mu in args.mu:
        cfg = os.path.join(args.out, f'mu-{mu:.4f}.toml')
        # relative paths of the set-up (law files) stay relative to the original's folder
        with open(cfg, 'w', encoding='utf-8') as f:
            f.write(variant(base, mu, args))
        out = os.path.join(args.out, f'mu-{mu:.4f}')
        t0 = time.time()
        subprocess.run([args.greybox, '-q', 'simulate', 'cutting', '--config', cfg, '--out', out,
                        '--force'], check=True)
        wall = time.time() - t0
        s = json.load(open(os.path.join(out, 'summary.json'), encoding='utf-8'))
        runs.append((mu, s, wall))
    keys = [('cutting_force_n_per_mm', "F'c N/mm"), ('feed_force_n_per_mm', "F'f N/mm"),
            ('compression_ratio', 'h_c/h')]
    print('| μ | ' + ' | '.join(k[1] for k in keys) + ' | steady from – to mm | sure | wall s |')
    print('|---' * (len(keys) + 4) + '|')
    for mu, s, wall in runs:
        st = s.get('steady_state') or {}
        cells = []
        for key, _ in keys:
            m, ci, _ = quantity(s, key)
            cells.append('—' if m is None else (f'{m:.3f}' if ci is None else
                                                f'{m:.3f} ± {ci:.3f} ({100 * ci / abs(m):.1f} %)'))
        print(f'| {mu:.4f} | ' + ' | '.join(cells) +
              f" | {st.get('from_mm', float('nan')):.3f} – {st.get('to_mm', float('nan')):.3f} "
              f"| {s.get('sure')} | {wall:.1f} |")
    ok = True
    for key, name in keys:
        vals = [quantity(s, key) for _, s, _ in runs]
        if any(v[0] is None or v[1] is None for v in vals):
            print(f'{name}: a cut gave no interval')
            continue
        inside = all(abs(a[0] - b[0]) <= b[1] for a in vals for b in vals)
        # two cuts of one condition differ by up to 1.96 √(se_a² + se_b²) at 95 %
        paired = all(abs(a[0] - b[0]) <= 1.96 * (a[2] ** 2 + b[2] ** 2) ** 0.5
                     for a in vals for b in vals)
        ok &= paired
        spread = statistics.stdev(v[0] for v in vals) if len(vals) > 1 else float('nan')
        se = statistics.mean(v[2] for v in vals)
        print(f"{name}: every mean inside every other cut's interval: {inside}; every "
              f"difference inside its 95 % interval 1.96 √(se_a² + se_b²): {paired}; spread of "
              f"the means {spread:.3f} against the mean stated standard error {se:.3f}")
    sys.exit(0 if ok else 1)


if __name__ == '__main__':
    main()
