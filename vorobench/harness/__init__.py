"""Layer 4, the harness: runs benchmarks and campaigns, stores and reports results, compares
runs and tracks them over commits.

Stands on every layer below it; only the command line (``vorobench.cli``) stands on it.
"""
