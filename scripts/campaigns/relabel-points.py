#!/usr/bin/env python3
"""relabel-points.py: the points that issue 64 relabels under the label protocol, as two CSVs for
`mixload campaign create v3 --points ...` and `... v3-holdout --points ...`, from the landed
exports data/campaigns/mixer-v2.csv and mixer-v2-holdout.csv (replicates left out; they repeat a point).

A point is relabelled when it lies in the bed-to-film band (140-210 rpm), when its replicate found
another state (loadings more than 2x apart), when its verdict came at under 1.5 residence times of
its own flow (end_time_s < 1.5 M / feed), or when it never finished. Within each file the cheapest
come first (residence time M / feed, ascending; unfinished points last), so that a slice of runs lands
the most labels; the band comes before the rest. The hold-out file ends with the paper's reference
point (Avicel, 39 rpm, 5 kg/h), which `make demo` compares with."""
import csv, sys, os

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
cols = ["mu_s", "delta_mu", "i0", "d", "rho", "feed_kg_h", "rpm"]

def rows(name):
    with open(os.path.join(here, "data", "campaigns", name + ".csv")) as f:
        return list(csv.DictReader(l for l in f if not l.startswith("#")))

def pick(name):
    rs = rows(name)
    originals = [r for r in rs if not r.get("initial_loading_kg")]
    twins = {}
    for r in rs:
        if r.get("initial_loading_kg") and r["status"] == "done":
            twins[tuple(r[c] for c in cols)] = float(r["loading_kg"])
    out = []
    for r in originals:
        rpm = float(r["rpm"]); feed = float(r["feed_kg_h"]) / 3600
        done = r["status"] == "done" and r["loading_kg"]
        m = float(r["loading_kg"]) if done else None
        rt = m / feed if done else None
        why = []
        if 140 <= rpm <= 210: why.append("band")
        t = twins.get(tuple(r[c] for c in cols))
        if done and t and max(m, t) > 2 * min(m, t): why.append("two-states")
        if done and float(r["end_time_s"]) < 1.5 * rt: why.append("early-verdict")
        if not done: why.append("unfinished")
        if why:
            out.append(((0 if "band" in why else 1, 0 if done else 1, rt or 0), r, "+".join(why)))
    out.sort(key=lambda e: e[0])
    return out

def write(path, picked, extra=()):
    with open(path, "w") as f:
        f.write("# relabel points (issue 64), written by scripts/campaigns/relabel-points.py; " \
                "of = the landed campaign and index the point repeats\n")
        f.write(",".join(cols + ["of", "why"]) + "\n")
        for _, r, why in picked:
            f.write(",".join([r[c] for c in cols] + [f"{r['_src']}:{r['index']}", why]) + "\n")
        for e in extra:
            f.write(e + "\n")

if __name__ == "__main__":
    outdir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "data", "campaigns")
    train = pick("mixer-v2")
    for e in train: e[1]["_src"] = "v2"
    hold = pick("mixer-v2-holdout")
    for e in hold: e[1]["_src"] = "v2-holdout"
    # The paper's reference point: Avicel (mu_s 0.31, mu_d 0.44, I0 0.28, d 240 um, rho 329.84), 39 rpm, 5 kg/h.
    write(os.path.join(outdir, "relabel-v3-points.csv"), train)
    write(os.path.join(outdir, "relabel-v3-holdout-points.csv"), hold,
          ["0.31,0.13,0.28,0.00024,329.84,5,39,reference,reference"])
    print(f"{len(train)} training and {len(hold) + 1} hold-out points")
