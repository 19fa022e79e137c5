#!/usr/bin/env python3
"""Write TDMS files with npTDMS (an independent implementation) plus the same data as CSV.

greybox's TDMS reader must read these back identically to its CSV path
(crates/greybox-tribo/tests/nptdms_parity.rs). Usage: nptdms_fixtures.py OUT_DIR
Test-only: npTDMS is never a runtime dependency of greybox.
"""
import sys
from datetime import datetime
from pathlib import Path

import numpy as np
from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(12345)
    n_seg, per_seg, dt = 3, 400, 1e-3

    # 1. waveform timing, three segments, float64 forces and a float32 trigger
    t = np.arange(n_seg * per_seg) * dt
    normal = 500.0 + 3.0 * np.sin(2 * np.pi * 2.0 * t) + rng.normal(0, 1.0, t.size)
    tangential = 0.35 * normal + rng.normal(0, 0.5, t.size)
    radial = 0.05 * normal + rng.normal(0, 0.5, t.size)
    trigger = np.where(t > 0.1, 5.0, 0.0).astype(np.float32) + rng.normal(0, 0.01, t.size).astype(np.float32)
    props = {"unit_string": "N", "wf_increment": dt, "wf_start_offset": 0.0}
    with TdmsWriter(str(out / "waveform.tdms")) as w:
        for s in range(n_seg):
            sl = slice(s * per_seg, (s + 1) * per_seg)
            w.write_segment([
                RootObject(properties={"title": "greybox parity fixture", "created": np.datetime64(datetime(2026, 1, 2, 3, 4, 5))}),
                GroupObject("Tribometer", properties={"rig": "virtual"}),
                ChannelObject("Tribometer", "normal_force_N", normal[sl], properties=props),
                ChannelObject("Tribometer", "tangential_force_N", tangential[sl], properties=props),
                ChannelObject("Tribometer", "radial_force_N", radial[sl], properties=props),
                ChannelObject("Tribometer", "trigger_V", trigger[sl], properties={"unit_string": "V", "wf_increment": dt}),
            ])
    with open(out / "waveform.csv", "w") as f:
        f.write("time_s,normal_force_N,tangential_force_N,radial_force_N,trigger_V\n")
        for i in range(t.size):
            f.write(f"{repr(float(i * dt))},{repr(float(normal[i]))},{repr(float(tangential[i]))},"
                    f"{repr(float(radial[i]))},{repr(float(trigger[i]))}\n")

    # 2. a time channel, kN units, a different group, and an int32 channel that is ignored
    t2 = np.cumsum(np.full(600, 2e-3))
    fz = 1.2 + rng.normal(0, 0.002, t2.size)
    fx = -0.4 + rng.normal(0, 0.002, t2.size)
    counter = np.arange(t2.size, dtype=np.int32)
    with TdmsWriter(str(out / "timechannel.tdms")) as w:
        for s in range(2):
            sl = slice(s * 300, (s + 1) * 300)
            w.write_segment([
                ChannelObject("Dyno", "time", t2[sl], properties={"unit_string": "s"}),
                ChannelObject("Dyno", "Fz", fz[sl], properties={"unit_string": "kN"}),
                ChannelObject("Dyno", "Fx", fx[sl], properties={"unit_string": "kN"}),
                ChannelObject("Dyno", "counter", counter[sl]),
            ])
    with open(out / "timechannel.csv", "w") as f:
        f.write("time,Fz,Fx\n")
        for i in range(t2.size):
            f.write(f"{repr(float(t2[i]))},{repr(float(fz[i]))},{repr(float(fx[i]))}\n")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
