"""Shared by the plotting scripts: reading a numeric CSV whose header must be exactly the expected
columns (the scripts are run as files, so they import this module from their own folder)."""
import sys

import numpy as np


def read_numeric_csv(path: str, columns: list, script: str):
    """The rows of `path` as a 2-D float array, or None after printing why (wrong header, no rows)."""
    with open(path) as f:
        header = f.readline().strip().split(",")
    if header != columns:
        print(f"{script}: {path}: expected columns {','.join(columns)}", file=sys.stderr)
        return None
    data = np.atleast_2d(np.loadtxt(path, delimiter=",", skiprows=1))
    if data.size == 0:
        print(f"{script}: {path} has no rows", file=sys.stderr)
        return None
    return data
