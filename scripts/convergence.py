#!/usr/bin/env python3
"""Spacing convergence of the cutting solver (docs/validation.md): one case per material at
three uniform particle spacings and with dynamic refinement (a coarse spacing away from the
tool, half of it in a region that follows the cutting edge); prints forces, chip ratio,
contact length, temperatures and cost per spacing as a Markdown table.

    python3 scripts/convergence.py [--greybox target/release/greybox] [--out convergence-out]

Cases: the article's AISI 1045 cut (examples/aisi1045-cut.toml, run to a steady force) and the
Ti6Al4V validation condition D09 (validation/ti64-setup.toml: 10 m/min time-scaled, h = 60 µm,
thermal tool, the μ the validation calibrated). The windows follow the finest spacing.
A spacing written (coarse, "refined") is refined once: REGION below, as in
validation/suite-refined-fast.toml.
"""
import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

CASES = [
    (
        "AISI 1045, 150 m/min, h 0.1 mm (article)",
        "examples/aisi1045-cut.toml",
        {},
        [20e-6, 14e-6, 10e-6, (20e-6, "refined")],
    ),
    (
        "Ti6Al4V D09, 10 m/min, h 0.06 mm, thermal tool",
        "validation/ti64-setup.toml",
        {"physical_cutting_speed_m_s": 10 / 60, "mu": None},
        [10e-6, 7.5e-6, 5e-6, (20e-6, "refined"), (10e-6, "refined")],
    ),
]

# The refinement region (frame of the cutting edge), m.
REGION = "{ ahead_m = 0.2e-3, behind_m = 0.02e-3, below_m = 0.04e-3, above_m = 0.3e-3 }"


def with_values(text, values):
    """Sets top-level keys (before the first table) in a TOML text."""
    head, sep, rest = text.partition("\n[")
    for k, v in values.items():
        line = f"{k} = {v!r}"
        if re.search(rf"^{k}\s*=", head, flags=re.M):
            head = re.sub(rf"^{k}\s*=.*$", line, head, flags=re.M)
        else:
            head += "\n" + line
    return head + sep + rest


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--greybox", default="target/release/greybox")
    ap.add_argument("--out", default="convergence-out")
    ap.add_argument("--mu-ti", type=float, required=True, help="the μ the validation calibrated (thermal tool)")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(exist_ok=True)
    print(
        "| case | spacing µm | particles across h | particles at the end | F'c N/mm | F'f N/mm | h_c/h "
        "| contact mm | T peak °C | T_max at the end °C | wall s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, path, extra, spacings in CASES:
        base = Path(path).read_text()
        for spacing in spacings:
            refined = isinstance(spacing, tuple)
            dx = spacing[0] if refined else spacing
            fine = dx / 2 if refined else dx
            values = {k: (a.mu_ti if v is None else v) for k, v in extra.items()}
            values["spacing_m"] = dx
            text = with_values(base, values)
            text = re.sub(r"^window_length_m\s*=.*$", f"window_length_m = {fine!r}", text, flags=re.M)
            if refined:
                text += f"\n[refinement]\nregions = [{REGION}]\n"
            label = f"{dx * 1e6:g}" + (f" → {fine * 1e6:g} refined" if refined else "")
            cfg = out / (f"{Path(path).stem}-{dx * 1e6:g}um" + ("-refined" if refined else "") + ".toml")
            cfg.write_text(text)
            run = out / cfg.stem
            r = subprocess.run(
                [a.greybox, "simulate", "cutting", "--config", str(cfg), "--out", str(run), "--force", "--json", "-q"],
                capture_output=True, text=True,
            )
            if r.returncode != 0:
                sys.exit(f"{cfg}: {r.stderr}")
            s = json.loads(r.stdout)
            h = float(re.search(r"^uncut_chip_thickness_m\s*=\s*([^\s#]+)", text, flags=re.M).group(1))
            print(
                f"| {name} | {label} | {h / fine:.0f} | {s['particles']} | {s['cutting_force_n_per_mm']:.1f} | "
                f"{s['feed_force_n_per_mm']:.1f} | {s['compression_ratio'] or float('nan'):.3f} "
                f"| {s['contact_length_mm'] or float('nan'):.3f} | {s['peak_temperature_c']:.0f} "
                f"| {s['max_temperature_c']:.0f} | {s['wall_s']:.0f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
