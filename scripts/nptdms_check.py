#!/usr/bin/env python3
"""Read a TDMS file written by greybox with npTDMS and compare it with greybox's CSV of the
same recording. Usage: nptdms_check.py FILE.tdms FILE.csv GROUP. Exit 0 when equal."""
import csv
import sys

import numpy as np
from nptdms import TdmsFile


def main(tdms_path: str, csv_path: str, group: str) -> int:
    f = TdmsFile.read(tdms_path)
    g = f[group]
    with open(csv_path) as fh:
        rows = list(csv.reader(fh))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    for j, name in enumerate(header):
        if name == "time_s":
            ch = g["normal_force_N"]
            t = ch.properties["wf_start_offset"] + np.arange(len(ch)) * ch.properties["wf_increment"]
            got = t
        else:
            got = g[name][:]
            if g[name].properties.get("unit_string") not in ("N", "V"):
                print(f"{name}: unexpected unit_string {g[name].properties.get('unit_string')}")
                return 1
        # the CSV holds 4 decimals; the TDMS holds the full doubles
        if len(got) != len(data) or not np.allclose(got, data[:, j], atol=6e-5, rtol=0):
            print(f"{name}: mismatch (len {len(got)} vs {len(data)})")
            return 1
    print(f"npTDMS read {tdms_path}: {len(header)} channels x {len(data)} samples match the CSV")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
