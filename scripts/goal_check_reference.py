#!/usr/bin/env python3
"""An independent reading of a validation suite's goal checks (standard library only).

From a suite run's `results.csv` and the measured data it was run on, per friction model:
the held-out mean |error| of F'c, F'f and the chip ratio, with the 95 % interval of both the
cuts' scatter (each simulated value's stated interval, a value without one given the median
of the others') and the measured means' scatter (the dispersion over its number of standard
deviations and the square root of the repeats, carried into the error as (s/m) se_m/m), and
the verdict against each goal: met when the interval lies at or below it, not met when it
lies above, otherwise cannot tell. Then how each signed error moves with the cutting speed:
the least-squares line of the signed error against ln v_c over the held-out conditions, its
slope per doubling of v_c with the slope's 95 % t-interval (n − 2 degrees of freedom, the
t quantile found here by integrating Student's density), and whether the interval lies on
one side of zero.

    python3 scripts/goal_check_reference.py out/results.csv validation/orthogonal-cutting.csv \
        --goals 15 30 8
"""
import argparse
import csv
import math
import statistics


def measured_rows(path):
    with open(path, newline="") as f:
        lines = [l for l in f if not l.startswith("#")]
    return {r["id"]: r for r in csv.DictReader(lines)}


def number(text):
    return float(text) if text not in ("", None) else None


def t_quantile(p, dof):
    """Student's t quantile by bisection on its CDF (the density integrated by Simpson's rule)."""
    c = math.exp(math.lgamma((dof + 1) / 2) - math.lgamma(dof / 2)) / math.sqrt(dof * math.pi)

    def cdf(x):
        steps = 4000
        h = x / steps
        f = lambda t: c * (1 + t * t / dof) ** (-(dof + 1) / 2)
        total = f(0) + f(x) + sum((4 if i % 2 else 2) * f(i * h) for i in range(1, steps))
        return 0.5 + total * h / 3

    lo, hi = 0.0, 100.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if cdf(mid) < p else (lo, mid)
    return 0.5 * (lo + hi)


def speed_trend(points):
    """(per doubling, half-width) of the signed error against ln v, or None."""
    n = len(points)
    if n < 3 or len({v for v, _ in points}) < 2:
        return None
    xs = [math.log(v) for v, _ in points]
    es = [e for _, e in points]
    slope, intercept = statistics.linear_regression(xs, es)
    sxx = sum((x - statistics.fmean(xs)) ** 2 for x in xs)
    ss = sum((e - intercept - slope * x) ** 2 for x, e in zip(xs, es))
    half = t_quantile(0.975, n - 2) * math.sqrt(ss / (n - 2) / sxx)
    return slope * math.log(2), half * math.log(2)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("results")
    p.add_argument("data")
    p.add_argument("--goals", nargs=3, type=float, default=[15.0, 30.0, 8.0],
                   metavar=("FC", "FF", "CHIP"), help="goals in %% (F'c, F'f, chip ratio)")
    a = p.parse_args()
    data = measured_rows(a.data)
    with open(a.results, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["role"] == "held-out"]
    measures = [
        ("F'c", "cutting_force", "N_per_mm", "cutting_force_dispersion_N_per_mm"),
        ("F'f", "feed_force", "N_per_mm", "feed_force_dispersion_N_per_mm"),
        ("chip ratio", "chip_ratio", None, "chip_ratio_dispersion"),
    ]
    for model in dict.fromkeys((r["material"], r["tool"], r["friction"]) for r in rows):
        group = [r for r in rows if (r["material"], r["tool"], r["friction"]) == model]
        print(" / ".join(model))
        for (name, key, unit, disp), goal in zip(measures, a.goals):
            suffix = f"_{unit}" if unit else ""
            used = [r for r in group if number(r[f"simulated_{key}{suffix}"]) is not None
                    and number(r[f"measured_{key}{suffix}"]) is not None]
            n = len(used)
            errors, cut_se, meas_var = [], [], 0.0
            for r in used:
                s, m = number(r[f"simulated_{key}{suffix}"]), number(r[f"measured_{key}{suffix}"])
                errors.append(abs(s / m - 1.0))
                ci = number(r[f"simulated_{key}_ci95{suffix}"])
                cut_se.append(None if ci is None else ci / 1.96 / m)
                d = data[r["id"]]
                k, reps = number(d.get("dispersion_sigmas")), number(d.get("repeats"))
                dv = number(d.get(disp))
                if k and reps and dv is not None:
                    meas_var += (s / m * dv / (k * math.sqrt(reps)) / m) ** 2
            known = [e for e in cut_se if e is not None]
            med = statistics.median(known)
            cut_var = sum((e if e is not None else med) ** 2 for e in cut_se)
            mean = sum(errors) / n
            half = 1.96 * math.sqrt(cut_var + meas_var) / n
            g = goal / 100.0
            verdict = "met" if mean + half <= g else "not met" if mean - half > g else "cannot tell"
            print(f"  {name}: {100 * mean:.2f} ± {100 * half:.2f} % (cuts ± {100 * 1.96 * math.sqrt(cut_var) / n:.2f},"
                  f" measurements ± {100 * 1.96 * math.sqrt(meas_var) / n:.2f}) against ≤ {goal:g} %: {verdict}")
            trend = speed_trend([(number(r["cutting_speed_m_per_min"]),
                                  number(r[f"simulated_{key}{suffix}"]) / number(r[f"measured_{key}{suffix}"]) - 1.0)
                                 for r in used])
            if trend:
                slope, half = trend
                reading = ("rises with speed" if slope - half > 0 else
                           "falls with speed" if slope + half < 0 else "no trend resolved")
                print(f"    signed error {100 * slope:+.2f} ± {100 * half:.2f} points per doubling of v_c: {reading}")


if __name__ == "__main__":
    main()
