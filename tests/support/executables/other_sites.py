"""A test program that prints the Voronoi diagram of other sites (each moved by 1e-3)."""
import sys

from scipy.spatial import Voronoi

from sites_io import read_sites

sites, _ = read_sites()
vor = Voronoi(sites + 1e-3)
out = [f"v {x!r} {y!r}\n" for x, y in vor.vertices.tolist()]
out += [f"e {i} {j} {a} {b}\n" for (i, j), (a, b) in zip(vor.ridge_points.tolist(), vor.ridge_vertices)]
sys.stdout.write("".join(out))
