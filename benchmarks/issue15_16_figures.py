import time, numpy as np, impls, datasets_gen
rng = np.random.default_rng(1)
for n in (10**3, 10**4, 10**5, 10**6):
    d = impls.build("incremental", rng.random((n, 2)))
    t = time.perf_counter(); d.regions; t1 = time.perf_counter()
    for i in range(100):
        d.regions[d.point_region[i]]
    print(f"regions n={n}: first call {t1 - t:.4f} s, then 100 lookups {time.perf_counter() - t1:.6f} s")
for name, n in (("qhull", 10**5), ("halfplane", 10**4)):
    pts = datasets_gen.generate("uniform", n, seed=0); w = datasets_gen.weights("radii", pts, seed=0)
    impls.build(name, pts[:50]); impls.build(name, pts[:50], weights=w[:50])
    best = {}
    for label, kw in (("ordinary", {}), ("weighted", {"weights": w})):
        best[label] = min(_t for _t in [(lambda: (lambda t0: (impls.build(name, pts, **kw), time.perf_counter() - t0)[1])(time.perf_counter()))() for _ in range(3)])
    print(f"{name} n={n}: ordinary {best['ordinary']:.3f} s, radii-weighted {best['weighted']:.3f} s, ratio {best['weighted'] / best['ordinary']:.2f}")
