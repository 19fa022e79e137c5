#!/usr/bin/env python3
"""Write a Stribeck sweep with a run-in its plan omits, and the plan, for the picture in
docs/recordings.md ("Sliding, steps, alignment and coverage").

    python3 scripts/example_stribeck_run_in.py OUT_DIR
    greybox identify --plan-steps OUT_DIR/plan.csv --recordings OUT_DIR/stribeck.csv \
        --out OUT_DIR/data.csv --inspect

Standard library only, seeded: the same bytes every run. 7 speed steps, 0.01-1 m/s log
spaced (30 s each, 1 s linear ramps), mu falling from 0.12 to 0.04 at 20 N, after a 40 s
run-in at the 4th step's speed (mu decaying from 0.15 to 0.095) that the plan does not list.
"""
import random
import sys
from pathlib import Path


def main(out: Path) -> None:
    rng = random.Random(44)
    out.mkdir(parents=True, exist_ok=True)
    steps = [(0.01 * 10 ** (2 * k / 6), 0.12 - 0.08 * k / 6) for k in range(7)]
    fs, load = 50.0, 20.0
    run_in_v = steps[3][0]
    pieces = [(2.0, 42.0, run_in_v, run_in_v, None)]
    t, prev = 42.0, run_in_v
    for v, mu in steps:
        pieces.append((t, t + 1.0, prev, v, mu))
        pieces.append((t + 1.0, t + 30.0, v, v, mu))
        prev, t = v, t + 30.0
    t_stop, t_end = t, t + 3.0
    lines = ["Time [s],Load [N],Friction [N],Speed [m/s]"]
    for k in range(int(t_end * fs)):
        t = k / fs
        loaded = 1.0 <= t < t_stop + 1.0
        v, mu = 0.0, 0.0
        for a, b, v0, v1, m in pieces:
            if a <= t < b:
                if m is None:
                    v, mu = v0, 0.095 + 0.055 * 2.718281828459045 ** (-(t - 2.0) / 8.0)
                else:
                    v, mu = v0 + (v1 - v0) * (t - a) / (b - a), m
                break
        fn = (load if loaded else 0.0) + rng.gauss(0, 0.02)
        ft = (mu + rng.gauss(0, 0.004)) * load if loaded and v > 0 else rng.gauss(0, 0.01)
        lines.append("%.3f,%.4f,%.5f,%.6f" % (t, fn, ft, v * (1 + rng.gauss(0, 0.002))))
    (out / "stribeck.csv").write_text("\n".join(lines) + "\n")
    plan = ["pin,step,normal_force_N,sliding_velocity_m_per_min"]
    plan += ["1,%d,%g,%.6g" % (k + 1, load, v * 60) for k, (v, _) in enumerate(steps)]
    (out / "plan.csv").write_text("\n".join(plan) + "\n")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "stribeck-example"))
