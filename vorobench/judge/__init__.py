"""Layer 3, the judge: compares diagrams, certifies them against the definition of a Voronoi
diagram, and judges implementations case by case in isolated sandboxes (with shrinking of
failures to witnesses).

Stands on the geometric core and on the constructions (``impls``); the harness stands on it.
"""
