#!/usr/bin/env python3
"""What sets the chip's speed dependence: one set-up cut at a slow and at fast measured
conditions, each variant changing one thing (docs/validation.md, "The chip's speed
dependence: ablations").

Every cut is the validation suite's cut of a condition of `orthogonal-cutting.csv` (the
template with the condition's speed, uncut chip thickness, rake, clearance and edge radius;
run at the template's `cutting_speed_m_s` and scaled back to the physical speed), refined
20 → 10 µm as `validation/suite-refined-fast.toml` (`--coarse-spacing-um 10`: 10 → 5 µm), at a
fixed μ, run to its full length.
The variants:

* `baseline` — as the suite cuts it (time scaling: strain rate ÷ s, conductivity × s);
* `mass-scaled` — no time scaling: cut at the physical speed, the mass scaled by s² more
  instead (the same steps, inertia and wave-to-cut speed ratio; strain rate and conduction
  physical without scaling);
* `no-conduction` — the workpiece's conductivity 10⁻³ W/(m·K) (adiabatic);
* `adiabatic-tool` — no tool temperature field (`[tool_thermal]` removed);
* `steady-tool` — the tool's thermal mass ÷ max(1, 200/s) (`thermal_mass_scaling`; the time
  scaling already speeds its conduction by s): the tool settles 200 times sooner than in an
  unscaled 600 m/min cut, at its steady field within the first tenths of a mm of cut;
* `heat-to-chip`, `heat-to-tool` — the friction heat's share into the workpiece 1 or 0;
* `no-rate` — the flow stress without its strain-rate term (C = 0);
* `no-softening` — without thermal softening (m = 50: (T*)^m ≈ 0 below the melt);
* `m=X` — the thermal-softening exponent m set to X (the template's Sima–Özel set has 1;
  published Ti6Al4V J-C sets range from about 0.7 to 1.1);
* `tanh-s=X` — the TANH strain softening's exponent s set to X (Sima & Özel's model 3 has
  0.05, which keeps tanh(·)^s near 1 and the softening weak; Calamaz et al.'s model is s = 1);
* `chip-break=X` — the chip breaks off X mm above the uncut surface (`chip_break_height_m`:
  the chip's far part leaves the model instead of acting back on the contact);
* `mu-half`, `mu-1.5x` — μ × 0.5, × 1.5;
* `damage`, `damage-gf=X` — Johnson–Cook damage with Lesuer's Ti6Al4V constants and
  Hillerborg softening (`[material.damage]`, greybox_material::damage), the fracture energy
  43.6 kJ/m² (plane-strain K_IC = 75 MPa√m) or X kJ/m²;
* `shear-limit`, `shear-limit=X` — Coulomb friction capped by a limiting shear stress
  (`[friction] shear_limit_pa`): the flow stress's A/√3, or X MPa;
* `source-mu`, `source-mu-shear-limit` — the measurements' source's own friction: μ by
  cutting speed from its Table (Ducobu, Pantalé & Lauwers, `Article.tex` of
  `pantale/CIRP-2022-paper`, after Rech et al. 2013: 0.24 at 5 m/min falling to 0.17 at
  40 m/min, linear between its speeds), without and with the limiting shear stress A/√3 it
  uses (its heat partition β is not carried over: the thermal tool takes its share by
  conduction here);
* `seo-jc`, `source-model` — the source's Ti6Al4V: the flow stress and thermal constants of
  `validation/ti64-seo-setup.toml` (Seo et al.'s J-C set, 2005: A 997.9 MPa, B 653.1 MPa,
  n 0.45, C 0.0198, m 0.7, T_room 293 K, T_m 1873 K; λ 6.3 W/(m·K), c_p 531 J/(kg·K)) at the
  given μ; `source-model` with the source's friction as well (μ by
  speed and τ_max = A/√3 = 576 MPa): the source's FE model in greybox's 2D cut;
* `seo-jc+KEY=X` (`+` repeated for several) — `seo-jc` with one flow-stress constant set to X
  (`seo-jc+m=1.0`), and `seo-jc+template-thermal` with the template's own λ and c_p: which of
  the source's constants gives the speed dependence;
* `jc-of-tanh` — the TANH law without its TANH terms: plain J-C with the template's own A, B,
  n, C, m (no hardening damping exp(−ε^a), no tanh softening);
* `VARIANT@PATH=VALUE` (`@` repeated for several) — any variant above with set-up keys set
  afterwards, `PATH` a dotted key of the set-up and `VALUE` a TOML value as written
  (`seo-jc@numerics.av_alpha=0.5@numerics.xsph=0.0`: the SPH numerics under another flow
  stress).

    python3 scripts/chip_ablation.py GREYBOX validation/ti64-tanh-setup.toml \\
        --data validation/orthogonal-cutting.csv --conditions D07 D12 D17 --mu 0.396 \\
        --out /tmp/ablation [--variants baseline mass-scaled …] [--cut-length-mm 1.2] [--jobs 2] \\
        [--coarse-spacing-um 20]

Prints a table per condition (F'c, F'f, h_c/h by continuity and the chip's extent over h, with
their 95 % intervals, serrated share, segment pitch, peak rake temperature) beside the
measured values, and per variant the chip ratio's change from the slowest to the fastest
condition against the measured one.
Relative paths in the template stay relative to its folder (the variants are written
beside the outputs with absolute paths where needed).
"""
import argparse
import concurrent.futures
import csv
import json
import os
import subprocess
import time

from setup_toml import get_key, join, remove_section, sections, set_key, set_path

REFINEMENT = ('[refinement]\nregions = [{ ahead_m = 0.2e-3, behind_m = 0.02e-3, '
              'below_m = 0.04e-3, above_m = 0.3e-3 }]\n')


def condition_rows(path):
    with open(path, newline='', encoding='utf-8') as f:
        lines = [line for line in f if not line.startswith('#')]
    return {r['id']: r for r in csv.DictReader(lines)}


def variant_text(template, cond, mu, variant, cut_length_m, coarse_spacing_m):
    """The set-up of one cut: `variant`'s base (module doc), then its `@PATH=VALUE` keys."""
    base, *overrides = variant.split('@')
    text = base_variant_text(template, cond, mu, base, cut_length_m, coarse_spacing_m)
    for override in overrides:
        path, sep, value = override.partition('=')
        if not sep or not path or not value:
            raise SystemExit(f'{variant}: expected @PATH=VALUE, found @{override}')
        text = set_path(text, path, value)
    return text


def base_variant_text(template, cond, mu, variant, cut_length_m, coarse_spacing_m):
    parts = sections(template)
    run_speed = float(get_key(parts, '', 'cutting_speed_m_s'))
    speed = float(cond['cutting_speed_m_per_min']) / 60.0
    s = run_speed / speed
    set_key(parts, '', 'uncut_chip_thickness_m', repr(float(cond['uncut_chip_thickness_mm']) * 1e-3))
    set_key(parts, '', 'cut_length_m', repr(cut_length_m))
    set_key(parts, '', 'spacing_m', repr(coarse_spacing_m))
    set_key(parts, '', 'mu', repr(mu))
    set_key(parts, 'insert', 'rake_deg', cond['rake_deg'])
    set_key(parts, 'insert', 'clearance_deg', cond['clearance_deg'])
    set_key(parts, 'insert', 'edge_radius_m', repr(float(cond['edge_radius_um']) * 1e-6))
    set_key(parts, 'steady', 'stop_when_sure', 'false')
    if variant == 'mass-scaled':
        set_key(parts, '', 'cutting_speed_m_s', repr(speed))
        mass = float(get_key(parts, 'numerics', 'mass_scaling'))
        set_key(parts, 'numerics', 'mass_scaling', repr(mass * s * s))
    else:
        set_key(parts, '', 'physical_cutting_speed_m_s', repr(speed))
    if variant == 'no-conduction':
        set_key(parts, 'material.thermal', 'conductivity', '{ x = [0.0], y = [1.0e-3] }')
    elif variant == 'adiabatic-tool':
        parts = remove_section(parts, 'tool_thermal')
    elif variant == 'steady-tool':
        # the time scaling already speeds the tool's conduction by s: ρc ÷ (200/s) makes the
        # tool settle 200 times sooner than an unscaled 600 m/min cut at every condition
        set_key(parts, 'tool_thermal', 'thermal_mass_scaling', repr(max(1.0, 200.0 / s)))
    elif variant == 'heat-to-chip':
        set_key(parts, 'numerics', 'friction_heat_share', '1.0')
    elif variant == 'heat-to-tool':
        set_key(parts, 'numerics', 'friction_heat_share', '0.0')
    elif variant == 'no-rate':
        set_key(parts, 'material.plasticity', 'c', '0.0')
    elif variant == 'no-softening':
        set_key(parts, 'material.plasticity', 'm', '50.0')
    elif variant.startswith('m='):
        set_key(parts, 'material.plasticity', 'm', repr(float(variant.split('=')[1])))
    elif variant.startswith('tanh-s='):
        set_key(parts, 'material.plasticity', 'tanh_s', repr(float(variant.split('=')[1])))
    elif variant.startswith('chip-break='):
        set_key(parts, '', 'chip_break_height_m', repr(float(variant.split('=')[1]) * 1e-3))
    elif variant == 'mu-half':
        set_key(parts, '', 'mu', repr(mu * 0.5))
    elif variant == 'mu-1.5x':
        set_key(parts, '', 'mu', repr(mu * 1.5))
    elif variant == 'damage' or variant.startswith('damage-gf='):
        gf = float(variant.split('=')[1]) * 1e3 if '=' in variant else LESUER_FRACTURE_ENERGY
        parts.append(('material.damage', damage_lines(parts, gf)))
    elif variant == 'jc-of-tanh':
        for header, lines in parts:
            if header == 'material.plasticity':
                lines[:] = [line for line in lines if not line.startswith('tanh_')]
        set_key(parts, 'material.plasticity', 'model', '"johnson_cook"')
    elif variant.startswith('seo-jc+'):
        thermal = dict(parts)['material.thermal'][:]
        parts = source_material(parts)
        for change in variant.split('+')[1:]:
            if change == 'template-thermal':
                parts = remove_section(parts, 'material.thermal')
                parts.append(('material.thermal', thermal))
            else:
                key, value = change.split('=')
                set_key(parts, 'material.plasticity', key, repr(float(value)))
    elif variant in ('seo-jc', 'source-model'):
        parts = source_material(parts)
        if variant == 'source-model':
            friction_variant(parts, 'source-mu-shear-limit', speed * 60.0)
    elif variant.startswith('shear-limit') or variant.startswith('source-mu'):
        friction_variant(parts, variant, speed * 60.0)
    elif variant not in ('baseline', 'mass-scaled'):
        raise SystemExit(f'unknown variant {variant}')
    return join(parts) + '\n' + REFINEMENT


# μ by cutting speed (m/min) of the measurements' source (Ducobu, Pantalé & Lauwers,
# pantale/CIRP-2022-paper, Article.tex, table "Friction and heat transfer coefficients").
SOURCE_MU = [(5.0, 0.24), (7.5, 0.22), (10.0, 0.21), (20.0, 0.19), (30.0, 0.18), (40.0, 0.17)]


def source_mu(speed_m_per_min):
    """The source's μ at a speed, linear between its speeds (its end values outside)."""
    pts = SOURCE_MU
    if speed_m_per_min <= pts[0][0]:
        return pts[0][1]
    for (v0, m0), (v1, m1) in zip(pts, pts[1:]):
        if speed_m_per_min <= v1:
            return m0 + (m1 - m0) * (speed_m_per_min - v0) / (v1 - v0)
    return pts[-1][1]


def friction_variant(parts, variant, speed_m_per_min):
    """`shear-limit[=MPa]`, `source-mu`, `source-mu-shear-limit` (module doc)."""
    if variant.startswith('source-mu'):
        set_key(parts, '', 'mu', repr(source_mu(speed_m_per_min)))
    if variant.startswith('shear-limit='):
        tau = float(variant.split('=')[1]) * 1e6
    elif variant in ('shear-limit', 'source-mu-shear-limit'):
        tau = float(get_key(parts, 'material.plasticity', 'a_pa')) / 3 ** 0.5
    elif variant == 'source-mu':
        return
    else:
        raise SystemExit(f'unknown variant {variant}')
    parts.append(('friction', [f'shear_limit_pa = {tau!r}']))


# The source's flow stress and thermal constants, as the Seo template states them.
SOURCE_TEMPLATE = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'validation',
                               'ti64-seo-setup.toml')


def source_material(parts):
    """The template's `[material.plasticity]` and `[material.thermal]` replaced by those of
    validation/ti64-seo-setup.toml (module doc: `seo-jc`)."""
    with open(SOURCE_TEMPLATE) as f:
        source = dict(sections(f.read()))
    for name in ('material.plasticity', 'material.thermal'):
        parts = remove_section(parts, name)
        parts.append((name, source[name]))
    return parts


# Plane-strain fracture energy K_IC² (1 − ν²)/E of Ti6Al4V, J/m²: K_IC = 75 MPa√m,
# E = 113.8 GPa, ν = 0.342 (greybox_material::damage::JohnsonCookDamage::ti6al4v_lesuer).
LESUER_FRACTURE_ENERGY = 75e6 ** 2 * (1 - 0.342 ** 2) / 113.8e9


def damage_lines(parts, fracture_energy):
    """Lesuer's Johnson–Cook damage constants for Ti6Al4V (LLNL UCRL-ID-134691, 2000) with
    the flow stress's room and melting temperatures."""
    room = get_key(parts, 'material.plasticity', 'room_temperature_k')
    melt = get_key(parts, 'material.plasticity', 'melt_temperature_k')
    return ['d1 = -0.09', 'd2 = 0.25', 'd3 = -0.5', 'd4 = 0.014', 'd5 = 3.87',
            'ref_strain_rate = 1.0', f'room_temperature_k = {room}',
            f'melt_temperature_k = {melt}', f'fracture_energy_j_m2 = {fracture_energy!r}', '']


VARIANTS = ['baseline', 'mass-scaled', 'no-conduction', 'adiabatic-tool', 'steady-tool', 'heat-to-chip',
            'heat-to-tool', 'no-rate', 'no-softening', 'mu-half', 'mu-1.5x']


def run(greybox, cfg, out):
    t0 = time.time()
    r = subprocess.run([greybox, '-q', 'simulate', 'cutting', '--config', cfg, '--out', out,
                        '--force'], capture_output=True, text=True,
                       env={**os.environ, 'RAYON_NUM_THREADS': '1'})
    wall = time.time() - t0
    if r.returncode != 0:
        return None, wall, r.stderr.strip().splitlines()[-1] if r.stderr.strip() else 'failed'
    with open(os.path.join(out, 'summary.json'), encoding='utf-8') as f:
        return json.load(f), wall, None


def cell(summary, key, digits):
    q = (summary.get('steady_state') or {}).get(key)
    if not isinstance(q, dict) or q.get('mean') is None:
        return '—'
    ci = q.get('ci95')
    return f"{q['mean']:.{digits}f}" + ('' if ci is None else f" ± {ci:.{digits}f}")


def mean_of(summary, key):
    q = (summary.get('steady_state') or {}).get(key) if summary else None
    return q.get('mean') if isinstance(q, dict) else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('greybox')
    ap.add_argument('template')
    ap.add_argument('--data', required=True)
    ap.add_argument('--conditions', nargs='+', required=True)
    ap.add_argument('--mu', type=float, required=True)
    ap.add_argument('--out', required=True)
    ap.add_argument('--variants', nargs='+', default=VARIANTS)
    ap.add_argument('--cut-length-mm', type=float, default=1.2)
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--coarse-spacing-um', type=float, default=20.0,
                    help='the spacing away from the tool; the refined region has half of it')
    a = ap.parse_args()
    template = open(a.template, encoding='utf-8').read()
    rows = condition_rows(a.data)
    os.makedirs(a.out, exist_ok=True)
    jobs = {}
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for c in a.conditions:
            for v in a.variants:
                cfg = os.path.join(a.out, f'{c}-{v}.toml')
                with open(cfg, 'w', encoding='utf-8') as f:
                    f.write(variant_text(template, rows[c], a.mu, v, a.cut_length_mm * 1e-3,
                                         a.coarse_spacing_um * 1e-6))
                jobs[(c, v)] = pool.submit(run, a.greybox, cfg, os.path.join(a.out, f'{c}-{v}'))
        results = {k: f.result() for k, f in jobs.items()}
    for c in a.conditions:
        r = rows[c]
        print(f"\n{c}: {r['cutting_speed_m_per_min']} m/min, h = {r['uncut_chip_thickness_mm']} mm; "
              f"measured F'c {r['cutting_force_N_per_mm']}, F'f {r['feed_force_N_per_mm']} N/mm, "
              f"h_c/h {r['chip_ratio']}")
        print("| variant | F'c N/mm | F'f N/mm | h_c/h | extent/h | serrated share | segment pitch mm | "
              "rake peak °C | wall s |")
        print('|---' * 9 + '|')
        for v in a.variants:
            s, wall, err = results[(c, v)]
            if s is None:
                print(f'| {v} | failed: {err} ||||||| {wall:.0f} |')
                continue
            ss = s.get('steady_state') or {}
            share = ss.get('serrated_share')
            print(f"| {v} | {cell(s, 'cutting_force_n_per_mm', 1)} | {cell(s, 'feed_force_n_per_mm', 1)} "
                  f"| {cell(s, 'compression_ratio', 3)} | {cell(s, 'extent_ratio', 3)} | "
                  f"{'—' if share is None else f'{share:.2f}'} | {cell(s, 'segment_pitch_mm', 4)} "
                  f"| {cell(s, 'rake_peak_temperature_c', 0)} | {wall:.0f} |")
    speeds = sorted(a.conditions, key=lambda c: float(rows[c]['cutting_speed_m_per_min']))
    slow, fast = speeds[0], speeds[1:]
    if not fast:
        print('\n(one condition: no speed dependence to state)')
        return
    measured = float(rows[slow]['chip_ratio']) - sum(float(rows[c]['chip_ratio']) for c in fast) / len(fast)
    print(f"\nh_c/h at {slow} minus the mean over {', '.join(fast)} (measured {measured:+.3f}):")
    for v in a.variants:
        vals = [mean_of(results[(c, v)][0], 'compression_ratio') for c in speeds]
        if any(x is None for x in vals):
            print(f'  {v}: —')
            continue
        print(f'  {v}: {vals[0] - sum(vals[1:]) / len(vals[1:]):+.3f}')


if __name__ == '__main__':
    main()
