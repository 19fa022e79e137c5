#!/usr/bin/env python3
"""Independent reference for greybox's calibration certainty (crates/greybox-sweep/src/
fit_certainty.rs), written from its module documentation with numpy and scipy.

Reads a JSON file with `searched` (the fitted fields' names) and `evaluations` (each with
`parameters` and `condition_errors`), as `greybox sweep calibrate` writes them into
calibration.json (or a list of such documents), and prints the evaluations as good as the
best and each field's range (a list for a list).

Rule: evaluations with a finite error, a parameter set tried again counted once; the best
has the least mean over the conditions; evaluation k is as good as the best unless the mean
of d_i = e_ik - e_ib exceeds t(1 - 0.05/m; n - 1) * s_d / sqrt(n); m = 1 first, then m =
(the number kept by that first pass) - 1, at least 1.

usage: fit_certainty_reference.py calibration.json
"""
import json
import sys

import numpy as np
from scipy import stats


def reference(doc):
    names = doc["searched"]
    seen, errors, params = set(), [], []
    for e in doc["evaluations"]:
        p = tuple(e["parameters"])
        c = np.array([np.inf if v is None else v for v in e["condition_errors"]], float)
        if p in seen or len(p) != len(names) or not np.all(np.isfinite(c)):
            continue
        seen.add(p)
        errors.append(c)
        params.append(p)
    if not errors:
        return None
    n = len(errors[0])
    if n < 2:
        return None
    E = np.array(errors)
    P = np.array(params)
    best = int(np.argmin(E.mean(axis=1)))

    def kept(m):
        crit = stats.t.ppf(1.0 - 0.05 / max(m, 1), n - 1)
        out = []
        for k in range(len(E)):
            d = E[k] - E[best]
            if d.mean() <= crit * d.std(ddof=1) / np.sqrt(n):
                out.append(k)
        return out

    good = kept(max(len(kept(1)) - 1, 1))
    fields = []
    for j, name in enumerate(names):
        low, high = P[good, j].min(), P[good, j].max()
        tried = [P[:, j].min(), P[:, j].max()]
        fields.append({
            "field": name,
            "value": float(P[best, j]),
            "low": float(low),
            "high": float(high),
            "tried": [float(tried[0]), float(tried[1])],
            "bounded_below": bool(low > tried[0]),
            "bounded_above": bool(high < tried[1]),
        })
    return {"conditions": n, "evaluations": len(E), "as_good_as_best": len(good), "fields": fields}


def main():
    with open(sys.argv[1]) as f:
        doc = json.load(f)
    if isinstance(doc, list):
        json.dump([reference(d) for d in doc], sys.stdout)
    else:
        json.dump(reference(doc), sys.stdout)


if __name__ == "__main__":
    main()
