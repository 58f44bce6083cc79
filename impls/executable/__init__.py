"""Implementations in any language: a program behind a TOML manifest, run by the protocol.

:func:`implementation_of` turns a :class:`~impls.executable.manifest.Manifest` into an
:class:`~impls.base.Implementation` of kind ``executable``. Its build writes the prepared
(scaled, distinct) sites to the program's stdin, reads its answer (bounded), and then, outside
the program's measures, assembles the DCEL: triangles are dualised
(:func:`vorobench.core.from_triangles.diagram_from_triangles`), Voronoi edges linked by the
unoriented-ridge rule (:func:`vorobench.core.builder.assemble`). The program's own wall time,
CPU time and peak memory stand for the build's (:func:`impls.base.record_process`); its
``time`` line is the ``library`` phase, and the harness's encoding, reading and assembling the
``protocol`` phase. The sandbox that runs all this holds no code of the program's: the program
is its child process, and what crosses back to the judge is the assembled arrays, checked there.

Manifests are found three ways: ``--plugin impl.toml`` (:mod:`impls.plugins`), the folders of
``VOROBENCH_IMPLS_PATH``, and the references shipped under ``impls/references/`` (listed only
where their toolchain is present).
"""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import subprocess
import time
from pathlib import Path
from typing import Optional

import numpy as np
from numpy.typing import NDArray

from impls.base import Implementation, record_process, record_timing
from impls.executable.manifest import MANIFEST_NAME, Manifest, ManifestError, OutputKind, file_digest, read_manifest
from impls.executable.process import ProgramFailed, run_program
from impls.executable.protocol import InvalidOutput, encode_sites, output_limit, parse_output
from vorobench.core.diagram import Diagram

__all__ = ["implementation_of", "ensure_setup", "discovered", "rerun_command", "manifest_named", "program_input",
           "build_references", "Manifest", "ManifestError",
           "InvalidOutput", "ProgramFailed", "read_manifest", "REFERENCES", "PATH_VARIABLE", "SetupFailed"]

#: The shipped references: one folder each, holding ``impl.toml`` and the program's sources.
REFERENCES = Path(__file__).resolve().parents[1] / "references"

#: The environment variable naming folders of manifests (``os.pathsep``-separated).
PATH_VARIABLE = "VOROBENCH_IMPLS_PATH"

#: Seconds a ``version`` command may take.
_VERSION_TIMEOUT = 20.0


class SetupFailed(RuntimeError):
    """The manifest's ``setup`` failed, or its ``requires`` are not met here."""


def _manifests_in(folder: Path) -> list[Path]:
    """``*.toml`` files in ``folder`` and ``*/impl.toml`` one level down, sorted."""
    if not folder.is_dir():
        return []
    direct = sorted(p for p in folder.glob("*.toml") if p.is_file())
    nested = sorted(p for p in folder.glob(f"*/{MANIFEST_NAME}") if p.is_file())
    return direct + nested


def discovered() -> dict[str, Path]:
    """Executable implementations by name: the shipped references whose ``requires`` this
    machine meets, then the manifests of ``VOROBENCH_IMPLS_PATH`` (listed even when they
    cannot run here, so that using one says why). A manifest that does not read is left out
    of the references and listed under its file's name otherwise."""
    found: dict[str, Path] = {}
    for path in _manifests_in(REFERENCES):
        try:
            manifest = read_manifest(path)
        except ManifestError:
            continue
        if not manifest.missing():
            found[manifest.name] = path
    for folder in filter(None, os.environ.get(PATH_VARIABLE, "").split(os.pathsep)):
        for path in _manifests_in(Path(folder)):
            try:
                found[read_manifest(path).name] = path
            except ManifestError:
                # A manifest with a mistake is listed (using it says what is wrong); another TOML
                # file that happens to lie there (a pyproject.toml) is not one.
                try:
                    meant = "[implementation]" in path.read_text(encoding="utf-8", errors="replace")
                except OSError:
                    meant = False
                if meant:
                    found.setdefault(path.parent.name if path.name == MANIFEST_NAME else path.stem, path)
    return found


#: Manifest folders whose setup this process has checked (a build then costs no second look).
_READY: set[Path] = set()

#: How much of a failed setup's output its error message quotes (the whole is in setup.log).
_SETUP_TAIL = 4000


def _unchanged(recorded: dict, manifest: Manifest) -> bool:
    """Whether every source the setup was run on is still there, unchanged (files added since,
    such as a build's outputs or a program's logs, do not count)."""
    for relative, digest in recorded.items():
        try:
            if file_digest(manifest.folder / relative) != digest:
                return False
        except OSError:
            return False
    return True


def _check_command(manifest: Manifest) -> None:
    """The command's program exists and can run (said once, before any build, with a hint)."""
    program = manifest.argv(manifest.command)[0]
    if os.sep in program:
        if not Path(program).is_file():
            raise SetupFailed(f"{manifest.name}: its program {program} does not exist"
                              + (" (setup ran: does it build there?)" if manifest.setup else ""))
        if not os.access(program, os.X_OK):
            raise SetupFailed(f"{manifest.name}: its program {program} is not executable (chmod +x, or run it "
                              f"through its interpreter: command = [\"{{python}}\", ...])")
    elif shutil.which(program) is None:
        hint = (f"; the manifest's folder has a file {program}: write \"./{program}\" (a bare name is looked up "
                f"on PATH)" if (manifest.folder / program).exists() else "")
        raise SetupFailed(f"{manifest.name}: its program {program!r} is not on PATH{hint}")


def ensure_setup(manifest: Manifest) -> None:
    """Run the manifest's ``setup`` before the first use of its folder's sources: again when a
    source it was run on changed, and from an empty cache folder (a setup killed half-way
    leaves nothing behind). One lock per manifest folder keeps two sandboxes from running it at
    once. Then check that the command's program can run. :class:`SetupFailed` says what failed
    (the end of setup's output; the whole is in the cache folder's ``setup.log``)."""
    missing = manifest.missing()
    if missing:
        raise SetupFailed(f"{manifest.name} needs {', '.join(missing)}, not found on this machine "
                          f"(`python3 dev.py setup --references` installs the shipped references' toolchains)")
    if manifest.folder in _READY:
        return
    if manifest.setup:
        cache = manifest.cache()
        locks = cache.parent / "locks"
        locks.mkdir(parents=True, exist_ok=True)
        with open(locks / f"{cache.name}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            stamp = cache / ".setup.json"
            try:
                recorded = json.loads(stamp.read_text())["sources"]
            except (OSError, ValueError, KeyError, TypeError):
                recorded = None
            if recorded is None or not _unchanged(recorded, manifest):
                _run_setup(manifest, cache, stamp)
    _check_command(manifest)
    _READY.add(manifest.folder)


def _run_setup(manifest: Manifest, cache: Path, stamp: Path) -> None:
    """Empty the cache folder, run setup, record the sources it ran on (under the caller's lock)."""
    if cache.exists():
        shutil.rmtree(cache)
    cache.mkdir(parents=True)
    sources = manifest.sources()
    argv = manifest.argv(manifest.setup, cache)
    started = time.monotonic()
    log_path = cache / "setup.log"
    with open(log_path, "wb") as log:
        status = subprocess.call(argv, cwd=manifest.folder, stdout=log, stderr=subprocess.STDOUT,
                                 env={**os.environ, "VOROBENCH_CACHE": str(cache)})
    if status != 0:
        with open(log_path, "rb") as log:
            log.seek(max(0, log_path.stat().st_size - _SETUP_TAIL))
            tail = log.read().decode("utf-8", "replace").strip().splitlines()[-5:]
        raise SetupFailed(f"setup of {manifest.name} ({' '.join(argv)}, in {manifest.folder}) failed with status "
                          f"{status}: {' | '.join(tail)[:800]} (whole output: {log_path})")
    stamp.write_text(json.dumps({"sources": sources, "seconds": round(time.monotonic() - started, 1)}))


def _version(manifest: Manifest) -> str:
    """What the manifest's ``version`` command prints (first line), run without setup."""
    if not manifest.version or manifest.missing():
        return ""
    try:
        done = subprocess.run(manifest.argv(manifest.version), cwd=manifest.folder, capture_output=True,
                              timeout=_VERSION_TIMEOUT)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    lines = done.stdout.decode("utf-8", "replace").strip().splitlines() if done.returncode == 0 else []
    return lines[0].strip()[:200] if lines else ""


def _assembled(manifest: Manifest, sites: NDArray[np.float64], weights: Optional[NDArray[np.float64]],
               data: bytes, radii: Optional[NDArray[np.float64]] = None) -> tuple[Diagram, Optional[float]]:
    """The program's answer as a diagram of ``sites`` (and the seconds of its time line)."""
    from vorobench.core.builder import assemble
    from vorobench.core.errors import InvalidDiagramError
    from vorobench.core.from_triangles import NotATriangulation, diagram_from_triangles

    n = sites.shape[0]
    answer = parse_output(data, manifest.output, n, disks=radii is not None)
    if radii is not None:
        from vorobench.core.from_apollonius_graph import NotAnApolloniusGraph, diagram_from_apollonius_faces

        try:
            return diagram_from_apollonius_faces(sites, radii, answer.triangles), answer.library_s
        except NotAnApolloniusGraph as exc:
            raise InvalidOutput(f"not the Apollonius graph of the {n} disks: {exc}") from None
    try:
        if manifest.output == OutputKind.TRIANGLES:
            diagram = diagram_from_triangles(sites, answer.triangles, weights)
        elif n <= 1:
            if answer.edge_sites.shape[0]:
                raise InvalidOutput(f"edges for {n} site(s)")
            diagram = Diagram.empty(sites, weights)
        else:
            diagram = assemble(sites, answer.vertices, answer.edge_sites, answer.edge_ends, oriented=False,
                               weights=weights)
    except (NotATriangulation, InvalidDiagramError, ValueError) as exc:
        raise InvalidOutput(f"not a {'triangulation' if manifest.output == OutputKind.TRIANGLES else 'diagram'} "
                            f"of the {n} sites: {exc}") from None
    return diagram, answer.library_s


def _compile_readers() -> None:
    """Run the numba kernels of both answer kinds once, ordinary and power (cached on disk)."""
    from vorobench.core.builder import assemble
    from vorobench.core.from_triangles import diagram_from_triangles

    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.25]])
    fan = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    diagram_from_triangles(square, fan)
    diagram_from_triangles(square, fan, np.zeros(5))
    three = square[[0, 1, 3]]
    centre = np.array([[0.5, 0.5]])
    assemble(three, centre, np.array([[0, 1], [1, 2], [2, 0]]), np.array([[0, -1], [0, -1], [0, -1]]),
             oriented=False)


class _Program:
    """The build of one manifest (a class, not a closure: an implementation registered in a
    test crosses to its sandbox by pickle)."""

    def __init__(self, manifest: Manifest) -> None:
        self.manifest = manifest

    def __call__(self, sites: NDArray[np.float64], weights: Optional[NDArray[np.float64]],
                 stats: Optional[dict], radii: Optional[NDArray[np.float64]] = None) -> Diagram:
        manifest = self.manifest
        ensure_setup(manifest)
        t0 = time.perf_counter_ns()
        stdin = encode_sites(sites, weights, manifest.input, radii)
        encoded = time.perf_counter_ns() - t0
        run = run_program(manifest.argv(manifest.command), manifest.folder, stdin,
                          output_limit(sites.shape[0], manifest.output, disks=radii is not None))
        del stdin
        t1 = time.perf_counter_ns()
        diagram, library_s = _assembled(manifest, sites, weights, run.stdout, radii)
        if library_s is not None and library_s > 1.05 * run.wall_s + 0.005:
            raise InvalidOutput(f"its time line says {library_s:.6g} s, longer than its whole process "
                                f"({run.wall_s:.6g} s)")
        record_process(run.wall_s, run.cpu_s, run.peak_rss_mb)
        record_timing("protocol", (encoded + time.perf_counter_ns() - t1) / 1e9)
        if library_s is not None:
            record_timing("library", library_s)
        if stats is not None:
            stats["output_bytes"] = len(run.stdout)
        return diagram

    def unweighted(self, sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
        return self(sites, None, stats)

    def weighted(self, sites: NDArray[np.float64], weights: NDArray[np.float64],
                 stats: Optional[dict] = None) -> Diagram:
        return self(sites, weights, stats)

    def disks(self, sites: NDArray[np.float64], radii: NDArray[np.float64],
              stats: Optional[dict] = None) -> Diagram:
        return self(sites, None, stats, radii)

    def warmup(self) -> None:
        """Set the program up, and compile the kernels that turn its answers into diagrams (on a
        tiny answer of our own), so that neither counts against its first case's timeout."""
        ensure_setup(self.manifest)
        _compile_readers()

    def version(self) -> str:
        return _version(self.manifest)


def implementation_of(manifest: Manifest) -> Implementation:
    """The :class:`Implementation` (kind ``executable``) that runs ``manifest``'s program."""
    program = _Program(manifest)
    return Implementation(
        name=manifest.name,
        description=manifest.description or f"the program {' '.join(manifest.command)} ({manifest.output})",
        complexity=manifest.complexity, build=program.unweighted, exact=manifest.exact,
        origin=manifest.origin or str(manifest.path), warmup=program.warmup, kind="executable",
        build_weighted=program.weighted if manifest.weighted else None,
        build_apollonius=program.disks if manifest.apollonius else None, version=program.version)


def rerun_command(manifest: Manifest, input_file: Path) -> str:
    """A shell command that runs the program on ``input_file`` (its stdin), from anywhere."""
    import shlex

    return f"cd {shlex.quote(str(manifest.folder))} && {shlex.join(manifest.argv(manifest.command))} < " \
           f"{shlex.quote(str(input_file))}"


def manifest_named(name: str, plugin: str = "") -> Optional[Manifest]:
    """The manifest of executable ``name``: its ``--plugin`` file, else the one found among the
    references and ``VOROBENCH_IMPLS_PATH`` (None if there is none, or it does not read)."""
    path = Path(plugin) if plugin.endswith(".toml") else discovered().get(name)
    try:
        return read_manifest(path) if path is not None else None
    except ManifestError:
        return None


def program_input(manifest: Manifest, points: NDArray[np.float64],
                  weights: Optional[NDArray[np.float64]] = None) -> bytes:
    """The stdin the program gets for ``points`` (and ``weights``): the prepared, distinct
    sites, scaled into the exact range as every implementation gets them."""
    from vorobench.core.prepare import prepare, prepare_weighted
    from vorobench.core.scaling import exact_shift, scale_points, scale_weights

    if weights is None:
        sites, site_weights = prepare(points)[0], None
    else:
        sites, site_weights, _ = prepare_weighted(points, weights)
    shift = exact_shift(sites)
    if shift:
        sites = scale_points(sites, shift)
        site_weights = None if site_weights is None else scale_weights(site_weights, shift)
    return encode_sites(sites, site_weights, manifest.input)


def build_references() -> int:
    """Run the setup of every shipped reference whose toolchain is here (say which are not):
    what ``python3 dev.py setup --references`` does after installing the toolchains. 1 if a
    setup failed."""
    failed = 0
    for path in _manifests_in(REFERENCES):
        manifest = read_manifest(path)
        missing = manifest.missing()
        if missing:
            print(f"{manifest.name}: not available here (needs {', '.join(missing)})", flush=True)
            continue
        started = time.monotonic()
        print(f"{manifest.name}: setting up ...", end=" ", flush=True)
        try:
            ensure_setup(manifest)
        except SetupFailed as exc:
            failed = 1
            print(f"failed: {exc}", flush=True)
            continue
        print(f"ready ({time.monotonic() - started:.0f} s; version {_version(manifest) or 'unknown'})", flush=True)
    return failed
