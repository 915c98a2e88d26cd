#!/usr/bin/env python3
"""What a rule about ensembles would have done on a corpus already run, without fitting again.

`rhonn corpus --out DIR` keeps each system's model.json; where the selection chose a mean of
structures, that file less its `members` is its best member alone, and less its last member the
mean of the best two. For every output so chosen this prints the test ratio to the corpus's ARX
(as `rhonn corpus` computes it: `rhonn predict` on the system's test record) of the mean, of its
first member alone, and of the rule "a mean must be below its first member on every fold"
(else the mean of the best two under the same test, else the first member; the folds from the
system's summary.json), then the geometric mean of each column and how many are above 1.01 x.
The rule's choice is approximate where the real selection would also weigh candidates that
were not in the mean (docs/results.md, seed 34, compares it with a real run).

Usage: python3 tools/corpus/ensemble_members.py path/to/rhonn CORPUS_DIR WORK_DIR
Standard library only.
"""
import json
import math
import os
import subprocess
import sys


def selection(summary):
    """The fit's selection in a system's summary.json (the object with `work_budget`)."""
    if isinstance(summary, dict):
        if "work_budget" in summary:
            return summary
        values = summary.values()
    elif isinstance(summary, list):
        values = summary
    else:
        return None
    for v in values:
        found = selection(v)
        if found:
            return found
    return None


def below(a, b):
    return len(a) == len(b) and all(x < y for x, y in zip(a, b))


def test_rms(exe, model, test, work, tag):
    """`rhonn predict`'s RMS error per output of `model` (a dict) on `test`."""
    path = os.path.join(work, f"{tag}.json")
    with open(path, "w") as f:
        json.dump(model, f)
    out = os.path.join(work, f"{tag}-predict")
    p = subprocess.run([exe, "predict", "--model", path, "--data", test, "--out", out],
                       capture_output=True, text=True)
    if p.returncode:
        sys.exit(f"{tag}: {p.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        return [o["rms_error"] for o in json.load(f)["outputs"]]


def main(exe, corpus, work):
    os.makedirs(work, exist_ok=True)
    with open(os.path.join(corpus, "summary.json")) as f:
        rows = json.load(f)["systems"]
    ratios = {"mean": [], "first": [], "rule": []}
    for row in rows:
        system = row["system"]
        with open(os.path.join(corpus, system, "model.json")) as f:
            model = json.load(f)
        if not model.get("members"):
            continue
        with open(os.path.join(corpus, system, "summary.json")) as f:
            sel = selection(json.load(f))
        by_name = {c["name"]: c for c in sel["candidates"]}
        names = sel["candidates"][sel["chosen"]]["name"].split(": ", 1)[1].split("; ")
        first = by_name[names[0]]["fold_scores"]
        rule_k = 1
        for k in range(len(names), 1, -1):
            mean_k = by_name.get(f"mean of the best {k}: " + "; ".join(names[:k]))
            if mean_k and below(mean_k.get("fold_scores") or [], first):
                rule_k = k
                break
        test = os.path.join(corpus, system, "test_0.csv")
        rms = {}
        for tag, k in (("mean", len(names)), ("first", 1), ("rule", rule_k)):
            m = dict(model)
            m["members"] = model["members"][: k - 1]
            if k == 1:
                del m["members"]
            rms[tag] = test_rms(exe, m, test, work, f"{system}-{tag}")
        for j, out in enumerate(row["outputs"]):
            r = {t: rms[t][j] / out["arx_rmse"] for t in rms}
            for t in r:
                ratios[t].append(r[t])
            print(f"{system:30s} {out['output']:4s} {row['train_input']} -> {row['test_input']}: "
                  f"mean of {len(names)} {r['mean']:.3f}, first alone {r['first']:.3f}, "
                  f"rule ({rule_k}) {r['rule']:.3f}")
    for t, v in ratios.items():
        if v:
            g = math.exp(sum(math.log(x) for x in v) / len(v))
            print(f"{t}: geometric mean {g:.3f}, above 1.01 x the ARX {sum(x > 1.01 for x in v)} of {len(v)}")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
