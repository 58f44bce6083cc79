"""Shared by the test programs here: read the protocol's text input (n, then x y [w] lines)."""

import sys

import numpy as np


def read_sites():
    """(sites (n, 2), weights (n,) or None) from stdin."""
    lines = sys.stdin.read().split("\n")
    head = lines[0].split()
    n = int(head[0])
    rows = np.array([[float(v) for v in line.split()] for line in lines[1:1 + n]]).reshape(n, -1)
    return rows[:, :2], (rows[:, 2] if "weighted" in head else None)
