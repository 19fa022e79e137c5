#!/usr/bin/env python3
"""How thick is a simulated chip? Three readings of the same particles, independent of
greybox's own measure (docs/validation.md, "How thick is the chip?").

Reads the particle and tool frames a cut wrote (`greybox simulate cutting ... --vtk-every N`,
legacy-VTK `vtk/particles_*.vtk` and `vtk/tool0_*.vtk`) and, for every frame from
`--from-step` on, takes the chip's particles between h and 2h above the uncut surface
(free particles, boundary group 0, in front of the rake face) and reads their thickness
three ways:

* section: the band's area (the particles' spacing squared) over the length of chip the band
  holds, h / cos(ψ), ψ the angle of the chip's mean flow from the vertical; positions, spacings
  and the flow's direction only;
* continuity: h v_c / |v̄|, v̄ the band's area-weighted mean velocity relative to the tool,
  v_c the tool's speed (the tool's velocity from its positions in consecutive frames);
* extent: the band projected on the rake-face normal, max − min + the spacing.

The first two agree where the chip flows steadily (the volume the cut removes passes through
the band); the third is the outer size of the chip in the band.

    python3 scripts/chip_section_check.py CUT_DIR --h-mm 0.06 --rake-deg 15 [--from-step 14000]

Standard library only.
"""
import argparse
import glob
import math
import os
import statistics


def read_vtk(path):
    """Points (x, y) and every SCALARS/VECTORS field of a legacy ASCII POLYDATA file."""
    with open(path, encoding='utf-8') as f:
        lines = f.read().split('\n')
    start = next(k for k, line in enumerate(lines) if line.startswith('POINTS'))
    n = int(lines[start].split()[1])
    points = [tuple(map(float, lines[start + 1 + j].split()[:2])) for j in range(n)]
    fields = {}
    for k, line in enumerate(lines):
        if line.startswith('SCALARS'):
            fields[line.split()[1]] = [float(v) for v in lines[k + 2:k + 2 + n]]
        elif line.startswith('VECTORS'):
            fields[line.split()[1]] = [tuple(map(float, v.split()[:2])) for v in lines[k + 1:k + 1 + n]]
    return points, fields


def step_of(path):
    return int(os.path.basename(path).split('_')[-1].split('.')[0])


def time_of(path):
    """The frame's time, s, from its title line (`greybox-sim particles t=... s`)."""
    with open(path, encoding='utf-8') as f:
        f.readline()
        title = f.readline()
    return float(title.split('t=')[1].split()[0])


def edge(tool_points):
    """The tool's lowest point: the cutting edge's bottom, which moves with the tool."""
    return min(tool_points, key=lambda q: q[1])


def readings(frame, tool_velocity, h, rake):
    points, fields = read_vtk(frame)
    tool, _ = read_vtk(frame.replace('particles_', 'tool0_'))
    ex, ey = edge(tool)
    spacing = fields['spacing_m']
    normal = (-math.cos(rake), math.sin(rake))
    # the uncut surface: the top of the workpiece's untouched particles far ahead of the tool
    ahead = [y + 0.5 * s for (x, y), s in zip(points, spacing) if x < ex - 0.5e-3]
    surface = max(ahead) if ahead else 0.0
    band = []
    for k, ((x, y), s) in enumerate(zip(points, spacing)):
        if fields['boundary_group'][k] != 0 or not surface + h <= y <= surface + 2 * h:
            continue
        d = (x - ex) * normal[0] + (y - ey) * normal[1]
        if -s < d < 10 * h:
            band.append((k, d, s))
    if len(band) < 10:
        return None
    area = sum(s * s for _, _, s in band)
    vel = fields['velocity_m_per_s']
    mvx = sum((vel[k][0] - tool_velocity[0]) * s * s for k, _, s in band) / area
    mvy = sum((vel[k][1] - tool_velocity[1]) * s * s for k, _, s in band) / area
    psi = math.atan2(mvx, mvy)
    section = area * math.cos(psi) / h
    continuity = h * math.hypot(*tool_velocity) / math.hypot(mvx, mvy)
    lo = min(band, key=lambda b: b[1])
    hi = max(band, key=lambda b: b[1])
    extent = hi[1] - lo[1] + 0.5 * (lo[2] + hi[2])
    return section / h, continuity / h, extent / h, math.degrees(psi)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('cut')
    ap.add_argument('--h-mm', type=float, required=True)
    ap.add_argument('--rake-deg', type=float, required=True)
    ap.add_argument('--from-step', type=int, default=0)
    a = ap.parse_args()
    h, rake = a.h_mm * 1e-3, math.radians(a.rake_deg)
    frames = sorted(glob.glob(os.path.join(a.cut, 'vtk', 'particles_*.vtk')), key=step_of)
    rows = []
    for prev, frame in zip(frames, frames[1:]):
        if step_of(frame) < a.from_step:
            continue
        # the tool's velocity from its edge's travel between this frame and the one before
        (x0, y0), (x1, y1) = (edge(read_vtk(p.replace('particles_', 'tool0_'))[0]) for p in (prev, frame))
        dt = time_of(frame) - time_of(prev)
        r = readings(frame, ((x1 - x0) / dt, (y1 - y0) / dt), h, rake)
        if r:
            rows.append((step_of(frame),) + r)
            print(f'step {rows[-1][0]}: section {r[0]:.3f}, continuity {r[1]:.3f}, extent {r[2]:.3f} '
                  f'(h_c/h), flow {r[3]:+.1f}° from the vertical')
    if rows:
        means = [statistics.mean(r[k] for r in rows) for k in range(1, 5)]
        print(f'mean over {len(rows)} frames: section {means[0]:.3f}, continuity {means[1]:.3f}, '
              f'extent {means[2]:.3f}, flow {means[3]:+.1f}°')


if __name__ == '__main__':
    main()
