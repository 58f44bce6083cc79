"""Layer 1, the geometric core: exact predicates, the Diagram (DCEL) and its builder, input
preparation and the constructions every implementation shares.

Imports nothing above itself: the constructions (``impls``) stand on it, and so do the judge
and the harness.
"""
