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
