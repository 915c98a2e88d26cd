"""Contiguous thirds of a CSV record for 3-fold cross-validation (shared by the selection
scripts beside it)."""
import csv
import os


def write_thirds(path, d):
    """Write the header and each contiguous third of `path`'s rows into `d`; their paths."""
    rows = list(csv.reader(open(path)))
    head, body = rows[0], rows[1:]
    n = len(body)
    thirds = []
    for f in range(3):
        p = os.path.join(d, f"third{f}.csv")
        with open(p, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(head)
            w.writerows(body[f * n // 3:(f + 1) * n // 3])
        thirds.append(p)
    return thirds


def rank(grid, score, toml, unit, higher_is_better, out_toml=None):
    """Score every setting of `grid` (`score(c)`: one figure per fold, or None when a fold
    failed), print each with its folds, then how many ran, their median and the best; write
    the best as `toml(c)` to `out_toml`. `unit` formats a figure, e.g. "{:.3f} V"."""
    worst = float("-inf") if higher_is_better else float("inf")
    results = []
    for c in grid:
        folds = score(c)
        mean = sum(folds) / len(folds) if folds else worst
        results.append((mean, c, folds))
        print(f"{unit.format(mean)}  folds {folds}  {toml(c).strip().replace(chr(10), '; ')}", flush=True)
    results.sort(key=lambda r: -r[0] if higher_is_better else r[0])
    ran = sorted(r[0] for r in results if r[0] != worst)
    print(f"{len(grid)} settings, {len(ran)} ran on every fold; median {unit.format(ran[len(ran) // 2])}")
    best = results[0]
    print(f"best: {unit.format(best[0])}, folds {best[2]}: {toml(best[1]).strip()}")
    if out_toml:
        open(out_toml, "w").write(toml(best[1]))
