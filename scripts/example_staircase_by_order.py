#!/usr/bin/env python3
"""Write a continuous velocity staircase without a speed channel, and a plan of loads and
velocities without durations, for the picture in docs/recordings.md:

    python3 scripts/example_staircase_by_order.py OUT_DIR
    greybox identify --plan-steps OUT_DIR/plan.csv --recordings OUT_DIR/staircase.csv \
        --out OUT_DIR/data.csv --inspect

One pin at 200 N, 200 Hz: 2 s unloaded, the load, then an unplanned 4 s run-in at 30 m/min
(mu decaying from 0.42 to 0.30), then five steps of 0.5 s ramps and 5 s dwells at 20, 30, 45,
68 and 100 m/min (mu 0.36, 0.34, 0.32, 0.30, 0.28), the stop and 2 s unloaded. Nothing but the
order places a segment on a step: every row is flagged label-by-order.
"""
import math
import random
import sys
from pathlib import Path

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)
rng = random.Random(58)
fs, load = 200.0, 200.0
steps = [(20.0, 0.36), (30.0, 0.34), (45.0, 0.32), (68.0, 0.30), (100.0, 0.28)]
t_load, t_run = 2.0, 3.0
t_steps = t_run + 4.0
t_stop = t_steps + 5.5 * len(steps)
t_end = t_stop + 3.0
lines = ["Time [s],Fn [N],Ft [N]"]
for k in range(int(t_end * fs)):
    t = k / fs
    f = load * min(max((t - t_load) / 0.5, 0.0), 1.0) * (1.0 if t < t_stop + 0.5 else 0.0)
    if t_run <= t < t_steps:
        mu = 0.30 + 0.12 * math.exp(-(t - t_run) / 1.0)
    elif t_steps <= t < t_stop:
        i = int((t - t_steps) / 5.5)
        into = t - t_steps - 5.5 * i
        prev = steps[i - 1][1] if i > 0 else 0.30
        mu = prev + (steps[i][1] - prev) * min(into / 0.5, 1.0)
    else:
        mu = 0.0
    ft = mu * f + 0.6 * rng.gauss(0.0, 1.0)
    lines.append("%.4f,%.3f,%.4f" % (t, f + 0.4 * rng.gauss(0.0, 1.0), ft))
(out / "staircase.csv").write_text("\n".join(lines) + "\n")
plan = ["pin,step,normal_force_N,sliding_velocity_m_per_min"]
plan += ["1,%d,%g,%g" % (k + 1, load, v) for k, (v, _) in enumerate(steps)]
(out / "plan.csv").write_text("\n".join(plan) + "\n")
